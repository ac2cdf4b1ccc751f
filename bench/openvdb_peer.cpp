// The OpenVDB peers: brick memory as a pruned uint8 label tree, and mesh voxelization by meshToVolume.
#include <chrono>
#include <limits>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/version.h>
#include <tbb/task_arena.h>

#include "bench/peers.h"

namespace dentsim::bench {
namespace {

// A TriangleMesh as OpenVDB's MeshDataAdapter (counts and getters), mapping mm to index space,
// where integer coordinates are voxel centres.
class TriangleMeshAdapter {
 public:
  TriangleMeshAdapter(const TriangleMesh& mesh, double voxel_mm, const Vec3d& origin_mm)
      : mesh_(mesh), inv_voxel_(1.0 / voxel_mm), origin_(origin_mm) {}

  size_t polygonCount() const { return mesh_.triangles.size(); }
  size_t pointCount() const { return mesh_.positions.size(); }
  size_t vertexCount(size_t) const { return 3; }
  void getIndexSpacePoint(size_t n, size_t v, openvdb::Vec3d& pos) const {
    const Vec3f& p = mesh_.positions[mesh_.triangles[n][v]];
    for (int a = 0; a < 3; ++a) pos[a] = (double(p[size_t(a)]) - origin_[size_t(a)]) * inv_voxel_ - 0.5;
  }

 private:
  const TriangleMesh& mesh_;
  double inv_voxel_;  // [1/mm]
  Vec3d origin_;      // [mm]
};

}  // namespace

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

PeerVoxelize openvdbMeshToVolume(const TriangleMesh& mesh, double voxel_mm, const Vec3d& origin_mm,
                                 VdbInterior interior) {
  openvdb::initialize();
  // Index (0,0,0) sits at the centre of dentsim's voxel (0,0,0), so both sample the same points.
  openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(voxel_mm);
  transform->postTranslate(openvdb::Vec3d(origin_mm[0] + 0.5 * voxel_mm, origin_mm[1] + 0.5 * voxel_mm,
                                          origin_mm[2] + 0.5 * voxel_mm));
  const bool filled = interior == VdbInterior::Filled;
  // An unbounded interior band makes meshToVolume grow the band until the whole inside is stored.
  const float exterior_band = filled ? 1.0f : float(openvdb::LEVEL_SET_HALF_WIDTH);
  const float interior_band = filled ? std::numeric_limits<float>::max() : float(openvdb::LEVEL_SET_HALF_WIDTH);

  // The map to index space is part of the timed work, as makeRaySetup is on dentsim's side.
  const auto start = std::chrono::steady_clock::now();
  const TriangleMeshAdapter adapter(mesh, voxel_mm, origin_mm);
  openvdb::FloatGrid::Ptr grid =
      openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *transform, exterior_band, interior_band);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  PeerVoxelize p;
  p.available = true;
  p.name = filled ? "OpenVDB " OPENVDB_LIBRARY_VERSION_STRING " meshToVolume<FloatGrid>, interior filled"
                  : "OpenVDB " OPENVDB_LIBRARY_VERSION_STRING " meshToVolume<FloatGrid>, narrow band of 3 voxels";
  p.threads = tbb::this_task_arena::max_concurrency();
  p.ms = ms;
  // Inside voxels may also sit in tiles, so walk values of every kind and weigh tiles by size.
  for (auto it = grid->tree().cbeginValueAll(); it; ++it)
    if (*it < 0.0f) p.interior_voxels += it.getVoxelCount();
  p.active_voxels = grid->tree().activeVoxelCount();
  p.leaf_nodes = grid->tree().leafCount();
  p.interior_mm3 = double(p.interior_voxels) * voxel_mm * voxel_mm * voxel_mm;
  return p;
}

}  // namespace dentsim::bench
