// Peer libraries measured beside dentsim in the same run; each is compiled in only when installed.
#pragma once

#include <cstdint>
#include <string>

#include "core/triangle_mesh.h"
#include "volume/brick_volume.h"

namespace dentsim::bench {

// Memory of an OpenVDB tree holding the same voxels' labels (uint8, 5-4-3 tree, pruned to tiles).
struct PeerMemory {
  bool available = false;   // false when dentsim was built without OpenVDB
  std::string name;         // "OpenVDB 10.0.1 uint8 label tree"
  uint64_t bytes = 0;       // Tree::memUsage() [B]
  uint64_t leaf_nodes = 0;  // leaves after pruning
  double build_s = 0.0;     // time to fill and prune [s]
};

PeerMemory openvdbLabelTreeMemory(const BrickVolume& volume);

// How OpenVDB is asked to voxelize: the solid filled with stored distances (what a voxelizer
// delivers, and the paper's comparison) or its usual narrow-band level set, where the inside is
// known by sign only (tiles and inactive values).
enum class VdbInterior { Filled, NarrowBand };

// One closed surface turned into an OpenVDB level set by meshToVolume.
struct PeerVoxelize {
  bool available = false;        // false when dentsim was built without OpenVDB
  std::string name;              // "OpenVDB 10.0.1 meshToVolume<FloatGrid>, interior filled"
  int threads = 0;               // TBB worker threads it could use
  double ms = 0.0;               // wall time of meshToVolume alone [ms]
  uint64_t interior_voxels = 0;  // voxels whose centre has a negative distance (inside)
  uint64_t active_voxels = 0;    // stored distance values
  uint64_t leaf_nodes = 0;       // 8^3 leaves of the result
  double interior_mm3 = 0.0;     // interior_voxels x voxel volume [mm^3]
};

// Voxelizes `mesh` into a grid of `voxel_mm` whose voxel (0,0,0) has its lower corner at
// `origin_mm`, so its voxel centres coincide with those of dentsim's grid in the same frame.
// Filled: exterior band 1 voxel (the least that classifies the surface), interior unbounded.
// NarrowBand: OpenVDB's default half-width of 3 voxels on both sides.
PeerVoxelize openvdbMeshToVolume(const TriangleMesh& mesh, double voxel_mm, const Vec3d& origin_mm,
                                 VdbInterior interior = VdbInterior::Filled);

}  // namespace dentsim::bench
