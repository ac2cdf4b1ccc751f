// The simulator's frame loop: segments started and ended, one frame (edits, re-mesh, panel, draw, pictures), the panel's actions, the score screen, and the run's outcome.
//
// The parts it drives, one job each: the device rack (pens and pedal), the segments (loops and
// their sessions), the frame painter (window, device, renderer), the window's input, the pictures
// on disk (screenshots.h), the score screen and the sound; simulator_setup.cpp sets them up, and
// simulator_picks.cpp carries out the panel's tooth and task picks and Record as ideal.
#include "app/simulator.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <limits>
#include <cstdio>

#include "app/score_screen.h"
#include "app/simulator_state.h"
#include "core/percentile.h"
#include "eval/cut_score.h"
#include "io/session_file.h"
#include "sim/tool_library.h"
#include "volume/tooth_file.h"

namespace dentsim::app {
namespace {

using Clock = Simulator::Clock;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

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

// ---- segments ------------------------------------------------------------------------------------------

Status Simulator::startSegment() {
  SegmentSetup s;
  s.params = &params_;
  s.params_json = ui::presetJson({params_, looks_});
  s.drill = &*drill_tool_;
  s.mirror = mirror_tool_ ? &*mirror_tool_ : nullptr;
  s.pens = {rack_.pen(PenRole::Drill), rack_.pen(PenRole::Mirror)};
  s.drill_name = drill_name_;
  s.mirror_name = mirror_name_;
  s.task_name = task_ ? task_->name : "";
  s.tooth_source = builtinTooth() ? builtinToothSource(o_.level) : toothName();
  s.idle_latency_us = o_.idle_latency_us;
  s.lockstep = lockstep_;
  s.out = o_.out;
  s.guide = guide_ ? &*guide_ : nullptr;
  s.guide_goes_on = tooth_first_segment_ <= segments_.count();  // not the first segment on this tooth
  if (Status st = segments_.start(cut_, s, &out_.written); !st) return st;
  restartGhost();
  final_saved_ = false;
  ui_.segment_recorded = segments_.recording();
  // Forces may go out only now that the loop commands them every step (the watchdog counts from here).
  rack_.enable();
  rate_steps_ = segments_.stepsDone();
  rate_t0_ = Clock::now();
  if (segments_.count() == 1) haptic_t0_ = rate_t0_;
  ui_.run_state = ui::RunState::Running;
  return Ok{};
}

Status Simulator::endSegment(const std::string& reason) {
  if (!segments_.running()) return Ok{};
  // Zero force before the loop stops commanding it (else every pen would latch a watchdog fault).
  rack_.disable();
  Status result = segments_.end(reason, cut_, &out_.written);
  if (std::string denial = segments_.takeIdleLatencyDenial(); !denial.empty()) note("dentsim: " + denial);
  // The loop's last edits reach the frame loop's copy before the next loop starts.
  segments_.drainEdits(view_.voxels, &pending_dirty_);
  if (painter_)
    if (Status st = painter_->remesh(view_.voxels, &pending_dirty_); !st && result) result = st;
  out_.removed_mm3 = segments_.removedDoneMm3();
  ui_.run_state = ui::RunState::Stopped;
  ui_.segment_recorded = false;
  return result;
}

// ---- one frame -------------------------------------------------------------------------------------------

render::FrameState Simulator::frameState(const HapticState& state, VkExtent2D extent) const {
  // The parameter window covers the right edge: the view's centre moves into the rest, so that the
  // tooth sits in the middle of what the student sees.
  render::FrameState fs = sceneFrameState(
      camera_, extent, float(sceneShiftPx()), 0.0f, state,
      SceneContents{view_.frame, ui_.looks.looks, drill_name_, mirror_tool_.has_value(), ui_.params.device.max_force_n});
  showGhost(fs);
  fs.lod.pixel_error = o_.detail_pixels;
  if (score_shown_ && !last_actions_.score_image_rect.empty()) {
    fs.overlay_shown = true;
    fs.overlay_rect = last_actions_.score_image_rect;
  }
  return fs;
}

PixelRect Simulator::toothRect(VkExtent2D extent) const {
  // The tissue box's corners projected as drawn (shifted beside the panel).
  const int w = int(std::max(1u, extent.width)), h = int(std::max(1u, extent.height));
  float lo_x = 1e9f, lo_y = 1e9f, hi_x = -1e9f, hi_y = -1e9f;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p{(i & 1) ? box_.hi.x : box_.lo.x, (i & 2) ? box_.hi.y : box_.lo.y, (i & 4) ? box_.hi.z : box_.lo.z};
    if (camera_.depthOf(render::toGlm(p)) <= camera_.nearMm()) return {};
    const glm::vec3 px = camera_.project(render::toGlm(p), w, h);
    lo_x = std::min(lo_x, px.x - float(sceneShiftPx()));
    hi_x = std::max(hi_x, px.x - float(sceneShiftPx()));
    lo_y = std::min(lo_y, px.y);
    hi_y = std::max(hi_y, px.y);
  }
  PixelRect r;
  r.x = int(std::floor(lo_x));
  r.y = int(std::floor(lo_y));
  r.width = int(std::ceil(hi_x)) - r.x;
  r.height = int(std::ceil(hi_y)) - r.y;
  return r;
}

Status Simulator::drawFrame(const ShotSchedule::Due& due) {
  const HapticState state = segments_.state();
  render::FrameState drawn;
  const bool read_back = !due.shot_stem.empty() || !due.frame_stem.empty();
  auto picture = painter_->draw(
      [&](VkExtent2D extent) {
        drawn = frameState(state, extent);
        return drawn;
      },
      read_back);
  if (!picture) return picture.error();
  const render::ToothDrawStats drew = painter_->renderer().toothDrawStats();
  ui_.stats.triangles = drew.main_triangles + drew.mirror_triangles;
  triangles_drawn_sum_ += double(ui_.stats.triangles);
  if (out_.drawn == 0) out_.first_frame_s = std::chrono::duration<double>(Clock::now() - run_t0_).count();
  if (!*picture) return Ok{};
  if (!due.shot_stem.empty()) {
    ShotFacts facts;
    facts.loop_time_s = segments_.loopTime();
    facts.windowed = !headless_;
    facts.shift_px = float(sceneShiftPx());
    facts.tooth_centre = box_.centre();
    facts.removed_mm3 = segments_.removedMm3();
    if (painter_->panel()) facts.score_image_rect = last_actions_.score_image_rect;
    facts.panel_shown = painter_->panel() != nullptr;
    facts.panel_rect = panel_rect_;
    facts.task = task_ ? task_->name : "";
    facts.view_fixed = input_.viewFixed();
    facts.tooth_top_mm = box_.hi.z;
    facts.tooth_rect = toothRect(painter_->extent());
    if (Status st = writeShot(outPath(due.shot_stem), **picture, camera_, drawn, facts); !st) return st;
    out_.written.push_back(outPath(due.shot_stem + ".png"));
  }
  if (!due.frame_stem.empty()) {
    const std::string png = outPath(due.frame_stem + ".png");
    if (Status st = writePng(png, **picture); !st) return st;
    out_.written.push_back(png);
  }
  return Ok{};
}

Status Simulator::scoreNow() {
  if (!task_) return Ok{};
  // The session holds the whole cut when this tooth has had one segment only.
  ScoredCut cut;
  const int on_tooth = segments_.count() - tooth_first_segment_ + 1;
  if (o_.out.empty())
    cut.no_session_reason = "no session was recorded (no --out folder)";
  else if (on_tooth > 1)
    cut.no_session_reason = "the cut spans " + std::to_string(on_tooth) + " segments, and no one session holds it";
  else {
    cut.initial_file = segments_.initialPath();
    cut.session_file = segments_.sessionPath();
  }
  auto score = scoreForScreen(*task_, initial_, view_, cut, o_.out);
  if (!score) return score.error();
  final_saved_ = !o_.out.empty();
  ui_.score = score->panel;
  panel_relayout_ = true;  // the Score page appears and comes forward
  if (Status st = painter_->renderer().setOverlayImage(score->picture); !st) return st;
  score_shown_ = true;
  out_.score = score->total;
  note(score->summary);
  for (const std::string& w : score->warnings) noteWarning(w);
  for (std::string& f : score->written) out_.written.push_back(std::move(f));
  if (o_.on_scored) {
    o_.on_scored(*task_, score->report, cut.session_file, final_saved_ ? outPath("final.dvol") : "");
    // The score report names its learning record's statement, so that a class report counts it once.
    if (final_saved_ && score->report.contains("statement_id"))
      if (Status st = writeScoreReport(outPath("score.json"), score->report); !st) return st;
  }
  return Ok{};
}

Status Simulator::handleActions(ui::PanelActions& a) {
  ui::applyPresetActions(a, *presets_, ui_);
  if (a.params_changed) {
    params_ = ui_.params;
    looks_ = ui_.looks;
    if (segments_.recorder()) segments_.recorder()->setParams(params_, ui::presetJson({params_, looks_}));
    else if (segments_.loop()) segments_.loop()->setParams(params_);
  }
  if (a.normal_mode_changed) painter_->surfaces().setNormalMode(looks_.view.normals);
  if (a.speed_changed && pens_) pens_->setPedal(ui_.turbine_speed);
  // Teacher mode needs its segments recorded: without --out they go to a temporary folder from the
  // next segment on (Reset starts one).
  if (ui_.teacher && o_.out.empty())
    if (Status st = recordingFolder(); !st) return st;
  if (a.task_changed)
    if (Status st = pickTask(); !st) return st;
  if (a.tooth_changed && !a.task_changed)
    if (Status st = pickTooth(); !st) return st;
  if (a.record_ideal)
    if (Status st = recordIdeal(); !st) return st;
  const bool running = segments_.running();
  if (a.stop && running)
    if (Status st = endSegment("stopped"); !st) return st;
  if (a.start && !running)
    if (Status st = startSegment(); !st) return st;
  if (a.bur_changed && ui_.bur != drill_name_) {
    if (running)
      if (Status st = endSegment("bur changed"); !st) return st;
    drill_name_ = ui_.bur;
    if (Status st = loadDrill(); !st) return st;
    note("drill: " + drill_name_);
    if (running)
      if (Status st = startSegment(); !st) return st;
  }
  if (a.level_changed && !builtinTooth()) {
    note("the voxel level applies to the built-in molar; " + toothName() + " keeps its own grid");
    ui_.level = initial_.frame.level;
  }
  if (a.reset || (a.level_changed && builtinTooth())) {
    if (running)
      if (Status st = endSegment("reset"); !st) return st;
    if (a.level_changed) {
      o_.level = ui_.level;
      if (Status st = loadTooth(); !st) return st;
    } else {
      cut_ = initial_;
      view_ = initial_;
    }
    if (Status st = painter_->surfaces().build(view_.voxels); !st) return st;
    score_shown_ = false;
    ui_.score = {};
    tooth_first_segment_ = segments_.count() + 1;  // the restored or rebuilt tooth starts uncut
    if (Status st = startSegment(); !st) return st;
  }
  if (a.score) {
    if (segments_.running())
      if (Status st = endSegment("scored"); !st) return st;
    if (Status st = scoreNow(); !st) return st;
  }
  return Ok{};
}

Status Simulator::frame() {
  const auto t0 = Clock::now();
  if (ui::Window* window = painter_->window()) {
    ui::Window::pollEvents();
    if (window->closeRequested()) {
      quit_ = true;
      quit_reason_ = "the window was closed";
    }
  }
  if (g_interrupted.load()) {
    quit_ = true;
    quit_reason_ = "interrupted (Ctrl-C)";
  }
  // Lockstep: the haptic loop catches up with this frame's loop time.
  if (lockstep_) segments_.stepTo(double(out_.frames) / o_.fps);
  const double t = segments_.loopTime();
  const ShotSchedule::Due due = o_.out.empty() ? ShotSchedule::Due{} : shots_.at(t);
  // Headless, a frame nobody will see is not drawn: the edits wait, and the steps run back to back.
  const bool draw = !headless_ || !due.shot_stem.empty() || !due.frame_stem.empty() ||
                    (o_.bench_frames > 0 && t >= o_.bench_from_s - 1e-9);
  // A headless frame's time starts here: the haptic steps the frame loop ran for it are not drawing.
  const auto draw_t0 = Clock::now();

  // The loop's voxel edits reach this copy of the tooth at once; the changed bricks are re-meshed
  // when the frame is drawn.
  segments_.drainEdits(view_.voxels, &pending_dirty_);
  render::ToothSurfaces& surfaces = painter_->surfaces();
  if (draw && !pending_dirty_.empty()) {
    gpu::SurfaceUpdateStats st;
    if (Status u = painter_->remesh(view_.voxels, &pending_dirty_, &st); !u) return u;
    remesh_sum_ms_ += st.total_ms;
    ++remesh_count_;
    ui_.stats.remesh_ms = st.total_ms;
    final_triangles_ = st.triangles;
  } else if (draw && surfaces.coarseLagging()) {
    // Nothing cut this frame: the coarse copies catch up with the cuts they lag behind.
    if (Status u = surfaces.update(view_.voxels, {}); !u) return u;
  }
  // A first frame in parts: full detail fills in nearest the eye first, a slice of each frame.
  if (draw && !surfaces.done()) {
    // A picture written to a file never depends on how fast this machine meshes: it waits for all.
    const bool picture_due = !due.shot_stem.empty() || !due.frame_stem.empty();
    const double slice_ms = picture_due ? std::numeric_limits<double>::infinity() : kDetailSliceMs;
    if (Status st = surfaces.continueBuild(view_.voxels, camera_.eye(), slice_ms); !st) return st;
    ui_.stats.detail_progress = surfaces.progress();
    progress_.progress(surfaces.progress());
    if (surfaces.done()) {
      progress_.end();
      out_.full_detail_s = std::chrono::duration<double>(Clock::now() - run_t0_).count();
      std::printf("surface: full detail everywhere %.1f s after the start\n", out_.full_detail_s);
      if (o_.quit_at_full_detail) quit_ = true;
    }
  }

  const HapticState state = segments_.state();
  followGhost(state);
  const ToolState& drill = state.tools[size_t(PenRole::Drill)];
  ui_.force.force_n = norm(drill.display.force);
  ui_.force.contact = drill.contacts > 0;
  ui_.force.max_force_n = ui_.params.device.max_force_n;
  if (ui_.pedal_present) ui_.turbine_speed = state.pedal;
  if (rack_.service(segments_.running())) quit_ = true;
  sound_.update(camera_, ui_.sound.volume, ui_.sound.mute, state);
  const double wall = std::chrono::duration<double>(Clock::now() - rate_t0_).count();
  const uint64_t steps_now = segments_.stepsAll();
  if (wall > 0.5) {
    ui_.stats.haptic_rate_hz = double(steps_now - rate_steps_) / wall;
    rate_steps_ = steps_now;
    rate_t0_ = Clock::now();
  }

  // The panel.
  ui::PanelActions actions;
  if (!draw) {
    // nothing shown: no panel either
  } else if (ui::ImGuiLayer* panel = painter_->panel()) {
    const VkExtent2D e = painter_->extent();
    const double dt_s = lockstep_ ? 1.0 / o_.fps : msSince(last_frame_) / 1000.0;
    if (panel_relayout_) {
      // ImGui shows a new tab (all of them on the first frame, the Score page with a score) and
      // brings a page forward only from the next frame on: such a frame is laid out once unseen,
      // so that the one shot a headless run takes of it shows it whole. Its actions are dropped.
      panel->newFrame(int(e.width), int(e.height), dt_s);
      panel_rect_ = ui::drawParamPanel(ui_).panel_rect;  // where the scene's shift comes from
      ui::drawOverlay(ui_);
      panel->discardFrame();
      panel_relayout_ = false;
    }
    // The tooth as this frame draws it, beside the panel (which stays where it was last frame).
    ui_.keep_clear = toothRect(e);
    panel->newFrame(int(e.width), int(e.height), dt_s);
    actions = ui::drawParamPanel(ui_);
    ui::drawOverlay(ui_);
    panel_rect_ = actions.panel_rect;
    if (pens_ && painter_->windowed()) pens_->setViewport(int(std::max(1u, e.width)), int(std::max(1u, e.height)));
  } else if (pens_) {
    pens_->setViewport(o_.width, o_.height);
  }

  if (draw) {
    last_actions_ = actions;
    if (Status st = drawFrame(due); !st) return st;
    if (Status st = handleActions(actions); !st) return st;
    ++out_.drawn;
    // Windowed, the time from frame to frame (the frame rate); headless, the frame's own time.
    frame_ms_.push_back(headless_ ? msSince(draw_t0) : msSince(last_frame_));
    ui_.stats.frame_ms = msSince(t0);
    last_frame_ = Clock::now();
  }
  ++out_.frames;

  // The end: the script played out (and scored when asked), or the time given.
  if (o_.exit_after_s > 0 && t >= o_.exit_after_s - 1e-9) {
    quit_ = true;
    quit_reason_ = "--exit-after ended the run";
  }
  if (o_.bench_frames > 0 && out_.drawn >= uint64_t(o_.bench_frames)) quit_ = true;
  if (script_ && segments_.running() && t >= script_end_s_ + 0.2) {
    if (o_.record_ideal_at_end)
      if (Status st = recordIdeal(); !st) return st;
    if (Status st = endSegment("completed"); !st) return st;
    if (o_.score_at_end)
      if (Status st = scoreNow(); !st) return st;
    // One more frame shows the end (and the score); headless then stops.
    if (!o_.out.empty()) shots_.finalShot();
    if ((headless_ && o_.exit_after_s <= 0) || o_.exit_at_end) quit_after_final_ = true;
    ended_at_ = Clock::now();
  }
  if (quit_after_final_ && !shots_.finalShotPending() && !segments_.running()) quit_ = true;
  // Windowed, the score screen stays up this long, then the window closes by itself.
  if (ended_at_ && o_.linger_s >= 0 && !segments_.running() &&
      std::chrono::duration<double>(Clock::now() - *ended_at_).count() >= o_.linger_s)
    quit_ = true;
  // Stopped, loop time stands still; headless it follows the frames, so that --exit-after ends it.
  if (headless_ && !segments_.running()) segments_.holdTimeAtLeast(double(out_.frames) / o_.fps);
  return Ok{};
}

Result<SimulatorOutcome> Simulator::run() {
  run_t0_ = Clock::now();
  last_frame_ = run_t0_;
  if (Status st = setUp(); !st) {
    rack_.close();  // whatever opened gets zero force and is let go
    return st.error();
  }
  const InterruptGuard interrupt;
  Status result = Ok{};
  while (result && !quit_) result = frame();
  // Whatever happened, the loop stops and the recording is closed, so that no drilling is lost.
  if (Status st = endSegment(result ? "completed" : "error"); !st && result) result = st;
  rack_.close();
  if (sound_.offline()) {
    if (Status st = sound_.finish(); !st && result) result = st;
    else if (st) out_.written.push_back(o_.audio_out);
  }
  (void)painter_->context().waitIdle();  // teardown: a failure here changes nothing the user keeps
  if (!result) return result.error();
  // With validation on (DENTSIM_VALIDATION=1, as in the tests), any error fails the run.
  if (Status st = painter_->context().validationStatus(); !st) return st.error();
  if (!o_.out.empty() && !final_saved_) {
    if (Status st = saveTooth(outPath("final.dvol"), view_); !st) return st.error();
    out_.written.push_back(outPath("final.dvol"));
    // A score of an earlier state no longer describes the tooth as the run leaves it.
    out_.score.reset();
  }
  if (!out_.score)
    out_.not_scored = !task_                         ? "no task"
                      : !quit_reason_.empty()        ? quit_reason_ + " before the cut was scored"
                      : script_ && !o_.score_at_end ? "scoring was not asked for (--score-at-end)"
                                                    : "the cut was not scored (the panel's Score button scores it)";
  out_.wall_s = std::chrono::duration<double>(Clock::now() - run_t0_).count();
  out_.haptic_steps = segments_.stepsDone();
  // Over the drilling only: set-up (voxelizing, point shells, pipelines) is not the loop's.
  const double drilling_s = std::chrono::duration<double>(Clock::now() - haptic_t0_).count();
  out_.haptic_rate_hz = drilling_s > 0 ? double(out_.haptic_steps) / drilling_s : 0.0;
  if (!frame_ms_.empty()) {
    // The first frames build the pipelines' caches and the panel's layout: a benchmark leaves them out.
    std::vector<double> sorted(frame_ms_.begin() + std::min<ptrdiff_t>(o_.bench_frames > 0 ? 3 : 0, ptrdiff_t(frame_ms_.size()) - 1),
                               frame_ms_.end());
    std::sort(sorted.begin(), sorted.end());
    double sum = 0;
    for (double v : sorted) sum += v;
    out_.frame_ms_mean = sum / double(sorted.size());
    out_.frame_ms_p50 = percentileSorted(sorted, 50.0);
    out_.frame_ms_p95 = percentileSorted(sorted, 95.0);
  }
  out_.remesh_ms_mean = remesh_count_ ? remesh_sum_ms_ / double(remesh_count_) : 0.0;
  out_.triangles = final_triangles_;
  if (out_.drawn) out_.triangles_drawn_mean = triangles_drawn_sum_ / double(out_.drawn);
  return out_;
}

Result<SimulatorOutcome> runSimulator(const SimulatorOptions& options) {
  Simulator sim(options);
  return sim.run();
}

}  // namespace dentsim::app
