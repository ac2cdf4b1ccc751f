// GPU material counts: voxels and fill per material of a BrickVolume, the GPU twin of BrickVolume::materialTotals().
#pragma once

#include <cstdint>
#include <string>

#include "core/result.h"
#include "gpu/context.h"
#include "volume/brick_volume.h"

namespace dentsim::gpu {

// Where the time went, when the caller asks.
struct TimingOut {
  bool timestamps = false;      // kernel_ns is valid (the queue writes timestamps)
  double kernel_ns = 0.0;       // GPU time of all count dispatches [ns]
  std::string timestamp_note;   // why timestamps are missing, when they are
  uint32_t dispatches = 0;      // dispatches the brick range was split into
  uint64_t workgroups = 0;      // records summed
};

struct CountOptions {
  // Most workgroups per dispatch; 0 = the device's maxComputeWorkGroupCount[0]. Tests lower it to
  // exercise the split by firstBrick/brickLimit that very large grids need.
  uint32_t max_groups_per_dispatch = 0;
};

// Uploads the volume's three word arrays, counts every brick on the GPU and sums the per-workgroup
// records in 64 bits. Equal to volume.materialTotals(). Errors: a pool over maxStorageBufferRange,
// any Vulkan failure, a dispatch that times out.
Result<MaterialTotals> countMaterialsGpu(Context& ctx, const BrickVolume& volume, TimingOut* timing = nullptr,
                                         const CountOptions& options = {});

}  // namespace dentsim::gpu
