// GuideSpring: haptic guidance, a spring that pulls the student's bur toward a professional's recorded path, at the nearest point ahead on it.
//
// The path is the professional's drill grip, 100 points a second (sim/pro_path.h). Each step the
// guide looks for the point nearest the student's bur among the points ahead of the last one it
// chose (within search_s of the professional's time), never behind: a student who follows is led
// on, and one who wanders is pulled back to where the professional was at that stage of the work,
// not to a later pass over the same place. The spring pulls toward the point lookahead_s further
// on, so that it also leads along the path. Its force is capped on its own (max_force_n) and then
// joins the coupling's force, so the device's clamp and the devices' safety layer bound the sum.
//
// The guide is a pure function of its path and the bur's positions: a session records the path
// and the settings in its header (guideJson), and the replay rebuilds the same guide from it, so a
// guided session replays to the same forces.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "io/pen_path_file.h"
#include "sim/pro_path.h"

namespace dentsim {

// What a guide may hold, so that a session's header cannot make the 1 kHz step slow: its search
// covers at most kMaxGuideSearchPoints points a step (20 s of the professional's at 100 a second),
// and its path at most kMaxGuidePoints (an hour), which also keeps the header under the session
// reader's 16 MiB.
inline constexpr size_t kMaxGuideSearchPoints = 2000;
inline constexpr size_t kMaxGuidePoints = 360000;

struct GuideSettings {
  double stiffness_n_per_mm = 1.0;  // the spring toward the path [N/mm]; > 0
  double max_force_n = 2.0;         // the guide's own cap, under the device's [N]; > 0
  double lookahead_s = 0.05;        // the spring's end is this much of the professional's time ahead [s]; >= 0
  double search_s = 1.0;            // the nearest point is sought this far ahead of the last [s]; > 0
};

// What a guided session follows; its header's "guide" object.
struct GuidePath {
  GuideSettings settings;
  std::string source;               // the professional's session file, as given
  std::string source_hash;          // its XXH3 (io/file_hash.h), 16 hex digits
  std::string source_task;          // the professional's task (SessionInfo::task)
  std::string source_tooth_hash;    // the tooth the professional cut (SessionInfo::tooth_hash)
  double spacing_s = ProPath::kSampleEveryS;  // time between points [s]
  std::vector<Vec3> points;         // the professional's drill grip, rounded to 0.1 um [mm]
  size_t start_index = 0;           // the point the guide starts from (a later segment goes on where the last stopped)
};

// The drill's path of `pro`, with `settings`. The points are rounded so that their JSON text reads
// back to the same numbers.
GuidePath guidePathFrom(const ProPath& pro, const GuideSettings& settings, const std::string& source,
                        const std::string& source_hash);
// The drill's path of a scripted preparation (the task's professional, sim/course_paths.h), its
// grip sampled every ProPath::kSampleEveryS (linearly between the script's samples), for the
// tasks with no recorded session: the guide on every shipped task. `source` names it ("the task's
// scripted professional"), the hash is the points' own (XXH3), the task and tooth are the caller's.
// Empty points when the path has no drill sample.
GuidePath guidePathFromScript(const PenPath& script, const GuideSettings& settings, const std::string& source,
                              const std::string& task, const std::string& tooth_hash);
// Reads `path` (a session file) into a guide: one line naming the file when it does not read.
Result<GuidePath> loadGuidePath(const std::string& path, const GuideSettings& settings);

// The header's JSON object (one line) and its reader, which checks every value: one line naming
// `where` and the field.
std::string guideJson(const GuidePath& path);
Result<GuidePath> parseGuideJson(const std::string& text, const std::string& where);

class GuideSpring {
 public:
  explicit GuideSpring(GuidePath path) : path_(std::move(path)) { reset(); }

  // The force on the pen for the bur's grip at `bur_grip` [mm] -> [N]; moves the guide on.
  Vec3 force(const Vec3& bur_grip);
  void reset() { cursor_ = path_.points.empty() ? 0 : std::min(path_.start_index, path_.points.size() - 1); }
  size_t cursor() const { return cursor_; }  // the point chosen last
  const GuidePath& path() const { return path_; }

 private:
  GuidePath path_;
  size_t cursor_ = 0;
};

}  // namespace dentsim
