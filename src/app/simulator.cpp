// The simulator's frame loop: one frame as a contents list of stages (input, haptics, edits, surfaces, reduction map, readouts, panel, scene, actions, end rules), and the run from set-up to outcome.
//
// The parts it drives, one job each: the device rack (pens and pedal), the segments (loops and
// their sessions), the frame painter (window, device, renderer), the window's input, the pictures
// on disk (screenshots.h), the score screen, the sound and the end rules (sim_end_rules.h).
// simulator_setup.cpp sets them up; simulator_segments.cpp starts and ends segments;
// simulator_scene.cpp draws; simulator_panel.cpp carries out the panel's actions and the score;
// simulator_picks.cpp the tooth and task picks; simulator_ghost.cpp the professional's ghost;
// simulator_reduction.cpp a crown task's live reduction map.
#include "app/simulator.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <limits>

#include "app/simulator_state.h"

namespace dentsim::app {
namespace {

using Clock = Simulator::Clock;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Ctrl-C ends the run the way closing the window does, so that the session is finished and the
// files are listed. A signal handler can only reach a global; nothing else is shared through it.
std::atomic<bool> g_interrupted{false};
extern "C" void onInterrupt(int) { g_interrupted.store(true); }

// Installs the handler for one run and puts the previous one back.
class InterruptGuard {
 public:
  InterruptGuard() {
    g_interrupted.store(false);
    previous_ = std::signal(SIGINT, onInterrupt);
  }
  ~InterruptGuard() { std::signal(SIGINT, previous_); }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  void (*previous_)(int) = SIG_DFL;
};

}  // namespace

// ---- one frame -------------------------------------------------------------------------------------------

// Headless, a frame nobody sees still steps the loop and keeps the edits, but skips the surfaces,
// the panel, the scene and the actions: the pictures a run writes never depend on frames unseen.
Status Simulator::frame() {
  const auto t0 = Clock::now();
  readInput();
  if (Status st = feedScriptedInput(); !st) return st;
  clickAfterScore();
  const FramePlan plan = stepHaptics();
  drainEdits();
  if (Status st = updateSurfaces(plan); !st) return st;
  if (Status st = refreshReductionMap(plan); !st) return st;
  showReadouts(segments_.state());
  ui::PanelActions actions = drawPanel(plan);
  if (plan.draw) {
    state_.last_actions = actions;
    if (Status st = drawFrame(plan.due); !st) return st;
    if (Status st = handleActions(actions); !st) return st;
    if (Status st = handleReview(actions.review); !st) return st;  // simulator_review.cpp
    timeFrame(t0, plan);
  }
  ++out_.frames;
  return applyEndRules(plan.t);
}

void Simulator::readInput() {
  if (ui::Window* window = painter_->window()) {
    ui::Window::pollEvents();
    if (window->closeRequested()) end_.stop("the window was closed");
  }
  if (g_interrupted.load()) end_.stop("interrupted (Ctrl-C)");
}

FramePlan Simulator::stepHaptics() {
  // Lockstep: the haptic loop catches up with this frame's loop time.
  if (lockstep_) segments_.stepTo(double(out_.frames) / o_.fps);
  FramePlan plan;
  plan.t = segments_.loopTime();
  if (!o_.out.empty()) plan.due = shots_.at(plan.t);
  // Headless, a frame nobody will see is not drawn: the edits wait, and the steps run back to back.
  plan.draw = !headless_ || plan.picture() || end_.benchDraws(plan.t);
  // A headless frame's time starts here: the haptic steps the frame loop ran for it are not drawing.
  plan.draw_t0 = Clock::now();
  return plan;
}

void Simulator::drainEdits() {
  // The loop's voxel edits reach this copy of the tooth at once; the changed bricks are re-meshed
  // when the frame is drawn.
  const size_t dirty_before = state_.pending_dirty.size();
  segments_.drainEdits(state_.view.voxels, &state_.pending_dirty);
  if (state_.pending_dirty.size() != dirty_before) map_.toothChanged();
}

Status Simulator::updateSurfaces(const FramePlan& plan) {
  if (!plan.draw) return Ok{};
  render::ToothSurfaces& surfaces = painter_->surfaces();
  if (!state_.pending_dirty.empty()) {
    gpu::SurfaceUpdateStats st;
    if (Status u = painter_->remesh(state_.view.voxels, &state_.pending_dirty, &st); !u) return u;
    stats_.remesh_sum_ms += st.total_ms;
    ++stats_.remesh_count;
    ui_.stats.remesh_ms = st.total_ms;
    stats_.final_triangles = st.triangles;
  } else if (surfaces.coarseLagging()) {
    // Nothing cut this frame: the coarse copies catch up with the cuts they lag behind.
    if (Status u = surfaces.update(state_.view.voxels, {}); !u) return u;
  }
  if (surfaces.done()) return Ok{};
  // A first frame in parts: full detail fills in nearest the eye first, a slice of each frame. A
  // picture written to a file never depends on how fast this machine meshes: it waits for all.
  const double slice_ms = plan.picture() ? std::numeric_limits<double>::infinity() : kDetailSliceMs;
  if (Status st = surfaces.continueBuild(state_.view.voxels, camera_.eye(), slice_ms); !st) return st;
  ui_.stats.detail_progress = surfaces.progress();
  progress_.progress(surfaces.progress());
  if (surfaces.done()) {
    progress_.end();
    out_.full_detail_s = secondsSince(stats_.run_t0);
    std::printf("surface: full detail everywhere %.1f s after the start\n", out_.full_detail_s);
    end_.fullDetailReached();
  }
  return Ok{};
}

void Simulator::showReadouts(const HapticState& state) {
  followGhost(state);
  const ToolState& drill = state.tools[size_t(PenRole::Drill)];
  ui_.force.force_n = norm(drill.display.force);
  ui_.force.contact = drill.contacts > 0;
  ui_.force.max_force_n = ui_.params.device.max_force_n;
  showGuidePull(state, painter_->extent());
  if (ui_.pedal_present) ui_.turbine_speed = state.pedal;
  if (rack_.service(segments_.running())) end_.stopQuietly();
  sound_.update(camera_, ui_.sound.volume, ui_.sound.mute, state);
  const double wall = secondsSince(stats_.rate_t0);
  const uint64_t steps_now = segments_.stepsAll();
  if (wall > 0.5) {
    ui_.stats.haptic_rate_hz = double(steps_now - stats_.rate_steps) / wall;
    stats_.rate_steps = steps_now;
    stats_.rate_t0 = Clock::now();
  }
}

ui::PanelActions Simulator::drawPanel(const FramePlan& plan) {
  ui::PanelActions actions;
  if (!plan.draw) return actions;  // nothing shown: no panel either
  ui::ImGuiLayer* panel = painter_->panel();
  if (!panel) {
    if (pens_) pens_->setViewport(o_.frames.width, o_.frames.height);
    return actions;
  }
  const VkExtent2D e = painter_->extent();
  const double dt_s = lockstep_ ? 1.0 / o_.fps : msSince(stats_.last_frame) / 1000.0;
  if (state_.panel_relayout) {
    // ImGui shows a new tab (all of them on the first frame, the Score page with a score) and
    // brings a page forward only from the next frame on: such a frame is laid out once unseen,
    // so that the one shot a headless run takes of it shows it whole. Its actions are dropped.
    panel->newFrame(int(e.width), int(e.height), dt_s);
    const ui::PanelActions laid = ui::drawParamPanel(ui_);
    state_.panel_rect = laid.panel_rect;  // where the scene's shift comes from
    state_.help_rect = laid.help_rect;
    ui::drawOverlay(ui_);
    panel->discardFrame();
    state_.panel_relayout = false;
  }
  // The tooth as this frame draws it, beside the panel (which stays where it was last frame).
  ui_.keep_clear = toothRect(e);
  panel->newFrame(int(e.width), int(e.height), dt_s);
  actions = ui::drawParamPanel(ui_, inputs_.empty() && o_.review.presses.empty() ? nullptr : &rects_);
  ui::drawOverlay(ui_);
  state_.panel_rect = actions.panel_rect;
  state_.help_rect = actions.help_rect;
  if (pens_ && painter_->windowed()) pens_->setViewport(int(std::max(1u, e.width)), int(std::max(1u, e.height)));
  return actions;
}

void Simulator::timeFrame(Clock::time_point t0, const FramePlan& plan) {
  ++out_.drawn;
  // Windowed, the time from frame to frame (the frame rate); headless, the frame's own time.
  stats_.frame_ms.push_back(headless_ ? msSince(plan.draw_t0) : msSince(stats_.last_frame));
  ui_.stats.frame_ms = msSince(t0);
  stats_.last_frame = Clock::now();
}

Status Simulator::applyEndRules(double t) {
  end_.limits(t, out_.drawn);
  if (end_.scriptEnds(t, segments_.running())) {
    if (Status st = endScript(); !st) return st;
    end_.scriptEnded(secondsSince(stats_.run_t0));
  }
  end_.afterScript(shots_.finalShotPending(), segments_.running(), secondsSince(stats_.run_t0));
  // Stopped, loop time stands still; headless it follows the frames, so that --exit-after ends it.
  if (headless_ && !segments_.running()) segments_.holdTimeAtLeast(double(out_.frames) / o_.fps);
  return Ok{};
}

Status Simulator::endScript() {
  if (o_.record_ideal_at_end)
    if (Status st = recordIdeal(); !st) return st;
  if (Status st = endSegment("completed"); !st) return st;
  if (o_.score_at_end)
    if (Status st = scoreNow(); !st) return st;
  // One more frame shows the end (and the score); headless then stops.
  if (!o_.out.empty()) shots_.finalShot();
  return Ok{};
}

// ---- the run ---------------------------------------------------------------------------------------------

Result<SimulatorOutcome> Simulator::run() {
  stats_.run_t0 = Clock::now();
  stats_.last_frame = stats_.run_t0;
  if (Status st = setUp(); !st) {
    rack_.close();  // whatever opened gets zero force and is let go
    return st.error();
  }
  const InterruptGuard interrupt;
  Status result = Ok{};
  // Scripted clicks after the score hold a quiet end (--exit-at-end) until they are done.
  while (result && (!end_.quit() || reviewHolds())) result = frame();
  if (Status st = finishRun(result); !st) return st.error();
  fillOutcome();
  return out_;
}

Result<SimulatorOutcome> runSimulator(const SimulatorOptions& options) {
  Simulator sim(options);
  return sim.run();
}

}  // namespace dentsim::app
