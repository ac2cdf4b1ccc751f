// NormalMode's box sides, the neighbour-count check and its text form.
#include "volume/normal_mode.h"

#include "volume/surface_layout.h"

namespace dentsim {

uint32_t normalBoxSide(NormalMode mode) {
  switch (mode) {
    case NormalMode::Box8: return DS_MESH_SIDE_8;
    case NormalMode::Box64: return DS_MESH_SIDE_64;
    case NormalMode::Box216: return DS_MESH_SIDE_216;
  }
  return 0;  // not reached for a valid enumerator
}

std::optional<NormalMode> normalModeFromNeighbours(double neighbours) {
  for (NormalMode m : kNormalModes)
    if (neighbours == double(normalNeighbours(m))) return m;
  return std::nullopt;
}

std::optional<NormalMode> parseNormalMode(std::string_view text) {
  for (NormalMode m : kNormalModes)
    if (text == normalModeName(m)) return m;
  return std::nullopt;
}

std::string normalModeName(NormalMode mode) { return std::to_string(normalNeighbours(mode)); }

}  // namespace dentsim
