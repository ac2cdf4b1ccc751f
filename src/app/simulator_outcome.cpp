// The simulator's end: the last segment closed, the devices let go, the sound and the final tooth written, and the outcome's figures drawn from the run's statistics.
#include <algorithm>
#include <chrono>

#include "app/simulator_state.h"
#include "core/percentile.h"
#include "volume/tooth_file.h"

namespace dentsim::app {

Status Simulator::finishRun(Status result) {
  // Whatever happened, the loop stops and the recording is closed, so that no drilling is lost.
  if (Status st = endSegment(result ? "completed" : "error"); !st && result) result = st;
  rack_.close();
  if (sound_.offline()) {
    if (Status st = sound_.finish(); !st && result) result = st;
    else if (st) out_.written.push_back(o_.sound.audio_out);
  }
  (void)painter_->context().waitIdle();  // teardown: a failure here changes nothing the user keeps
  if (!result) return result;
  // With validation on (DENTSIM_VALIDATION=1, as in the tests), any error fails the run.
  if (Status st = painter_->context().validationStatus(); !st) return st;
  if (!o_.out.empty() && !state_.final_saved) {
    if (Status st = saveTooth(outPath("final.dvol"), state_.view); !st) return st;
    out_.written.push_back(outPath("final.dvol"));
    // A score of an earlier state no longer describes the tooth as the run leaves it.
    out_.score.reset();
  }
  return Ok{};
}

void Simulator::fillOutcome() {
  if (!out_.score)
    out_.not_scored = !model_.task                        ? "no task"
                      : !end_.reason().empty()            ? end_.reason() + " before the cut was scored"
                      : model_.script && !o_.score_at_end ? "scoring was not asked for (--score-at-end)"
                                                          : "the cut was not scored (the panel's Score button scores it)";
  out_.wall_s = std::chrono::duration<double>(Clock::now() - stats_.run_t0).count();
  out_.haptic_steps = segments_.stepsDone();
  // Over the drilling only: set-up (voxelizing, point shells, pipelines) is not the loop's.
  const double drilling_s = std::chrono::duration<double>(Clock::now() - stats_.haptic_t0).count();
  out_.haptic_rate_hz = drilling_s > 0 ? double(out_.haptic_steps) / drilling_s : 0.0;
  stats_.fill(out_, end_.warmUpFramesLeftOut());
}

void SimRunStats::fill(SimulatorOutcome& out, int skip_frames) const {
  if (!frame_ms.empty()) {
    std::vector<double> sorted(frame_ms.begin() + std::min<ptrdiff_t>(skip_frames, ptrdiff_t(frame_ms.size()) - 1),
                               frame_ms.end());
    std::sort(sorted.begin(), sorted.end());
    double sum = 0;
    for (double v : sorted) sum += v;
    out.frame_ms_mean = sum / double(sorted.size());
    out.frame_ms_p50 = percentileSorted(sorted, 50.0);
    out.frame_ms_p95 = percentileSorted(sorted, 95.0);
  }
  out.remesh_ms_mean = remesh_count ? remesh_sum_ms / double(remesh_count) : 0.0;
  out.triangles = final_triangles;
  if (out.drawn) out.triangles_drawn_mean = triangles_drawn_sum / double(out.drawn);
}

}  // namespace dentsim::app
