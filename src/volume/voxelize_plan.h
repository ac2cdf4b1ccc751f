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
  uint64_t scan_voxels = 0;     // a scan's read: its voxels (level 0 then: no grid yet)
};

// STL layers: from the ray set-up (its footprint and its triangles' area). `gpu` is the Vulkan
// path, whose ray arrays are bounded by its bands.
VoxelizeCost estimateMeshVoxelize(const RaySetup& setup, bool gpu);

// Label import at `level`: from the tissue's surface area in target voxel faces (the source's
// tissue faces scaled by the voxel ratio squared) and the source's voxels. The peak is the larger
// of two stages: the source read (labels and codes) and the bricks built while the codes are kept.
VoxelizeCost estimateLabelImport(int level, double surface_faces, uint64_t source_voxels);

// A scan's read and segmentation (DICOM, NIfTI, NRRD grey values): the floats, the segmentation's
// labels and masks, and `stored_bytes` a voxel the reader holds at once as the file stores them.
VoxelizeCost estimateScanRead(uint64_t voxels, uint32_t stored_bytes);

// One line: "level 12 (4096^3 voxels): about 180 000 dense bricks, 0.4 GB of memory and 50 s", or
// for a scan's read "reading the scan (144 000 000 voxels): about 0.93 GB of memory and 12 s".
std::string describeCost(const VoxelizeCost& cost);

// Refuses, unless `force`, a job expected to need more memory than `budget` (the memory budget,
// io/input_budget.h; 0: unknown, never refused), or meshes whose rays cross more than
// kMaxCrossingsPerRay surfaces on average (random or piled-up triangles, not a tooth, whose cost
// grows with every crossing). The refusal is one line naming the estimate, the budget, how the
// budget was set (its flag) and --force.
inline constexpr double kMaxCrossingsPerRay = 64.0;
Status checkAffordable(const VoxelizeCost& cost, uint64_t budget, bool force, const std::string& where);

}  // namespace dentsim
