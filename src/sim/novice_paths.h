// Scripted attempts with one fault each (over-cutting, stopping early, a heavy hand, slowness, the wrong place) beside the careful dentist's, for showing that a score tells them apart.
//
// Each attempt is the expert's path of sim/scripted_paths.h with one thing changed, so that a score
// should lose its points in the part that matches the fault and nowhere else:
//   expert    the careful path itself
//   overcut   a cut wider than it should be: for caries, a raster over the lesion's whole box and
//             beyond; for a cavity, the expert's outline and then a wider one
//   undercut  the expert's path, stopped when half its cutting time has passed
//   heavy     the expert's path, pressed three times as hard
//   slow      the expert's path at a third of the speed, hand and pedal, so that it cuts the same
//             tissue in three times the time (at full pedal a slower bur would also cut deeper)
//   trench    a groove across the buccal cusps, away from the caries and the fossa
//   tilted    the expert's path with the bur leaning 15 degrees off the insertion axis about its tip
//   token     the expert's path, stopped a moment after the bur first cuts: touches and stops
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "io/pen_path_file.h"
#include "sim/scripted_paths.h"
#include "sim/sim_params.h"
#include "volume/brick_volume.h"

namespace dentsim {

// A crown preparation's faults (derived from the professional's session only, sim/session_attempts.h):
//   overtaper      the walls leaning about 15 degrees each (TOC about 30)
//   shallow        the occlusal surface lowered about 1 mm less
//   wall_undercut  one wall (the buccal) leaning outward toward the occlusal: an undercut
//   thin_margin    on one side (the lingual) the bur kept out, the chamfer there about 0.4 mm
//   nick           one excursion from the mesial wall into the mesial neighbour
enum class Attempt { Expert, Overcut, Undercut, Heavy, Slow, Trench, Tilted, Token, Overtaper, Shallow, WallUndercut, ThinMargin, Nick };
// The attempts at a caries removal, a cavity or an access.
inline constexpr std::array<Attempt, 8> kAttempts = {Attempt::Expert, Attempt::Overcut, Attempt::Undercut,
                                                     Attempt::Heavy,  Attempt::Slow,    Attempt::Trench,
                                                     Attempt::Tilted, Attempt::Token};
// The attempts at a crown preparation.
inline constexpr std::array<Attempt, 7> kCrownAttempts = {Attempt::Expert,       Attempt::Overtaper,  Attempt::Shallow,
                                                          Attempt::WallUndercut, Attempt::ThinMargin, Attempt::Nick,
                                                          Attempt::Token};

// "expert", "overcut", "undercut", "heavy", "slow", "trench", "tilted", "token", "overtaper", "shallow",
// "wall_undercut", "thin_margin", "nick"
const char* attemptName(Attempt a);
const char* attemptFault(Attempt a);   // the fault in a few words, for tables
std::optional<Attempt> parseAttempt(const std::string& name);  // any attempt of either list
// kAttempts' names, for help and errors: "expert, overcut, undercut, heavy, slow, trench, tilted, token".
std::string attemptNames();
std::vector<std::string> attemptNameList();
// kCrownAttempts' names: "expert, overtaper, shallow, wall_undercut, thin_margin, nick, token".
std::string crownAttemptNames();
// The attempts a command's list names (`--attempts overcut,slow`); `option` starts the error, which
// names the first unknown one and lists the known (both lists).
Result<std::vector<Attempt>> parseAttemptList(const std::vector<std::string>& names, const std::string& option);

// How much each fault departs from the expert.
struct AttemptFaults {
  double overcut_margin_mm = 0.8;   // caries: the raster reaches this far past the lesion's box [mm]
  double overcut_widen = 1.6;       // cavity: the second outline is this times as wide
  double undercut_share = 0.35;      // the share of the cutting time before the pen stops
  double heavy_press = 3.0;         // times the expert's press
  double slow_factor = 3.0;         // times the expert's time
  double trench_offset_mm = 2.4;    // the groove's line this far buccal (-y) of the crown's centre [mm]
  double trench_length_mm = 5.0;    // along x [mm]
  double trench_speed_mm_s = 0.5;   // along the groove, one lap there and back [mm/s]
  double tilt_deg = 15.0;           // the tilted bur leans this far off the insertion axis [deg]
  double token_s = 0.3;             // the token cut stops this long after the pedal first goes down [s]
};

// The caries removal attempt on this volume with the bur `bur`, from the expert's settings `base`.
Result<PenPath> cariesAttemptPath(Attempt attempt, const BrickVolume& volume, const VolumeFrame& frame,
                                  const SimParams& params, const std::string& bur, const CariesPathSettings& base = {},
                                  const AttemptFaults& faults = {});
// The class I cavity attempt on this volume, from the expert's settings `base`.
Result<PenPath> cavityAttemptPath(Attempt attempt, const BrickVolume& volume, const VolumeFrame& frame,
                                  const CavityPathSettings& base = {}, const AttemptFaults& faults = {});

// ---- path edits, each a fault on any path -----------------------------------------------------------

// Every sample `factor` times later, and the pedal divided by it.
PenPath slowedPath(const PenPath& path, double factor);
// The path up to `stop_s`, then pedal up and back out along `lift_dir` (unit; the insertion axis) by
// `lift_mm` over `lift_s`.
PenPath stoppedPath(const PenPath& path, double stop_s, double lift_mm = 3.0, double lift_s = 0.3,
                    const Vec3& lift_dir = {0, 0, 1});
// A wandering hand: the drill's samples every 20 ms along the path, each moved sideways (in the
// simulation frame's x and y) by amplitude_mm (sin(2 pi t / period_s), sin(2 pi t / (1.37 period_s))),
// so that the bur drifts off the path and back at two unrelated rates; the mirror's samples as they were.
PenPath wanderingPath(const PenPath& path, double amplitude_mm, double period_s = 1.5);
// The drill's every sample turned by `degrees` about the bur's tip (kBurGripLocal below the grip),
// leaning its axis from `axis` toward `toward` (a direction not along `axis`): the
// tip follows the same line, the shank leans. The mirror's samples as they were.
PenPath tiltedPath(const PenPath& path, const Vec3& axis, const Vec3& toward, double degrees);
// `b` after `a`: b's times shifted to start `gap_s` after a's last sample.
PenPath joinedPaths(const PenPath& a, const PenPath& b, double gap_s = 0.01);

}  // namespace dentsim
