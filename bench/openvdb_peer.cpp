// The OpenVDB peer for brick memory: the same voxels as a uint8 label tree, pruned, measured by memUsage().
#include <chrono>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/version.h>

#include "bench/peers.h"

namespace dentsim::bench {

PeerMemory openvdbLabelTreeMemory(const BrickVolume& volume) {
  using LabelTree = openvdb::tree::Tree4<uint8_t, 5, 4, 3>::Type;  // OpenVDB's default node sizes
  openvdb::initialize();
  const auto start = std::chrono::steady_clock::now();
  LabelTree tree(0);  // background: empty
  openvdb::tree::ValueAccessor<LabelTree> acc(tree);
  volume.forEachBrick([&](const BrickView& b) {
    const openvdb::Coord origin(int(b.coord.x * DS_BRICK_DIM), int(b.coord.y * DS_BRICK_DIM), int(b.coord.z * DS_BRICK_DIM));
    if (b.uniform) {
      // A uniform brick is an 8^3 tile in OpenVDB too (level 1 = leaf-sized), as in ours.
      const auto label = uint8_t(voxelMaterial(b.value));
      if (label != 0) acc.addTile(1, origin, label, true);
      return;
    }
    for (uint32_t z = 0; z < DS_BRICK_DIM; ++z)
      for (uint32_t y = 0; y < DS_BRICK_DIM; ++y)
        for (uint32_t x = 0; x < DS_BRICK_DIM; ++x) {
          const auto label = uint8_t(voxelMaterial(b.voxels[layout::brickCoordToOffset(x, y, z)]));
          if (label != 0) acc.setValue(origin.offsetBy(int(x), int(y), int(z)), label);
        }
  });
  openvdb::tools::prune(tree);
  PeerMemory p;
  p.available = true;
  p.name = "OpenVDB " OPENVDB_LIBRARY_VERSION_STRING " uint8 label tree";
  p.bytes = tree.memUsage();
  p.leaf_nodes = tree.leafCount();
  p.build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return p;
}

}  // namespace dentsim::bench
