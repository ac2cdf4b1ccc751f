// The built-in instruments: round, fissure and tapered crown-preparation burs, a turbine handpiece and a mouth mirror, as closed meshes in mm.
//
// Frames (right-handed, mm):
//   burs        bur axis +Z; the cutting tip (lowest point of the head) at the origin; head, neck,
//               then the FG shank (1.6 mm) along +Z to the shank end at z = 19. A chamfer or shoulder
//               bur's head widens 2 degrees a side from its tip to its top at the cutting length.
//   handpiece   the same frame as a seated bur: bur axis +Z through the origin, bur tip at the
//               origin; the head cylinder (axis +Z) spans z = 8.6 .. 21.5; neck and body leave
//               the head toward +X, rising 18 degrees toward +Z (a contra-angle of 108 degrees
//               between the handle and the cutting direction -Z).
//   mirror      reflective face on the plane z = 0, centred at the origin, its normal +Z; the disc
//               lies behind it (z = -2 .. 0); neck and handle leave the rim toward -X, falling 20
//               degrees toward -Z.
// Every mesh is built from surfaces of revolution; the handpiece and the mirror are two closed
// shells each (head or disc, and neck plus handle) that interpenetrate, so read them as a union
// (winding number >= 1), not with even-odd parity.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "core/triangle_mesh.h"

namespace dentsim {

// ChamferBur: a tapered diamond with a rounded (torpedo) end, ISO shape 856, for a chamfer margin.
// ShoulderBur: a tapered diamond with a flat end, ISO shape 847, for a shoulder margin.
enum class ToolKind { RoundBur, FissureBur, ChamferBur, ShoulderBur, Handpiece, Mirror };

// True for the kinds that cut tooth (every kind but the handpiece and the mirror).
constexpr bool isBur(ToolKind kind) {
  return kind == ToolKind::RoundBur || kind == ToolKind::FissureBur || kind == ToolKind::ChamferBur ||
         kind == ToolKind::ShoulderBur;
}

struct ToolSpec {
  const char* name;          // file stem, e.g. "round_bur_010"
  ToolKind kind;
  double head_diameter_mm;   // bur head (its widest, at the top of a tapered head), handpiece head or mirror disc diameter [mm]
  double cutting_length_mm;  // length of the cutting head along the axis [mm]; 0 where none
  // A bur's taper carried down to the tip's height (z = 0) [mm]: equal to head_diameter_mm for
  // round and fissure burs, narrower for the tapered ones, whose rounded end (chamfer) or edge
  // (shoulder) is tangent to that cone. 0 for tools that are not burs.
  double tip_diameter_mm;
};

// The tools a run starts with when neither the task nor the command line names others.
inline constexpr const char* kDefaultBur = "round_bur_010";
inline constexpr const char* kDefaultMirror = "mirror_size4";
// The mirror's glass: the disc inside the rim that reflects (assets/tools/README.md) [mm].
inline constexpr double kMirrorGlassRadiusMm = 10.85;

// Every built-in tool, in a fixed order.
std::span<const ToolSpec> toolCatalog();
// The tool's mesh: welded, closed, 2-manifold shells, outward. Deterministic.
TriangleMesh generateTool(const ToolSpec& spec);
// The catalog's tool of that name, or nullptr.
const ToolSpec* findTool(std::string_view name);
// "round_bur", "fissure_bur", "chamfer_bur", "shoulder_bur", "handpiece" or "mirror".
const char* toolKindName(ToolKind kind);
// The radius of a bur's head at height_mm above its tip, along its axis, as generateTool builds
// it [mm]: the profile of its revolution, 0 below the tip, above the cutting length, or for a tool
// that is not a bur. The mesh's vertices lie on it; its facets, chords of it, lie a little inside
// (around the axis at most r (1 - cos(pi / 48)), 0.2 %).
double burRadiusAt(const ToolSpec& spec, double height_mm);
// assets/tools/tools.json: each tool's file, kind and sizes, in catalog order.
std::string toolCatalogJson();

}  // namespace dentsim
