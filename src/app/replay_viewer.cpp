// The replay window's frame loop: the playhead moved, the cursor stepped or restarted, the edits drained and re-meshed, the panel and the scene drawn, the end's files written once.
#include "app/replay_viewer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "app/commands.h"
#include "app/first_view.h"
#include "app/frame_painter.h"
#include "app/ghost.h"
#include "app/screenshots.h"
#include "app/window_input.h"
#include "io/png_file.h"
#include "render/camera.h"
#include "render/look_params.h"
#include "sim/edit_channel.h"
#include "sim/replay_cursor.h"
#include "sim/surface_probe.h"
#include "ui/replay_panel.h"
#include "ui/window.h"

namespace dentsim::app {
namespace {

using Clock = std::chrono::steady_clock;

// Stepping in a frame stops after this much wall time, so that a seek across a long session (or
// 8x on a slow machine) still answers the mouse; the playhead then waits for the cursor.
constexpr double kStepBudgetS = 0.025;
// Steps between two looks at the clock and two drains of the edit channel.
constexpr size_t kStepChunk = 32;

class ReplayViewer {
 public:
  ReplayViewer(const SessionRecording& session, ToothVolume& tooth, const ReplayViewerOptions& options)
      : session_(session),
        tooth_(tooth),
        o_(options),
        box_(firstViewBox(tooth.voxels, tooth.frame)),
        shots_(options.out.empty() ? std::vector<double>{} : options.shots_s, 0.0),
        input_(camera_, box_, WindowInput::Hooks{[](double) {}, [this] { quit_ = true; }, {}, {}}) {}

  Result<int> run(bool outputs_pending);

 private:
  Status setUp();
  Status frame();
  void seek(double t_s);
  size_t goal() const;  // the step the playhead stands at
  void playUpTo(size_t target);
  void drainEdits();
  render::FrameState frameState(VkExtent2D extent) const;
  Status writeScreenshot(const std::string& stem, const RgbImage& picture, const render::FrameState& drawn);
  void reachedEnd();  // the files written (at_end) the first time the last step has played

  const SessionRecording& session_;
  ToothVolume& tooth_;
  ReplayViewerOptions o_;
  TissueBox box_;
  ShotSchedule shots_;                // --shot's pictures in o_.out, each the first time the playhead reaches it
  render::OrbitCamera camera_;
  WindowInput input_;
  EditChannel edits_;
  std::unique_ptr<ReplayCursor> cursor_;
  std::unique_ptr<FramePainter> own_painter_;  // the replay's own window; none inside a run (o_.host)
  FramePainter* painter_ = nullptr;   // the one drawn with: its own, or the host run's
  std::optional<GhostDriver> ghost_;  // the professional beside the replay (o_.ghost)
  ToothVolume window_tooth_;          // the window's copy of the tooth, fed by the edit channel
  std::vector<uint64_t> batch_;
  std::vector<BrickCoord> dirty_;     // bricks to re-mesh before the next frame is drawn
  ui::ReplayPanelState panel_;
  PixelRect panel_rect_;
  double playhead_s_ = 0.0;           // where the replay should be [s of loop time]
  SceneContents scene_;               // the tooth's frame and looks, the bur, the mirror
  Clock::time_point last_frame_;
  bool quit_ = false;
  bool ended_ = false;                // at_end has run
  bool seeking_ = false;              // a seek's target is not reached yet
  bool seek_done_ = false, shot_done_ = false;
  int exit_code_ = 0;
};

Status ReplayViewer::setUp() {
  ReplayCursorOptions co;
  co.allow_other_tooth = o_.allow_other_tooth;
  co.edits = &edits_;
  auto cursor = ReplayCursor::open(session_, tooth_, co);
  if (!cursor) return cursor.error();
  cursor_ = std::move(*cursor);
  window_tooth_ = cursor_->start();
  if (box_.empty()) return makeError(o_.title, "the tooth holds no tissue");
  scene_.tooth_frame = window_tooth_.frame;
  scene_.looks = defaultLookParams().looks;
  scene_.bur = session_.info.drill_tool;
  scene_.mirror_tool = !session_.info.mirror_tool.empty();
  if (auto params = parseSimParams(session_.info.params_json, "session parameters")) scene_.max_force_n = params->device.max_force_n;

  // The simulator's own first view (buccal from the chair), so the replay opens on what the student saw.
  FirstView first;
  first.mirror = !session_.info.mirror_tool.empty();
  placeFirstView(camera_, box_, first);

  if (o_.host) {
    // Inside a run: its window, and the view as the student left it (its mouse keeps steering it).
    painter_ = o_.host->painter;
    camera_ = *o_.host->camera;
    panel_.back_shown = true;
  } else {
    PainterOptions po;
    po.width = o_.width;
    po.height = o_.height;
    po.device = o_.device;
    auto painter = FramePainter::create(po, [this](ui::Window& w) { input_.attach(w); });
    if (!painter) return painter.error();
    own_painter_ = std::move(*painter);
    painter_ = own_painter_.get();
    input_.setPanel(painter_->panel());
  }
  if (Status st = painter_->surfaces().build(window_tooth_.voxels); !st) return st;
  if (!o_.ghost.empty()) {
    auto params = parseSimParams(session_.info.params_json, "session parameters");
    const PointShellParams spacing = params ? params->point_shell : defaultSimParams().point_shell;
    auto ghost = GhostDriver::load(o_.ghost, spacing, window_tooth_);
    if (!ghost) return ghost.error();
    for (const std::string& w : ghost->warnings()) warn(w);
    ghost_ = std::move(*ghost);
  }

  panel_.title = o_.title;
  panel_.playing = true;
  panel_.speed_index = ui::replaySpeedIndex(o_.speed).value_or(2);
  panel_.duration_s = cursor_->duration();
  panel_.steps = cursor_->steps();
  panel_.threshold_n = o_.force_threshold_n;
  // On stderr, so that stdout stays the one JSON object under --json.
  std::fprintf(stderr, "replaying %s in a window: %zu steps (%s); %s\n", o_.title.c_str(), cursor_->size(),
               ui::replayClock(cursor_->duration()).c_str(), painter_->context().device().name.c_str());
  return Ok{};
}

void ReplayViewer::drainEdits() {
  batch_.clear();
  edits_.drain(&batch_);
  if (!batch_.empty()) applyVoxelEdits(window_tooth_.voxels, batch_, &dirty_);
}

void ReplayViewer::playUpTo(size_t target) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kStepBudgetS));
  // In lockstep every frame plays all the way to its playhead: its picture never depends on the machine.
  while (cursor_->position() < target && (o_.lockstep || Clock::now() < deadline)) {
    cursor_->stepTo(target, kStepChunk);
    drainEdits();
  }
}

size_t ReplayViewer::goal() const {
  return std::min(cursor_->size(), size_t(std::floor(playhead_s_ * cursor_->rateHz() + 1e-9)));
}

void ReplayViewer::seek(double t_s) {
  playhead_s_ = std::clamp(t_s, 0.0, cursor_->duration());
  seeking_ = true;
  if (goal() >= cursor_->position()) return;  // forward: the frames play on to it
  // Back: the cut so far cannot be undone, so the replay starts again from the starting tooth.
  // Edits still in the channel belong to the cut being dropped.
  batch_.clear();
  edits_.drain(&batch_);
  cursor_->restart();
  window_tooth_ = cursor_->start();
  dirty_.clear();
  if (Status st = painter_->surfaces().build(window_tooth_.voxels); !st)
    warn("re-meshing the starting tooth: " + st.message());
}

void ReplayViewer::reachedEnd() {
  ended_ = true;
  const ReplayOutcome outcome = cursor_->outcome();
  if (o_.at_end) {
    ToothVolume final_tooth = tooth_;
    exit_code_ = o_.at_end(outcome, final_tooth);
  }
  panel_.status = "played to the end: " + std::to_string(outcome.steps) + " steps, final volume " + outcome.final_hash +
                  (session_.end ? (outcome.recorded_hash_matches ? " (the recording's)" : " (NOT the recording's)") : "");
  if (o_.exit_at_end) quit_ = true;
}

render::FrameState ReplayViewer::frameState(VkExtent2D extent) const {
  // The panel covers the bottom: the view's centre moves up into the rest of the window.
  render::FrameState fs = sceneFrameState(camera_, extent, 0.0f, 0.5f * float(panel_rect_.height), cursor_->loop().latest(), scene_);
  if (ghost_) poseGhost(*ghost_, o_.ghost_opacity, fs);
  return fs;
}

Status ReplayViewer::frame() {
  ui::Window::pollEvents();
  if (painter_->window()->closeRequested()) quit_ = true;
  if (o_.host) {
    if (o_.host->quit && o_.host->quit()) quit_ = true;
    camera_ = *o_.host->camera;  // the run's mouse and keys turn the view
  }
  const Clock::time_point now = Clock::now();
  const double dt = o_.lockstep ? 1.0 / o_.fps : std::min(0.1, std::chrono::duration<double>(now - last_frame_).count());
  last_frame_ = now;

  // The playhead moves with the wall clock, but never more than a quarter second of wall time ahead
  // of what the cursor has played: a slow machine plays slower rather than in jumps. A seek's
  // target stays put until the cursor has got there.
  const double speed = ui::kReplaySpeeds[size_t(panel_.speed_index)];
  if (panel_.playing && !seeking_)
    playhead_s_ = std::min({playhead_s_ + dt * speed, cursor_->time() + 0.25 * speed, cursor_->duration()});
  playUpTo(goal());
  if (ghost_) ghost_->followTime(cursor_->time());  // the professional at the same task time
  if (o_.seek_at && !seek_done_ && cursor_->time() >= o_.seek_at->from_s - 1e-9) {
    seek_done_ = true;
    std::printf("seek from %s to %s\n", ui::replayClock(cursor_->time()).c_str(), ui::replayClock(o_.seek_at->to_s).c_str());
    std::fflush(stdout);
    seek(o_.seek_at->to_s);
    playUpTo(goal());
  }
  if (seeking_ && cursor_->position() >= goal()) seeking_ = false;
  if (cursor_->atEnd() && !ended_) reachedEnd();
  if (cursor_->atEnd()) panel_.playing = false;
  if (!dirty_.empty())
    if (Status st = painter_->remesh(window_tooth_.voxels, &dirty_); !st) return st;

  // The panel, then the scene under it.
  panel_.time_s = cursor_->time();
  ui::ReplayPanelActions actions;
  const VkExtent2D e = painter_->extent();
  if (ui::ImGuiLayer* panel = painter_->panel()) {
    panel->newFrame(int(e.width), int(e.height), dt);
    actions = ui::drawReplayPanel(panel_);
    panel_rect_ = actions.panel_rect;
  }
  const bool shot = !shot_done_ && o_.shot_at_s >= 0 && !o_.shot_png.empty() && cursor_->time() >= o_.shot_at_s - 1e-9;
  const ShotSchedule::Due due = shots_.at(cursor_->time());
  render::FrameState drawn;
  auto picture = painter_->draw(
      [&](VkExtent2D extent) {
        drawn = frameState(extent);
        return drawn;
      },
      shot || !due.shot_stem.empty());
  if (!picture) return picture.error();
  if (shot && *picture) {
    shot_done_ = true;
    if (Status st = writePng(o_.shot_png, **picture); !st) return st;
    std::printf("wrote %s\n", o_.shot_png.c_str());
  }
  if (!due.shot_stem.empty() && *picture)
    if (Status st = writeScreenshot(due.shot_stem, **picture, drawn); !st) return st;

  // What the panel asked for.
  if (actions.speed_changed) std::printf("speed %gx\n", ui::kReplaySpeeds[size_t(panel_.speed_index)]);
  if (actions.toggle_play) {
    panel_.playing = !panel_.playing;
    if (panel_.playing && cursor_->atEnd()) seek(0.0);  // Play at the end plays it again
  }
  if (actions.seek_s) seek(*actions.seek_s);
  if (actions.back) quit_ = true;  // inside a run: back to it
  return Ok{};
}

Status ReplayViewer::writeScreenshot(const std::string& stem, const RgbImage& picture, const render::FrameState& drawn) {
  ShotFacts facts;
  facts.loop_time_s = cursor_->time();
  facts.windowed = true;
  facts.tooth_centre = box_.centre();
  facts.panel_shown = painter_->panel() != nullptr;
  facts.panel_rect = panel_rect_;
  facts.tooth_top_mm = box_.hi.z;
  const std::string path = (std::filesystem::path(o_.out) / stem).string();
  if (Status st = writeShot(path, picture, camera_, drawn, facts); !st) return st;
  std::printf("wrote %s.png\n", path.c_str());
  return Ok{};
}

Result<int> ReplayViewer::run(bool outputs_pending) {
  if (Status st = setUp(); !st) return st.error();
  last_frame_ = Clock::now();
  Status result = Ok{};
  while (result && !quit_) result = frame();
  (void)painter_->context().waitIdle();  // teardown: a failure here changes nothing the user keeps
  if (!result) return result.error();
  // With validation on (DENTSIM_VALIDATION=1, as in the tests), any error fails the replay.
  if (Status st = painter_->context().validationStatus(); !st) return st.error();
  if (!ended_ && o_.host) {
    std::printf("review: back to the run at %s of %s\n", ui::replayClock(cursor_->time()).c_str(),
                ui::replayClock(cursor_->duration()).c_str());
  } else if (!ended_) {
    std::printf("the window closed at %s of %s, before the end\n", ui::replayClock(cursor_->time()).c_str(),
                ui::replayClock(cursor_->duration()).c_str());
    if (outputs_pending) return makeError(o_.title, "the window closed before the replay's end: its files were not written");
  }
  return exit_code_;
}

}  // namespace

Result<int> runReplayViewer(const SessionRecording& session, ToothVolume& tooth, const ReplayViewerOptions& options,
                            bool outputs_pending) {
  ReplayViewer viewer(session, tooth, options);
  return viewer.run(outputs_pending);
}

}  // namespace dentsim::app
