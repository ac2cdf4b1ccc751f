// GPU voxelization of mesh layers by depth peeling (compute): the same rule and result as voxelizeCpu.
#pragma once

#include <cstdint>

#include "core/interrupter.h"
#include "core/result.h"
#include "gpu/context.h"
#include "volume/brick_volume.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim::gpu {

// Where the time went, from the host clock and the kernels' timestamps.
struct VoxelizeTiming {
  double total_ms = 0.0;      // host wall time of voxelizeGpu, uploads and read-back included
  double kernels_ms = 0.0;    // sum of kernel times from timestamp queries
  double count_scan_ms = 0.0; // of which: counting hits and the prefix sum
  double store_sort_ms = 0.0; //           storing, sorting and finding donors
  double paint_ms = 0.0;      //           painting bricks
  double chunks_ms = 0.0;     //           packing chunks
  double upload_ms = 0.0;     // triangles to the device
  double readback_ms = 0.0;   // bricks and index back to the CPU mirror
  uint32_t bands = 0;         // slabs of chunk rows the grid was processed in
  uint64_t hits = 0;          // ray-surface crossings
  uint64_t dense_bricks = 0;  // bricks built
};

// Voxelizes on the GPU and mirrors the bricks to the CPU. The result equals voxelizeCpu's.
Result<BrickVolume> voxelizeGpu(Context& context, const RaySetup& setup, const VoxelizeOptions& options,
                                VoxelizeTiming* timing = nullptr, Interrupter& interrupter = nullInterrupter());

}  // namespace dentsim::gpu
