// What a voxelization will cost before it starts (voxels, dense bricks, memory, time), and whether this machine can afford it.
#pragma once

#include <cstdint>
#include <string>

#include "core/result.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim {

// An estimate, not a promise: the dense bricks follow from the surface's area (a sheet crosses
// about 1.5 bricks per brick face of area it covers), memory from what each path keeps per ray,
// per hit and per brick, and time from rates measured on a 2-core machine (docs/RELIABILITY.md).
// It errs high, so a refusal is never for a job that would have fitted by a wide margin.
struct VoxelizeCost {
  int level = 0;
  uint64_t rays = 0;            // rays cast (sub-samples included); 0 for label import
  uint64_t surface_bricks = 0;  // dense bricks expected
  uint64_t memory_bytes = 0;    // peak resident memory expected
  double seconds = 0.0;         // expected time on one core of the reference machine
  double crossings_per_ray = 0; // surfaces a ray of the footprint crosses on average (a tooth: a few)
};

// STL layers: from the ray set-up (its footprint and its triangles' area). `gpu` is the Vulkan
// path, whose ray arrays are bounded by its bands.
VoxelizeCost estimateMeshVoxelize(const RaySetup& setup, bool gpu);

// Label import at `level`: from the tissue's surface area in target voxel faces (the source's
// tissue faces scaled by the voxel ratio squared) and the source's voxels.
VoxelizeCost estimateLabelImport(int level, double surface_faces, uint64_t source_voxels);

// One line: "level 12 (4096^3 voxels): about 180 000 dense bricks, 0.4 GB and 50 s".
std::string describeCost(const VoxelizeCost& cost);

// Memory this machine can give now (MemAvailable), or 0 when it cannot be told.
// DENTSIM_MEMORY_LIMIT_MB, when set, is taken instead (a PC shared with other work, or a test).
uint64_t availableMemoryBytes();

// Refuses, unless `force`, a job expected to need more memory than `available` (0: unknown, never
// refused), or meshes whose rays cross more than kMaxCrossingsPerRay surfaces on average (random or
// piled-up triangles, not a tooth, whose cost grows with every crossing); the error says what it
// would need and that --force runs it all the same.
inline constexpr double kMaxCrossingsPerRay = 64.0;
Status checkAffordable(const VoxelizeCost& cost, uint64_t available, bool force, const std::string& where);

}  // namespace dentsim
