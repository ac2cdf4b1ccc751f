// Opening the Vulkan device for a command that can fall back to its CPU reference, with the one warning that says so.
#pragma once

#include <optional>
#include <string>

#include "core/result.h"
#include "gpu/context.h"

namespace dentsim::app {

// The context on `device` (or DENTSIM_DEVICE, or the best GPU). With no Vulkan device at all and
// no device asked for by name, prints "dentsim: warning: ...; <fallback> instead" and returns
// nothing, so the caller runs its CPU reference; any other failure (a named device missing, a
// broken driver) is an Error.
Result<std::optional<gpu::Context>> openGpuOrFallBack(const std::string& device, const std::string& fallback);

}  // namespace dentsim::app
