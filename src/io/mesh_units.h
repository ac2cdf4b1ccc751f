// Length units of mesh files (STL carries none) and a plausibility check of a tooth's size.
#pragma once

#include <string>
#include <string_view>

#include "core/triangle_mesh.h"

namespace dentsim {

// The unit a mesh file's coordinates are in; dentsim works in millimetres.
enum class LengthUnit { Millimetre, Centimetre, Metre, Micrometre };

// Parses a --units value: "mm", "cm", "m", "um" (or "µm"). Returns false and leaves *unit alone
// for anything else.
bool parseLengthUnit(std::string_view text, LengthUnit* unit);

// Millimetres in one `unit` (the factor to scale a file's coordinates by): 1, 10, 1000 or 0.001.
double millimetresPer(LengthUnit unit);

// The symbol parseLengthUnit accepts for `unit` ("mm", "cm", "m", "um").
std::string_view lengthUnitSymbol(LengthUnit unit);

// Largest extent [mm] of anything that can be a tooth or a dental tool: a bur head is a few mm, a
// molar about 20 mm, a handpiece or a full arch under 150 mm.
inline constexpr double kPlausibleMinExtentMm = 2.0;
inline constexpr double kPlausibleMaxExtentMm = 150.0;

// "" when the largest extent of `bounds_mm` lies in [2, 150] mm; otherwise a one-line warning
// starting "<where>: " that gives the extent and, when a factor of 10 or 1000 would make it
// plausible, the unit that factor suggests ("... as metres it would be 11 mm: --units m").
std::string toothExtentWarning(const Bounds3& bounds_mm, std::string_view where);

// "" when `extent_mm`, a label volume's tissue extent at `pitch_mm` voxels, lies in [2, 150] mm;
// otherwise a one-line warning starting "<where>: " that names the pitch and --voxel-size (a
// label file's header often carries a placeholder pitch such as 1.0).
std::string labelPitchWarning(double extent_mm, double pitch_mm, std::string_view where);

}  // namespace dentsim
