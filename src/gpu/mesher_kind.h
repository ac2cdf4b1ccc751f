// MesherKind: which mesher a GpuSurface runs (the compute kernel, CPU threads, or whichever suits the device), named, parsed and printed in one place.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <vulkan/vulkan.h>

namespace dentsim::gpu {

// Both meshers write the same slots and draw records; they give the same triangles, and vertices
// equal up to the rounding of one division and the 12-bit normal packing (docs/MESHING.md).
enum class MesherKind {
  Gpu,   // surface_mesh.comp.glsl: count and emit passes on the device
  Cpu,   // BlockMesher on the host's threads, writing host-visible slot pages
  Auto,  // Cpu where the Vulkan device is itself a CPU (lavapipe, SwiftShader), else Gpu
};

inline constexpr MesherKind kMesherKinds[] = {MesherKind::Gpu, MesherKind::Cpu, MesherKind::Auto};

// "gpu", "cpu" or "auto" to a kind; nothing for any other text.
std::optional<MesherKind> parseMesherKind(std::string_view text);
// "gpu", "cpu" or "auto".
std::string mesherKindName(MesherKind kind);
// What an error says the allowed values are.
inline constexpr const char* kMesherKindChoices = "gpu, cpu or auto";

// The mesher that runs: Auto becomes Cpu on a device of type CPU, where the kernel is emulated on
// the same cores the host threads would use, and Gpu on any other; Gpu and Cpu stay as asked.
MesherKind resolveMesher(MesherKind asked, VkPhysicalDeviceType device_type);

}  // namespace dentsim::gpu
