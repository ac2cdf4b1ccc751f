// The crown preparation's live reduction map: the tooth as cut, its prepared surface painted by the reduction measured there (green within the task's band, blue under, red over), recomputed off the frame thread while the panel's switch is on.
//
// Contents
//   1. The map of one tooth: the bands, the margin height it reads above, the paint, the picture
//   2. ReductionMapRefresh: when a new map is computed, one at a time, at most once per interval
//
// The map is eval/crown_prep_reduction.h's measureReduction drawn as eval/score_image.h draws the
// score picture (occlusal and oblique views). The window does not know where the student will put
// the finish line, so it reads the surface above the highest margin the task accepts: the original
// enamel's cervical edge (the CEJ) plus CrownTask::margin_above_cej_hi_mm. Everything above that
// line must come off whatever the margin's final height, so a blue patch there is always work left;
// below it the surface may rightly stay whole and is left in its tissue's colour. A tooth without
// enamel has no CEJ to read: the map then starts at the lowest point cut so far, so that it shows
// only the walls the student has begun (and nothing before the first cut).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <future>
#include <optional>
#include <string>

#include "core/result.h"
#include "eval/crown_prep_reduction.h"
#include "eval/crown_score.h"
#include "eval/cut_marks.h"
#include "eval/task.h"
#include "io/png_file.h"
#include "volume/brick_volume.h"

namespace dentsim::app {

// ---- 1. one map ------------------------------------------------------------------------------------------

// The lowest original enamel voxel's centre height along `axis` (normalized here) from the grid
// origin [mm]: the CEJ, where the enamel ends. None when the tooth has no enamel.
std::optional<double> cejHeightMm(const ToothVolume& original, const Vec3& axis);

// The height the map reads above [mm, along the task's insertion axis from the grid origin], as
// this file's opening comment chooses it. None when the tooth has no enamel and nothing is cut yet.
std::optional<double> reductionMapMarginMm(const CrownTask& crown, const Vec3& insertion_axis,
                                           const ToothVolume& original, const ToothVolume& prepared);

struct ReductionMap {
  RgbImage picture;               // the current tooth, occlusal and oblique views, painted
  std::string legend;             // the bands, one line: "occlusal 1.5-2.0 mm, axial 1.0-1.5 mm"
  std::string summary;            // the painted voxels' shares, one line: "62% within, 30% under, 8% over"
  double margin_mm = 0.0;         // the height it read above [mm from the grid origin]
  double compute_ms = 0.0;        // measuring and drawing, wall time [ms]
};

// The map of `prepared` against `original` for a crown task. Both are read as the picture draws
// them: a voxel under half full (the cutter leaves worn voxels with a little fill) is not tooth.
// Errors, one line: not a crown task, nothing above the margin yet (see reductionMapMarginMm),
// measureReduction's own.
Result<ReductionMap> drawReductionMap(const Task& task, const ToothVolume& original, const ToothVolume& prepared);

// ---- 2. refresh ------------------------------------------------------------------------------------------

// When the frame loop computes a new map: only after the tooth changed, never two at once, and at
// least `interval` after the last one started, so that a long cut costs one worker thread's time
// about once a second and the frames never wait. The job runs on its own thread (std::async, at a
// lower priority than the frame loop) and must own what it reads: the frame loop hands it copies of
// the teeth. The clock is passed in, so
// that the rules are tested without waiting.
class ReductionMapRefresh {
 public:
  using Clock = std::chrono::steady_clock;
  using Job = std::function<Result<ReductionMap>()>;

  explicit ReductionMapRefresh(Clock::duration interval = std::chrono::seconds(1)) : interval_(interval) {}
  ~ReductionMapRefresh() { wait(); }  // a job in flight is finished, never left running
  ReductionMapRefresh(const ReductionMapRefresh&) = delete;
  ReductionMapRefresh& operator=(const ReductionMapRefresh&) = delete;

  // The tooth changed since the map last started (a cut, the switch turned on).
  void toothChanged() { stale_ = true; }
  // The map in flight, if any, is of no use any more (another tooth, the switch off, a score shown
  // over it): its result is dropped when it comes, and the change that asked for it is forgotten
  // (a caller that wants a new map says toothChanged() after).
  void discard() {
    ++generation_;
    stale_ = false;
  }
  bool stale() const { return stale_; }
  bool running() const { return future_.valid(); }
  // A change is waiting, nothing runs, and the interval has passed since the last start.
  bool due(Clock::time_point now) const {
    return stale_ && !running() && (!started_ || now - last_start_ >= interval_);
  }
  // Starts `job` now (the caller asked due(), or a picture on disk needs the map at once). Needs
  // !running().
  void start(Clock::time_point now, Job job);
  // The finished job's result, once; none while it runs, when none ran, or when it was discarded.
  std::optional<Result<ReductionMap>> take();
  // As take(), but waits for the job in flight to finish.
  std::optional<Result<ReductionMap>> wait();

 private:
  std::optional<Result<ReductionMap>> collect();

  Clock::duration interval_;
  std::future<Result<ReductionMap>> future_;
  uint64_t generation_ = 0;       // bumped by discard()
  uint64_t job_generation_ = 0;   // generation_ when the job in flight started
  bool stale_ = false;
  bool started_ = false;
  Clock::time_point last_start_;
};

}  // namespace dentsim::app
