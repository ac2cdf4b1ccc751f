// NormalMode: how many voxel centres a surface normal averages (the paper's 8, 64 or 216), named, parsed and printed in one place.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace dentsim {

// The value is the neighbour count, which is also how presets ("normal_neighbours": 64) and the
// command line (`--normals 64`) write it. Gradients average over a box of side 2, 4 or 6 voxels
// (surface_layout.h DS_MESH_SIDE_*); wider boxes smooth more and reach further (paper Fig. 15).
enum class NormalMode : uint16_t {
  Box8 = 8,
  Box64 = 64,
  Box216 = 216,
};

inline constexpr NormalMode kNormalModes[] = {NormalMode::Box8, NormalMode::Box64, NormalMode::Box216};

// 8, 64 or 216.
constexpr int normalNeighbours(NormalMode mode) { return int(mode); }
// The averaging box's side in voxels: 2, 4 or 6.
uint32_t normalBoxSide(NormalMode mode);

// The one check of a neighbour count: the mode for 8, 64 or 216, nothing for any other number (a
// preset's double such as 64.0 counts; 64.5 does not).
std::optional<NormalMode> normalModeFromNeighbours(double neighbours);
// "8", "64" or "216" to a mode; nothing for any other text.
std::optional<NormalMode> parseNormalMode(std::string_view text);
// "8", "64" or "216".
std::string normalModeName(NormalMode mode);
// What an error says the allowed values are: "8, 64 or 216".
inline constexpr const char* kNormalModeChoices = "8, 64 or 216";

}  // namespace dentsim
