// The built-in instruments: round and fissure burs, a turbine handpiece and a mouth mirror, as closed meshes in mm.
//
// Frames (right-handed, mm):
//   burs        bur axis +Z; the cutting tip (lowest point of the head) at the origin; head, neck,
//               then the FG shank (1.6 mm) along +Z to the shank end at z = 19.
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

#include "core/triangle_mesh.h"

namespace dentsim {

enum class ToolKind { RoundBur, FissureBur, Handpiece, Mirror };

struct ToolSpec {
  const char* name;          // file stem, e.g. "round_bur_010"
  ToolKind kind;
  double head_diameter_mm;   // bur head, handpiece head or mirror disc diameter [mm]
  double cutting_length_mm;  // length of the cutting head along the axis [mm]; 0 where none
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
// "round_bur", "fissure_bur", "handpiece" or "mirror".
const char* toolKindName(ToolKind kind);
// assets/tools/tools.json: each tool's file, kind and sizes, in catalog order.
std::string toolCatalogJson();

}  // namespace dentsim
