// Scripted attempts at any task, derived from its professional's recorded session: a second careful hand, and one attempt for each fault a score must see.
//
// A teacher's own task has no built-in path, only the professional's session. Every attempt is
// therefore made from that session's pen readings, so that a task proves its own score whatever
// tooth and cavity it is:
//   expert    a second careful hand: the professional's motion at a different pace (pace_factor
//             slower, the pedal eased to match, so the same tissue is cut) with a small tremor
//   undercut  stopped where the professional had removed undercut_share of all it removed (or, when
//             that is not known, after undercut_share of its cutting time)
//   overcut   the professional's motion, then the same motion again pushed outward from the cavity's
//             axis by overcut_offset_mm (a point on the axis stays; one within the offset of it moves
//             out in proportion): a preparation finished, then widened
//   heavy     pressed heavy_press times as hard: the grip held heavy_press times as far past where
//             the bur stood (the coupling's spring then pulls that much harder), at least far enough
//             to press heavy_min_force_n
//   slow      slow_factor times as long: after each slow_work_s of the professional's motion the hand
//             holds still with the turbine stopped for (slow_factor - 1) times that, so it cuts what
//             the professional cut (a hand moving at a third of the speed at full turbine would cut
//             deeper, and with the turbine eased less: either would lose points for the cut, not the time)
//   tilted    the bur leaning tilt_deg off the insertion axis about its tip, toward the mesial
//   trench    the same motion trench_offset_mm away, across the insertion axis toward the mesial
//   token     stopped token_s after the bur first cut: touches the ideal and stops
// A crown preparation's faults edit the professional's lapping and lowering (sim/crown_paths.h): a
// drill sample whose bur leans more than crown_lap_lean_deg off the insertion axis is lapping an axial
// wall, and the wall it cuts faces the way the bur's top leans from (its "side": the bur's axis
// projected across the insertion axis, reversed); any other drill sample is lowering the occlusal
// surface or moving between. A side within crown_side_deg of a wall's direction (the tooth's buccal,
// lingual = -buccal, mesial; each across the insertion axis) is that wall's, fading to untouched over
// the next crown_fade_deg, so that an edit does not jerk the bur:
//   overtaper      every lapping sample turned about the tip by overtaper_deg further toward the axis
//                  (a 2-degree-tapered bur leaning 5 degrees cuts walls of 7; 9 more make 16, TOC 32)
//   shallow        every other drill sample lifted shallow_mm along the axis: the occlusal surface
//                  lowered that much less
//   wall_undercut  on the buccal wall the lapping bur turned about its tip by undercut_turn_deg away
//                  from the axis: its top leans out, the wall widens toward the occlusal, an undercut
//   thin_margin    on the lingual wall the lapping bur held thin_margin_mm further out, across the
//                  axis: the chamfer there narrower by as much (and the wall reduced as much less)
//   nick           at the last lapping sample facing the mesial (within 3 degrees), the lap stops and
//                  the bur swings nick_mm toward the mesial and back over nick_s, the rest of the
//                  session following later by nick_s: on the built-in molar, where the finishing
//                  lap's bur passes 1.0-1.1 mm from the premolar (its 0.3 mm clearance holds at the
//                  contact, off the mesial direction), about 0.4 mm into it
// "The cavity's axis" is the line along the insertion axis through the mean tip position while
// cutting. "Cutting" is a step with the drill in contact and the pedal down.
#pragma once

#include <string>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "core/volume_frame.h"
#include "io/pen_path_file.h"
#include "io/session_file.h"
#include "sim/novice_paths.h"

namespace dentsim {

// How far each derived attempt departs from the professional.
struct DerivedAttemptSettings {
  double sample_every_s = 0.005;     // the session's readings kept this often (1 kHz is more than a hand moves) [s]
  double pace_factor = 1.15;         // the second hand takes this times as long
  double tremor_mm = 0.03;           // and sways this far across the axis [mm]
  double tremor_period_s = 0.7;      // at this period, and 1.37 times it across [s]
  double undercut_share = 0.5;       // of the professional's removal (or cutting time) before the pen stops
  double overcut_offset_mm = 1.0;    // outward from the cavity's axis [mm]
  double heavy_press = 3.0;          // times the professional's press
  double heavy_min_force_n = 6.0;    // while cutting, the heavy hand presses at least this [N] (derivedSettingsFor)
  double slow_factor = 3.0;          // times the professional's time
  double slow_work_s = 1.0;          // the slow hand works this long between pauses [s]
  double tilt_deg = 15.0;            // off the insertion axis [deg]
  double trench_offset_mm = 2.0;     // the same motion this far away [mm]
  double token_s = 0.3;              // cutting time before the token attempt stops [s]
  double lift_mm = 3.0;              // a stopped attempt backs out this far along the axis [mm]
  // A crown preparation's faults (above).
  double crown_lap_lean_deg = 1.0;   // a bur leaning more than this off the axis laps a wall [deg]
  double crown_side_deg = 45.0;      // a wall's samples: their side within this of its direction [deg]
  double crown_fade_deg = 15.0;      // and fading out over this much further [deg]
  double overtaper_deg = 9.0;        // further toward the axis [deg]
  double shallow_mm = 1.3;           // the occlusal surface lowered this much less [mm]
  double undercut_turn_deg = 12.0;   // the buccal wall's bur turned away from the axis [deg]
  double thin_margin_mm = 0.6;       // the lingual wall's bur held out [mm]
  double nick_mm = 1.5;              // the swing toward the mesial neighbour [mm]
  double nick_s = 1.0;               // out, held and back [s]
};

// A heavy hand presses past the task's own force limit: at least this times force_error_n.
inline constexpr double kHeavyOverForceLimit = 2.0;
// `base` for a task whose contact force limit is force_error_n [N] (heavy_min_force_n set from it).
inline DerivedAttemptSettings derivedSettingsFor(double force_error_n, DerivedAttemptSettings base = {}) {
  base.heavy_min_force_n = kHeavyOverForceLimit * force_error_n;
  return base;
}

// The professional's session as a path to derive attempts from.
struct ProfessionalPath {
  PenPath path;                   // both pens' readings every sample_every_s, simulation frame
  std::vector<Vec3> drill_press;  // per drill sample of `path` in order: grip minus where the bur stood, -F / k [mm]
  std::vector<bool> drill_cutting;// per drill sample: in contact with the pedal down
  double cut_start_s = 0.0;       // the first cutting step [s]
  double cut_end_s = 0.0;         // the last cutting step [s]
  double elapsed_s = 0.0;         // the session's length [s]
  double half_removed_s = 0.0;    // when the professional had removed undercut_share of its total [s]; 0: not known
  Vec3 cut_centre;                // mean tip position while cutting [mm]
  double coupling_n_per_mm = 1.0; // the session's coupling spring [N/mm]
  std::string drill_tool;         // the professional's bur
};

// Reads the professional's session (`where` names it in errors): a session whose parameters do not
// parse, with no drill reading, or in which the bur never cut is an error.
Result<ProfessionalPath> professionalPath(const SessionRecording& session, const std::string& where,
                                          const DerivedAttemptSettings& settings = {});

// The attempt, derived from the professional's path. `insertion_axis` is the task's (unit, the
// bur's +z); `axes` the tooth's frame (for the mesial direction of the tilt and the trench).
PenPath derivedAttemptPath(const ProfessionalPath& pro, Attempt attempt, const Vec3& insertion_axis, const ToothAxes& axes,
                           const DerivedAttemptSettings& settings = {});

}  // namespace dentsim
