// `dentsim gpu`: the Vulkan devices, the chosen one with its limits, and a GPU-versus-CPU self-test of the count kernel.
#pragma once

#include <ostream>

#include "core/result.h"
#include "gpu/context.h"
#include "volume/brick_volume.h"

namespace dentsim::gpu {

// Creates a context with `options`, prints every device, the chosen one (name, type, ids, driver,
// API version) and the limits dentsim relies on, then counts materials of selfTestVolume() on the
// GPU and the CPU. Text for people, or one JSON object when `json`. An Error when no context can be
// made, when GPU and CPU differ, or when validation reported errors.
Status printDeviceReport(std::ostream& out, const ContextOptions& options, bool json);

// The built-in test volume: a 32^3 grid (level 5) with a sphere of enamel, its surface voxels
// partly filled, and a cube of dentin; tiles, dense bricks and mixed fills all occur.
BrickVolume selfTestVolume();

}  // namespace dentsim::gpu
