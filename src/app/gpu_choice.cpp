// Opening the Vulkan device for a command that can fall back to its CPU reference.
#include "app/gpu_choice.h"

#include "app/commands.h"

namespace dentsim::app {

Result<std::optional<gpu::Context>> openGpuOrFallBack(const std::string& device, const std::string& fallback) {
  gpu::ContextOptions co;
  co.device_override = device;
  auto ctx = gpu::Context::create(gpu::withEnvironment(co));
  if (ctx) return std::optional<gpu::Context>(std::move(ctx).value());
  if (gpu::isNoDeviceError(ctx.error()) && device.empty()) {
    warn(ctx.message() + "; " + fallback + " instead");
    return std::optional<gpu::Context>();
  }
  return ctx.error();
}

}  // namespace dentsim::app
