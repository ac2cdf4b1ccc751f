// Opening the Vulkan device for a command that can fall back to its CPU reference.
#include "app/gpu_choice.h"

#include <cstdio>

namespace dentsim::app {

Result<std::optional<gpu::Context>> openGpuOrFallBack(const std::string& device, const std::string& fallback) {
  gpu::ContextOptions co;
  co.device_override = device;
  auto ctx = gpu::Context::create(gpu::withEnvironment(co));
  if (ctx) return std::optional<gpu::Context>(std::move(ctx).value());
  if (gpu::isNoDeviceError(ctx.error()) && device.empty()) {
    std::fprintf(stderr, "dentsim: warning: %s; %s instead\n", ctx.message().c_str(), fallback.c_str());
    return std::optional<gpu::Context>();
  }
  return ctx.error();
}

}  // namespace dentsim::app
