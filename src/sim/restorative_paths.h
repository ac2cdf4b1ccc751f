// The course's restorative preparations as a professional cuts them: a class II mesio-occlusal cavity with its proximal box, a class V cervical cavity, and an endodontic access cavity.
//
// Each is worked out from the volume itself in the tooth's frame (mm; x mesiodistal, mesial toward
// -x; y buccolingual, buccal toward -y; z the long axis, crown up): where the fossa is, where the
// enamel ends at the cementoenamel junction (CEJ), where the pulp lies. Each outline becomes columns
// of tip positions that sim/pocket_planner.h paces into a pen path for the scripted pen. Every
// size is the cavity's own, the bur included; `widen` scales the outline for the over-cutting
// attempt (sim/course_paths.h).
//
// Contents
//   1. Landmarks: the CEJ along a line (the fossa is sim/surface_probe.h's lowestRestingTip)
//   2. Class II mesio-occlusal cavity (fissure bur, held along +z)
//   3. Class V cervical cavity (round bur, held along the buccal normal)
//   4. Endodontic access cavity (round bur, held along +z)
#pragma once

#include <optional>
#include <string>

#include "core/result.h"
#include "core/rigid.h"
#include "core/volume_frame.h"
#include "sim/pocket_planner.h"
#include "sim/sim_params.h"
#include "sim/surface_probe.h"
#include "volume/brick_volume.h"

namespace dentsim {

// ---- 1. landmarks ------------------------------------------------------------------------------------------

// The CEJ seen along a line: rays in direction `dir` from start + z (0, 0, 1), for z from z_from
// down to z_to in steps of step_mm, meet enamel above it and other tissue (or none) below it. The
// height [mm] halfway between the last enamel and the first other; nullopt when no ray meets enamel
// or the enamel never ends.
std::optional<double> cejAlong(TissueRay& ray, const Vec3& start, const Vec3& dir, double z_from, double z_to,
                               double step_mm, double reach_mm);

// ---- 2. class II mesio-occlusal ------------------------------------------------------------------------------

// A class II MO preparation with a fissure bur held along +z: an occlusal part from just distal of
// the fossa over the mesial marginal ridge, and a box down the mesial surface whose gingival floor
// lies above the mesial CEJ. Walls are parallel to the bur; floors are flat.
//
// Beside a mesial neighbour (Material::Neighbour voxels mesial of the fossa, across the box), the
// box stops short of it: the bur's mesial side keeps neighbour_clearance_mm from the neighbour's
// most distal voxel face over the box's width and height, and leaves the thin shell of the molar's
// enamel at the contact that a dentist breaks with a hand instrument rather than the bur. Without a
// neighbour the box opens the whole mesial surface, as before. The over-cutter's box (widen > 1)
// reaches (widen - 1) box depths past that limit, into the neighbour.
struct Class2Settings {
  double isthmus_width_mm = 1.6;      // buccolingual width of the occlusal part [mm]
  double occlusal_depth_mm = 1.8;     // its floor below the fossa's surface [mm]
  double distal_reach_mm = 0.6;       // it ends this far distal of the fossa [mm]
  double box_width_mm = 2.6;          // buccolingual width of the proximal box [mm]
  double box_depth_mm = 1.2;          // its gingival floor's depth: mesial surface to axial wall [mm]
  double gingival_above_cej_mm = 1.0; // the gingival floor this far above the mesial CEJ [mm]
  double widen = 1.0;                 // widths, box depth and distal reach grow by this factor (>= 1 over-cuts)
  // Beside a mesial neighbour, the bur keeps this far from it [mm], >= 0. Not less: the bur must not
  // ride the rim of the shell it leaves, or its press slides it off into the occlusal embrasure and
  // onto the premolar (at level 7, 0.5 mm put the bur's side 0.03 mm inside the molar's mesial
  // outline at the floor, and the scripted bur took 0.07 mm^3 of the premolar; 0.3, 0.4, 0.6 and 0.8
  // took none at levels 7 and 8).
  double neighbour_clearance_mm = 0.4;
  double fossa_search_mm = 1.0;       // the fossa: the lowest rest within this of the crown's centre [mm]
  double fossa_grid_mm = 0.1;
  PocketSettings pocket = [] {
    PocketSettings p;
    p.grid_mm = 0.25;
    p.layer_mm = 0.4;  // the flat end cuts a layer at a time
    return p;
  }();
};

struct Class2Path {
  PocketPath cut;
  Vec3 fossa_mm;               // the bur's rest over the fossa [mm]
  double fossa_surface_z = 0;  // the surface there [mm]
  double occlusal_floor_z = 0; // [mm]
  double mesial_cej_z = 0;     // the CEJ on the mesial surface [mm]
  double gingival_floor_z = 0; // the box's floor [mm]
  double mesial_surface_x = 0; // the mesial surface at the gingival floor's height [mm]
  double axial_wall_x = 0;     // the box's axial wall [mm]
  double box_half_width_mm = 0;  // buccolingual half-width of the box about the fossa's y [mm]
  std::optional<double> neighbour_x;  // the mesial neighbour's most distal voxel face across the box [mm]; none without one
  double bur_mesial_limit_x = 0; // with a neighbour: the bur's mesial side stays distal of this [mm]
};

Result<Class2Path> class2CavityPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                    const std::string& bur, const Class2Settings& settings = {});

// ---- 3. class V cervical -----------------------------------------------------------------------------------------

// A class V preparation on the buccal surface just above the CEJ: an oval outline, long
// mesiodistally, with a round bur held along `axis` (the task's insertion axis; zero: the buccal
// surface's normal measured at the outline's centre). The axial wall follows the surface's curve,
// depth_mm below it.
struct Class5Settings {
  Vec3 axis{0, 0, 0};               // the bur's axis, out of the tooth toward buccal; zero: the measured normal
  double width_mm = 3.2;            // mesiodistal extent of the outline [mm]
  double height_mm = 1.6;           // occlusogingival extent [mm]
  double above_cej_mm = 0.3;        // the gingival margin this far above the buccal CEJ [mm]
  double depth_mm = 1.2;            // the axial wall below the surface [mm]: through the enamel into dentin
  double widen = 1.0;               // the outline grows by this factor (>= 1 over-cuts)
  double fossa_search_mm = 1.0;     // the crown's centre: the fossa's x
  double fossa_grid_mm = 0.1;
  PocketSettings pocket = [] {
    PocketSettings p;
    p.grid_mm = 0.2;
    p.layer_mm = 0.2;
    p.press_mm = 0.2;
    return p;
  }();
};

struct Class5Path {
  PocketPath cut;
  double buccal_cej_z = 0;     // the CEJ on the buccal surface [mm]
  Vec3 centre_mm;              // the outline's centre on the surface [mm]
  Vec3 normal;                 // the buccal surface's outward normal there, measured (unit)
  Vec3 axis;                   // the bur's axis used (unit)
};

Result<Class5Path> class5CavityPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                    const std::string& bur, const Class5Settings& settings = {});

// ---- 4. endodontic access ------------------------------------------------------------------------------------------

// An access cavity with a round bur held along +z: down through the occlusal centre into the pulp
// chamber. The outline is an oval over the pulp horns (the pulp within horn_depth_mm of its highest
// point), `outline_share` of their extent; in every column the bur goes into_pulp_mm past the first
// pulp it meets, so the chamber's roof comes off whole. Columns over no pulp keep the highest such
// floor, a shelf rather than a gouge.
struct AccessSettings {
  double horn_depth_mm = 1.2;       // the horns: pulp within this of the pulp's top [mm]
  double outline_share = 0.85;      // the oval's extent as a share of the horns' [1]
  double into_pulp_mm = 0.3;        // the bur's tip past the pulp's surface [mm]
  double widen = 1.0;               // the outline grows by this factor (>= 1 over-cuts)
  PocketSettings pocket = [] {
    PocketSettings p;
    p.grid_mm = 0.3;
    p.layer_mm = 0.3;
    return p;
  }();
};

struct AccessPath {
  PocketPath cut;
  double pulp_top_z = 0;          // the highest pulp [mm]
  Vec3 horns_lo_mm, horns_hi_mm;  // the box of the horns [mm]
  Vec3 centre_mm;                 // the outline's centre (z 0) [mm]
  double half_x_mm = 0, half_y_mm = 0;  // the outline's half-extents, the bur included [mm]
  double lowest_floor_z = 0;      // the deepest tip [mm]
};

Result<AccessPath> accessCavityPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                    const std::string& bur, const AccessSettings& settings = {});

}  // namespace dentsim
