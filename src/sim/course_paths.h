// The course's scripted dentists in one place: the professional's path for each built-in path name, and every attempt (expert or with one fault) at any exercise of the course.
//
// A task (eval/task.h) names its kind and, for a cavity or an access, the built-in path that makes
// its ideal. sim sits below eval, so callers pass those names, not the task: eval's idealForTask
// drills expertPath(), and `dentsim bench scores`, the tests and the demo drill taskAttemptPath().
//
//   path            what the professional does                                      bur
//   class1_cavity   an oval groove around the fossa (scripted_paths.h)             the task's
//   class2_cavity   an occlusal part to the mesial marginal ridge and a mesial box  fissure bur
//   class5_cavity   an oval on the buccal surface just above the CEJ, from buccal   round bur
//   access_cavity   through the occlusal centre into the pulp chamber, roof off    round bur
//   caries_removal  the careful caries removal of cariesRemovalPath (scripted_paths.h), which
//                   leaves a layer of dentin over the pulp (selective removal)               the task's
//   crown_prep      a full-crown preparation: the occlusal surface lowered, laps around the  chamfer bur
//                   axial walls converging to a chamfer above the CEJ (crown_paths.h)
//
// A caries task without an ideal has no path name, and its expert is cariesRemovalPath as well.
#pragma once

#include <array>
#include <string>

#include "core/result.h"
#include "core/rigid.h"
#include "io/pen_path_file.h"
#include "sim/novice_paths.h"
#include "sim/sim_params.h"
#include "volume/brick_volume.h"

namespace dentsim {

inline constexpr std::array<const char*, 6> kBuiltinPaths = {"class1_cavity", "class2_cavity", "class5_cavity",
                                                             "access_cavity", "caries_removal", "crown_prep"};
// "class1_cavity, class2_cavity, class5_cavity, access_cavity, caries_removal, crown_prep", for errors and help.
std::string builtinPathNames();
bool isBuiltinPath(const std::string& name);

// What the scripted dentist needs to know of an exercise.
struct Exercise {
  std::string kind = "cavity";   // the task's kind: "caries", "cavity", "access" or "crown" (taskKindName)
  std::string path;              // the built-in path of its ideal; empty: none (a caries removal)
  std::string bur = "round_bur_010";  // the drill's tool
  Vec3 insertion_axis{0, 0, 1};  // the bur's axis the task asks for (class5_cavity holds the bur along it;
                                 // crown_prep's walls converge about it)
};

// The professional's path `exercise.path` (which must be a built-in path), drilled with its bur
// and paced for `params`. Errors: an unknown path name, or what the path's generator reports.
Result<PenPath> expertPath(const Exercise& exercise, const BrickVolume& volume, const VolumeFrame& frame,
                           const SimParams& params);

// The attempt at the exercise: the expert's own path, or it with one fault (novice_paths.h):
//   overcut   caries: a raster over the lesion's box and beyond; class I: its outline, then one
//             1.6 times as wide; the others: the outline 1.6 times as wide (faults.overcut_widen)
//   undercut  stopped after faults.undercut_share of its cutting time
//   heavy     pressed faults.heavy_press times as far, and not held at the floor
//   slow      faults.slow_factor times slower, the pedal eased to match
//   trench    the groove across the buccal cusps (the wrong place), with the exercise's bur
// A crown preparation's own faults (overtaper ... nick) are edits of the professional's recorded
// session (session_attempts.h); here crown_prep has the expert, undercut, slow and token.
// Errors: an exercise without a path that is not a caries removal, an attempt the path has not, or
// the generator's.
Result<PenPath> taskAttemptPath(const Exercise& exercise, Attempt attempt, const BrickVolume& volume,
                                const VolumeFrame& frame, const SimParams& params, const AttemptFaults& faults = {});

}  // namespace dentsim
