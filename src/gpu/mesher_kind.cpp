// MesherKind's text form and the rule that resolves Auto from the device type.
#include "gpu/mesher_kind.h"

namespace dentsim::gpu {

std::optional<MesherKind> parseMesherKind(std::string_view text) {
  for (MesherKind k : kMesherKinds)
    if (text == mesherKindName(k)) return k;
  return std::nullopt;
}

std::string mesherKindName(MesherKind kind) {
  switch (kind) {
    case MesherKind::Gpu: return "gpu";
    case MesherKind::Cpu: return "cpu";
    case MesherKind::Auto: return "auto";
  }
  return "?";  // not reached for a valid enumerator
}

MesherKind resolveMesher(MesherKind asked, VkPhysicalDeviceType device_type) {
  if (asked != MesherKind::Auto) return asked;
  return device_type == VK_PHYSICAL_DEVICE_TYPE_CPU ? MesherKind::Cpu : MesherKind::Gpu;
}

}  // namespace dentsim::gpu
