// The simulator's frame loop: set-up of tooth, tools, pens, GPU, window and panel; segments; input; frames, screenshots and the score screen.
//
// Contents
//   1. Placement: where the pens start and where the demo holds the mirror
//   2. Simulator: the state of one run
//   3. Segments: a haptic loop and its recording, from Start to Stop
//   4. Input: the window's mouse and keys (virtual pens, camera, turbine)
//   5. One frame: edits, re-mesh, panel, draw, screenshots, present
//   6. runSimulator
#include "app/simulator.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>
#include <tuple>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "app/session_support.h"
#include "eval/cut_score.h"
#include "audio/sound_engine.h"
#include "audio/sound_feed.h"
#include "devices/device_pen.h"
#include "devices/device_registry.h"
#include "devices/software_pen.h"
#include "devices/virtual_pen.h"
#include "gpu/compute.h"
#include "gpu/context.h"
#include "io/atomic_file.h"
#include "io/png_file.h"
#include "render/camera.h"
#include "render/offscreen.h"
#include "render/scene_renderer.h"
#include "render/swapchain.h"
#include "render/tooth_surfaces.h"
#include "sim/builtin_tooth.h"
#include "sim/edit_channel.h"
#include "sim/haptic_loop.h"
#include "sim/pen.h"
#include "sim/novice_paths.h"
#include "sim/scripted_paths.h"
#include "sim/session_recorder.h"
#include "sim/session_run.h"
#include "sim/tool_library.h"
#include "ui/imgui_layer.h"
#include "ui/param_panel.h"
#include "ui/preset_store.h"
#include "ui/pen_input.h"
#include "ui/window.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr double kPi = 3.14159265358979323846;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// ---- 1. placement ---------------------------------------------------------------------------------------

// The drill's grip with the bur upright (tip down, axis +Z) and its tip `above_mm` over the crown's centre.
Pose drillStartGrip(const TissueBox& box, double above_mm) {
  const Vec3 c = box.centre();
  Pose p;
  p.position = Vec3{c.x, c.y, box.hi.z + above_mm} + kBurGripLocal;
  return p;
}

// The rotation whose columns are the unit, right-handed axes x, y, z (Shepperd's method: the largest
// of the four candidate divisors keeps it accurate for any rotation).
Quat quatFromAxes(const Vec3& x, const Vec3& y, const Vec3& z) {
  const double m00 = x.x, m11 = y.y, m22 = z.z;
  const double trace = m00 + m11 + m22;
  Quat q;
  if (trace > 0) {
    const double s = 2.0 * std::sqrt(1.0 + trace);
    q = {0.25 * s, (y.z - z.y) / s, (z.x - x.z) / s, (x.y - y.x) / s};
  } else if (m00 > m11 && m00 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m00 - m11 - m22);
    q = {(y.z - z.y) / s, 0.25 * s, (y.x + x.y) / s, (z.x + x.z) / s};
  } else if (m11 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m11 - m00 - m22);
    q = {(z.x - x.z) / s, (y.x + x.y) / s, 0.25 * s, (z.y + y.z) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + m22 - m00 - m11);
    q = {(x.y - y.x) / s, (z.x + x.z) / s, (z.y + y.z) / s, 0.25 * s};
  }
  return q.normalized();
}

// Where the demo (and a virtual mirror at start) holds the mirror: beside the crown's distal side,
// a little lingual, turned the way a dentist turns it: its normal halves the angle between the eye
// and the crown, so the eye sees the crown's distal and lingual surfaces in it. The handle (-X)
// leaves away from the tooth. Returns the grip frame.
Pose mirrorGrip(const TissueBox& box, const Vec3& eye) {
  const Vec3 c = box.centre();
  const Vec3 crown{c.x, c.y, box.hi.z - 2.5};
  const Vec3 face{box.hi.x + 7.0, c.y + 4.0, box.hi.z - 1.0};
  const Vec3 z = normalized(normalized(eye - face) + normalized(crown - face));
  const Vec3 to_tooth = crown - face;
  const Vec3 x = normalized(to_tooth - z * dot(to_tooth, z));
  const Vec3 y = cross(z, x);
  Pose p;
  p.rotation = quatFromAxes(x, y, z);
  p.position = face + p.rotation.rotate(kMirrorGripLocal);
  return p;
}

// Mirror samples for a scripted path that has none: held still at mirrorGrip for the whole path.
void addStillMirror(PenPath& path, const Pose& grip) {
  double end_s = 0.0;
  for (const PenSample& s : path.samples) end_s = std::max(end_s, s.t_s);
  for (double t : {0.0, end_s}) {
    PenSample s;
    s.t_s = t;
    s.pen = PenRole::Mirror;
    s.pose = grip;
    path.samples.push_back(s);
  }
  std::stable_sort(path.samples.begin(), path.samples.end(), [](const PenSample& a, const PenSample& b) { return a.t_s < b.t_s; });
}

double pathEnd(const PenPath& path) {
  double end_s = 0.0;
  for (const PenSample& s : path.samples) end_s = std::max(end_s, s.t_s);
  return end_s;
}

// ---- 2. the simulator's state ------------------------------------------------------------------------------

// A recorded stretch of drilling: its loop and, with an output folder, its session file.
struct Segment {
  int index = 0;                      // 1, 2, ...
  std::unique_ptr<HapticLoop> loop;
  std::unique_ptr<SessionRecorder> recorder;
  std::string session_path;
};

class Simulator {
 public:
  explicit Simulator(const SimulatorOptions& o) : o_(o) {}
  Result<SimulatorOutcome> run();

  // Input (section 4): GLFW calls these through the window's user pointer.
  void onMouseButton(int button, int action, int mods);
  void onCursor(double x, double y);
  void onScroll(double dx, double dy);
  void onKey(int key, int action, int mods);

 private:
  Status setUp();
  Status loadTooth();
  Status loadDrill();
  Status startSegment();
  Status setUpPens();
  Status setUpSound();
  void updateSound(const HapticState& state);
  void enableDevices();
  void serviceDevices();
  void closeDevices();
  Status endSegment(const std::string& reason);
  Status frame();
  Status handleActions(ui::PanelActions& actions);
  Status scoreNow();
  render::FrameState frameState(const HapticState& state, VkExtent2D extent) const;
  Status writeShot(const RgbImage& image, const std::string& stem, const render::FrameState& fs, VkExtent2D extent);
  Status drawFrame(bool shot_due, const std::string& shot_stem, bool frame_due, const std::string& frame_stem);
  // Pixels the scene moves left so that its centre is the middle of what the panel leaves free.
  int sceneShiftPx() const { return imgui_ ? panel_rect_[2] / 2 : 0; }
  std::string outPath(const std::string& name) const { return (fs::path(o_.out) / name).string(); }
  double loopTime() const;
  // Steps the current segment's loop has run. While its thread runs, only the thread's atomic
  // counter may be read from here; in lockstep this thread steps it itself.
  uint64_t segmentSteps() const {
    return lockstep_ ? segment_.loop->stepsRun() : segment_.loop->counters().steps.load(std::memory_order_relaxed);
  }
  void note(const std::string& text);

  SimulatorOptions o_;
  SimulatorOutcome out_;
  bool headless_ = false;
  bool lockstep_ = false;

  // Tooth: the haptic loop's copy (cut), the frame loop's copy (view, fed by the edits), the start.
  ToothVolume initial_, cut_, view_;
  TissueBox box_;
  std::optional<Task> task_;
  SimParams params_;
  std::optional<ToolModel> drill_tool_, mirror_tool_;
  std::string drill_name_;

  // Pens: a device each (the virtual pen, a script's, hardware) seen by the loop through a
  // DevicePen; the pedal; the mouse and keys for the virtual ones.
  std::optional<PenPath> script_;
  std::array<std::unique_ptr<devices::HapticDevice>, 2> devices_;
  std::array<std::unique_ptr<devices::DevicePen>, 2> pens_;
  std::array<devices::VirtualPen*, 2> virtual_{};  // into devices_, where a pen is virtual
  std::array<devices::DeviceState, 2> shown_state_{};
  std::unique_ptr<devices::FootPedal> pedal_;
  devices::DeviceState shown_pedal_state_ = devices::DeviceState::Disconnected;
  std::unique_ptr<ui::PenInput> input_;
  double script_end_s_ = 0.0;

  // Sound: live, offline to a file, or none.
  std::unique_ptr<audio::SoundEngine> sound_;
  audio::SoundFeed sound_feed_;

  EditChannel edits_;
  std::vector<uint64_t> batch_;
  Segment segment_;
  HapticState last_state_;    // what the last segment ended on: drawn while stopped
  int segments_ = 0;
  uint64_t steps_done_ = 0;   // steps of finished segments
  double segment_t0_ = 0.0;   // loop time shown at the current segment's start [s]

  // GPU and window.
  std::optional<gpu::Context> ctx_;
  std::unique_ptr<ui::Window> window_;
  std::unique_ptr<render::Swapchain> swapchain_;
  std::optional<render::OffscreenTarget> offscreen_;
  std::optional<render::SceneRenderer> renderer_;
  std::optional<render::ToothSurfaces> surfaces_;
  std::optional<ui::ImGuiLayer> imgui_;
  render::OrbitCamera camera_;

  // Panel.
  ui::UiState ui_;
  std::unique_ptr<ui::PresetStore> presets_;
  ui::PanelActions last_actions_;
  bool score_shown_ = false;
  std::array<int, 4> panel_rect_{0, 0, 0, 0};  // the parameter window's x, y, width, height [px]

  // Input state.
  bool dragging_pen_ = false, orbiting_ = false, panning_ = false;
  double cursor_x_ = 0, cursor_y_ = 0;
  bool quit_ = false;

  // Timing.
  Clock::time_point run_t0_;
  Clock::time_point last_frame_;
  std::vector<double> frame_ms_;
  double remesh_sum_ms_ = 0.0;
  uint64_t remesh_count_ = 0;
  uint64_t rate_steps_ = 0;
  Clock::time_point rate_t0_;
  Clock::time_point haptic_t0_;  // the first segment's start
  size_t next_shot_ = 0;
  bool final_shot_due_ = false;
  bool quit_after_final_ = false;
  std::vector<BrickCoord> pending_dirty_;  // edited bricks not yet re-meshed
  double next_frame_s_ = 0.0;
  int frames_written_ = 0;
};

void Simulator::note(const std::string& text) {
  std::printf("%s\n", text.c_str());
  ui_.status = text;
}

double Simulator::loopTime() const {
  if (!segment_.loop) return segment_t0_;
  return segment_t0_ + double(segmentSteps()) / params_.device.rate_hz;
}

// ---- 3. set-up and segments -----------------------------------------------------------------------------

Status Simulator::loadTooth() {
  if (!o_.tooth.empty()) {
    auto t = dentsim::loadTooth(o_.tooth);
    if (!t) return t.error();
    initial_ = std::move(*t);
  } else {
    auto t = builtinMolarTooth(o_.level);
    if (!t) return t.error();
    initial_ = std::move(*t);
  }
  box_ = tissueBox(initial_.voxels, initial_.frame);
  if (box_.empty()) return makeError(o_.tooth.empty() ? "built-in molar" : o_.tooth, "the tooth holds no tissue");
  cut_ = initial_;
  view_ = initial_;
  return Ok{};
}

Status Simulator::loadDrill() {
  auto d = loadToolModel(drill_name_, params_.point_shell);
  if (!d) return d.error();
  drill_tool_ = std::move(*d);
  return Ok{};
}

Status Simulator::startSegment() {
  segment_ = Segment{};
  segment_.index = ++segments_;
  // The starting tooth is saved first: saving compacts the volume, which would drop the spare
  // bricks the loop reserves for cutting.
  const std::string suffix = segment_.index == 1 ? "" : "-" + std::to_string(segment_.index);
  const std::string tooth_name = "initial" + suffix + ".dvol";
  if (!o_.out.empty()) {
    if (Status st = saveTooth(outPath(tooth_name), cut_); !st) return st;
    out_.written.push_back(outPath(tooth_name));
  }
  segment_.loop = std::make_unique<HapticLoop>(cut_.voxels, cut_.frame, params_, *drill_tool_,
                                               mirror_tool_ ? &*mirror_tool_ : nullptr, &edits_);
  HapticLoop& loop = *segment_.loop;
  loop.setIdleLatencyUs(o_.idle_latency_us);
  for (PenRole role : {PenRole::Drill, PenRole::Mirror}) {
    if (role == PenRole::Mirror && !mirror_tool_) continue;
    PenSource* pen = pens_[size_t(role)].get();
    if (!pen) continue;
    loop.attach(role, pen);
    // A new loop's time starts at 0, and a session's proxies start on the reading its first step
    // consumes, which is what replay assumes.
    PenReading first;
    if (pen->read(0.0, &first)) loop.placeTool(role, first.grip);
  }
  if (!o_.out.empty()) {
    SessionInfo info;
    info.created_utc = utcNow();
    info.program = std::string("dentsim ") + DENTSIM_VERSION;
    info.task = task_ ? task_->name : "";
    info.tooth_file = tooth_name;
    info.tooth_source = o_.tooth.empty() ? builtinToothSource(o_.level) : o_.tooth;
    info = sessionHeader(std::move(info), cut_, params_, drill_name_, mirror_tool_ ? o_.mirror_tool : "");
    segment_.session_path = outPath("session" + suffix + ".dses");
    segment_.recorder = std::make_unique<SessionRecorder>();
    if (Status st = segment_.recorder->start(loop, segment_.session_path, info); !st) return st;
  }
  if (!lockstep_)
    if (Status st = loop.start(); !st) return st;
  // Forces may go out only now that the loop commands them every step (the watchdog counts from here).
  enableDevices();
  rate_steps_ = steps_done_;
  rate_t0_ = Clock::now();
  if (segments_ == 1) haptic_t0_ = rate_t0_;
  ui_.run_state = ui::RunState::Running;
  return Ok{};
}

Status Simulator::endSegment(const std::string& reason) {
  if (!segment_.loop) return Ok{};
  HapticLoop& loop = *segment_.loop;
  // Zero force before the loop stops commanding it (else every pen would latch a watchdog fault).
  for (auto& d : devices_)
    if (d) d->disable();
  loop.stop();
  segment_t0_ = loopTime();
  steps_done_ += loop.stepsRun();
  // Stopped, the tools stay where they were, at rest.
  last_state_ = loop.latest();
  for (ToolState& t : last_state_.tools) t.display = Wrench{};
  last_state_.pedal = 0.0;
  out_.removed_mm3 += loop.latest().removed_mm3;
  Status result = Ok{};
  if (segment_.recorder) {
    const SessionEnd end{loop.stepsRun(), volumeHashHex(cut_.voxels, cut_.frame), reason};
    if (Status st = segment_.recorder->finish(end); !st) result = st;
    else out_.written.push_back(segment_.session_path);
  }
  // The loop's last edits reach the frame loop's copy before the loop goes.
  batch_.clear();
  edits_.drain(&batch_);
  if (!batch_.empty()) applyVoxelEdits(view_.voxels, batch_, &pending_dirty_);
  if (surfaces_ && !pending_dirty_.empty()) {
    if (Status st = surfaces_->update(view_.voxels, pending_dirty_); !st && result) result = st;
    pending_dirty_.clear();
  }
  segment_ = Segment{};
  ui_.run_state = ui::RunState::Stopped;
  return result;
}

// ---- pens and pedal ----------------------------------------------------------------------------------------

Status Simulator::setUpPens() {
  const Pose drill_start = drillStartGrip(box_, 3.0);
  const Pose mirror_start = mirrorGrip(box_, render::fromGlm(camera_.eye()));
  const bool scripted = !o_.pen_script.empty() || o_.demo_script;
  if (scripted) {
    if (o_.demo_script) {
      // The task's own preparation, as the careful dentist does it or with one fault.
      const std::optional<Attempt> attempt = parseAttempt(o_.attempt);
      if (!attempt) return makeError("--attempt", "\"" + o_.attempt + "\" is not one of " + attemptNames());
      CavityPathSettings cavity;
      if (const std::optional<double> r = burHeadRadiusMm(drill_name_)) cavity.bur_radius_mm = *r;
      auto path = task_->kind == TaskKind::Caries
                      ? cariesAttemptPath(*attempt, initial_.voxels, initial_.frame, params_, drill_name_)
                      : cavityAttemptPath(*attempt, initial_.voxels, initial_.frame, cavity);
      if (!path) return path.error();
      script_ = std::move(*path);
    } else {
      auto path = loadPenPath(o_.pen_script);
      if (!path) return path.error();
      script_ = std::move(*path);
    }
    if (mirror_tool_ && !hasPen(*script_, PenRole::Mirror)) addStillMirror(*script_, mirror_start);
    script_end_s_ = pathEnd(*script_);
  }
  // The pedal first: the drill's pen reads it.
  if (!o_.pedal.empty() && o_.pedal != "none") {
    auto pedal = devices::makePedal(o_.pedal);
    if (!pedal) return makeError("pedal", pedal.message());
    pedal_ = std::move(*pedal);
    if (Status st = pedal_->open(); !st) return makeError("pedal", st.message());
    shown_pedal_state_ = pedal_->state();
  }
  // Hardware pens map their workspace around the tool's start, turned with the camera.
  const render::CameraBasis basis = camera_.basis();
  const Quat screen = quatFromAxes(render::fromGlm(basis.right), render::fromGlm(basis.up), -render::fromGlm(basis.forward));
  bool physical = false;
  for (PenRole role : {PenRole::Drill, PenRole::Mirror}) {
    if (role == PenRole::Mirror && !mirror_tool_) continue;
    const size_t r = size_t(role);
    const std::string& chosen = role == PenRole::Drill ? o_.drill_pen : o_.mirror_pen;
    const std::string where = std::string(penRoleName(role)) + " pen";
    const Pose& start = role == PenRole::Drill ? drill_start : mirror_start;
    if (chosen.empty() && scripted) {
      devices_[r] = std::make_unique<devices::SoftwarePen>(
          "script", std::make_unique<ScriptedPen>(*script_, role),
          devices::softwarePenSpec("pen script", params_.device.max_force_n, params_.device.max_torque_n_mm));
    } else {
      auto name = devices::parsePenName(chosen.empty() ? "virtual" : chosen);
      if (!name) return makeError(where, name.message());
      devices::PenContext pc;
      pc.role = role;
      pc.start_grip = start;
      pc.max_force_n = params_.device.max_force_n;
      pc.max_torque_n_mm = params_.device.max_torque_n_mm;
      pc.falcon.firmware_path = o_.falcon_firmware;
      auto made = devices::makePen(*name, pc);
      if (!made) return makeError(where, made.message());
      devices_[r] = std::move(*made);
    }
    devices::HapticDevice& device = *devices_[r];
    if (Status st = device.open(); !st) return makeError(where, st.message());
    shown_state_[r] = device.state();
    if (device.state() != devices::DeviceState::Ready)
      note(where + " " + device.name() + ": " + devices::stateName(device.state()) + " (" + device.reason() + ")");
    physical = physical || device.spec().physical;
    if (auto* sw = dynamic_cast<devices::SoftwarePen*>(&device)) virtual_[r] = dynamic_cast<devices::VirtualPen*>(&sw->source());
    pens_[r] = std::make_unique<devices::DevicePen>(device, devices::mapWorkspace(device.spec(), start, o_.reach_mm, screen),
                                                    role == PenRole::Drill ? pedal_.get() : nullptr);
  }
  if (physical) {
    if (lockstep_)
      return makeError("run", "a hardware pen needs the real-time haptic thread: drop --headless and --lockstep");
    // Ctrl-C and friends zero every pen at once; the frame loop then ends the run cleanly.
    devices::installDeviceSignalHandlers();
  }
  if (virtual_[0] || virtual_[1]) {
    input_ = std::make_unique<ui::PenInput>(camera_, virtual_[0], virtual_[1]);
    input_->reset(PenRole::Drill, drill_start);
    if (mirror_tool_) input_->reset(PenRole::Mirror, mirror_start);
  }
  return Ok{};
}

void Simulator::enableDevices() {
  for (size_t r = 0; r < devices_.size(); ++r) {
    devices::HapticDevice* d = devices_[r].get();
    if (!d) continue;
    if (d->state() == devices::DeviceState::Fault) d->disable();  // a watchdog fault clears on a new segment
    if (d->state() != devices::DeviceState::Ready) continue;
    if (Status st = d->enable(); !st) note(st.message());
  }
}

void Simulator::serviceDevices() {
  if (devices::allDevicesZeroRequested() && !quit_) {
    note("dentsim: stopping on a signal; every pen's force is zero");
    quit_ = true;
  }
  for (size_t r = 0; r < devices_.size(); ++r) {
    devices::HapticDevice* d = devices_[r].get();
    if (!d) continue;
    d->service();
    // A pen back from an unplug (replugged and homed) takes force again while the loop runs.
    if (segment_.loop && d->state() == devices::DeviceState::Ready)
      if (Status st = d->enable(); !st) note(st.message());
    const devices::DeviceState now = d->state();
    // Ready and Enabled are the usual states; a pen leaving them or coming back is news.
    if (now != shown_state_[r] && !(devices::tracking(now) && devices::tracking(shown_state_[r]))) {
      const std::string why = d->reason();
      note(std::string(penRoleName(PenRole(r))) + " pen " + d->name() + ": " + devices::stateName(now) +
           (why.empty() ? "" : " (" + why + ")"));
    }
    shown_state_[r] = now;
  }
  if (pedal_) {
    pedal_->service();
    if (pedal_->state() != shown_pedal_state_) {
      shown_pedal_state_ = pedal_->state();
      const std::string why = pedal_->reason();
      note("pedal " + pedal_->name() + ": " + devices::stateName(shown_pedal_state_) + (why.empty() ? "" : " (" + why + ")"));
    }
  }
}

void Simulator::closeDevices() {
  for (auto& d : devices_)
    if (d) d->close();
  if (pedal_) pedal_->close();
}

Status Simulator::setUpSound() {
  if (!o_.sound || (headless_ && o_.audio_out.empty())) {
    ui_.sound.output = "no sound";
    return Ok{};
  }
  audio::EngineOptions eo;
  eo.audio_out = o_.audio_out;
  eo.turbine_wav = o_.turbine_wav;
  eo.cutting_wav = o_.cutting_wav;
  eo.recorded_rpm = o_.recorded_rpm;
  auto engine = audio::SoundEngine::create(eo);
  if (!engine) return makeError("sound", engine.message());
  sound_ = std::move(*engine);
  if (sound_->silent()) {
    note("dentsim: " + sound_->notice());
    ui_.sound.output = sound_->notice();
  } else {
    ui_.sound.output = sound_->offline() ? "writing " + fs::path(o_.audio_out).filename().string() : "OpenAL Soft";
  }
  return Ok{};
}

// The sound follows the frame: the listener at the camera, the sources at the handpiece.
void Simulator::updateSound(const HapticState& state) {
  if (!sound_) return;
  const render::CameraBasis basis = camera_.basis();
  sound_->setListener(render::fromGlm(camera_.eye()), render::fromGlm(basis.forward), render::fromGlm(basis.up));
  sound_->setVolume(ui_.sound.volume);
  sound_->setMute(ui_.sound.mute);
  const ToolState& drill = state.tools[size_t(PenRole::Drill)];
  sound_->update(sound_feed_.next(state, drill.tool.apply(kBurGripLocal)));
}

Status Simulator::setUp() {
  // Window or not: a display that does not answer means headless, with a notice.
  headless_ = o_.headless;
  if (!headless_) {
    if (std::string why = ui::whyNoDisplay(); !why.empty()) {
      std::printf("dentsim: %s: running headless\n", why.c_str());
      headless_ = true;
    }
  }
  lockstep_ = headless_ || o_.lockstep;
  if (headless_ && o_.exit_after_s <= 0 && o_.pen_script.empty() && !o_.demo_script)
    return makeError("run", "headless with the mouse as the pen would never end: give --exit-after or a pen script");
  if (!(o_.fps > 0)) return makeError("run", "--fps must be > 0");

  // Names are checked before anything loads, so a mistyped pen or pedal fails at once.
  for (const std::string* pen : {&o_.drill_pen, &o_.mirror_pen}) {
    if (pen->empty() || (pen == &o_.mirror_pen && *pen == "none")) continue;
    if (auto name = devices::parsePenName(*pen); !name)
      return makeError(pen == &o_.drill_pen ? "drill pen" : "mirror pen", name.message());
  }
  if (Status st = devices::checkPedalName(o_.pedal); !st) return makeError("pedal", st.message());

  params_ = defaultSimParams();
  if (!o_.params.empty()) {
    auto p = loadSimParams(o_.params);
    if (!p) return p.error();
    params_ = std::move(*p);
  }
  auto task = builtinTask(o_.task);
  if (!task) return task.error();
  task_ = std::move(*task);
  drill_name_ = o_.bur.empty() ? task_->drill_tool : o_.bur;
  if (Status st = loadTooth(); !st) return st;
  if (Status st = loadDrill(); !st) return st;
  if (!o_.mirror_tool.empty() && o_.mirror_pen != "none") {
    auto m = loadToolModel(o_.mirror_tool, params_.point_shell);
    if (!m) return m.error();
    mirror_tool_ = std::move(*m);
  }

  // Camera: the chosen side, raised 30 degrees (a side view from the chair looks down on the crown),
  // then widened to take in the mirror where the demo holds it.
  auto preset = render::parseViewPreset(o_.view);
  if (!preset) return preset.error();
  const Vec3 c = box_.centre();
  const double radius = 0.5 * norm(box_.hi - box_.lo);
  camera_.setView(*preset, render::toGlm(c), float(radius));
  if (*preset != render::ViewPreset::Occlusal) camera_.orbit(0.0f, 0.52f);
  if (mirror_tool_) {
    const Vec3 face = mirrorGrip(box_, render::fromGlm(camera_.eye())).apply(-kMirrorGripLocal);
    camera_.setTarget(render::toGlm((c + face) * 0.5));
    camera_.setDistance(camera_.distance() * float((radius + 0.5 * norm(face - c)) / radius) * 0.8f);
  }

  if (Status st = setUpPens(); !st) return st;
  if (Status st = setUpSound(); !st) return st;

  // Window, device, swapchain.
  gpu::ContextOptions co;
  co.graphics = true;
  co.device_override = o_.device;
  if (!headless_) {
    auto w = ui::Window::open(o_.width, o_.height, "dentsim");
    if (!w) return w.error();
    window_ = std::move(*w);
    co.instance_extensions = ui::Window::requiredInstanceExtensions();
  }
  auto ctx = gpu::Context::create(gpu::withEnvironment(co));
  if (!ctx) return ctx.error();
  ctx_ = std::move(*ctx);
  out_.device = ctx_->device().name;
  out_.windowed = !headless_;
  VkFormat format = VK_FORMAT_B8G8R8A8_UNORM;
  VkImageLayout final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  uint32_t image_count = 2;
  if (window_) {
    auto surface = window_->createSurface(ctx_->core().instance);
    if (!surface) return surface.error();
    render::SwapchainOptions so;
    so.vsync = o_.vsync;
    auto sc = render::Swapchain::create(*ctx_, *surface, window_->framebufferExtent(), so);
    if (!sc) return sc.error();
    swapchain_ = std::move(*sc);
    format = swapchain_->format();
    final_layout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    image_count = swapchain_->imageCount();
  } else {
    auto target = render::OffscreenTarget::create(*ctx_, uint32_t(o_.width), uint32_t(o_.height), format);
    if (!target) return target.error();
    offscreen_ = std::move(*target);
  }
  auto renderer = render::SceneRenderer::create(*ctx_, format, final_layout);
  if (!renderer) return renderer.error();
  renderer_ = std::move(*renderer);
  auto surfaces = render::ToothSurfaces::create(*ctx_, params_.view.normals);
  if (!surfaces) return surfaces.error();
  surfaces_ = std::move(*surfaces);
  gpu::SurfaceUpdateStats stats;
  if (Status st = surfaces_->build(view_.voxels, &stats); !st) return st;
  ui_.stats.triangles = stats.triangles;
  std::printf("tooth: %s, level %d, %.4f mm voxels; surface %llu triangles in %.1f ms on %s\n",
              o_.tooth.empty() ? "built-in molar" : o_.tooth.c_str(), initial_.frame.level, initial_.frame.voxel_mm,
              static_cast<unsigned long long>(stats.triangles), stats.total_ms, out_.device.c_str());

  // Input callbacks go in before the panel's, which chain to them (ui/imgui_layer.h).
  if (window_) {
    GLFWwindow* w = window_->handle();
    glfwSetWindowUserPointer(w, this);
    glfwSetMouseButtonCallback(w, [](GLFWwindow* win, int b, int a, int m) {
      static_cast<Simulator*>(glfwGetWindowUserPointer(win))->onMouseButton(b, a, m);
    });
    glfwSetCursorPosCallback(w, [](GLFWwindow* win, double x, double y) {
      static_cast<Simulator*>(glfwGetWindowUserPointer(win))->onCursor(x, y);
    });
    glfwSetScrollCallback(w, [](GLFWwindow* win, double dx, double dy) {
      static_cast<Simulator*>(glfwGetWindowUserPointer(win))->onScroll(dx, dy);
    });
    glfwSetKeyCallback(w, [](GLFWwindow* win, int key, int, int action, int mods) {
      static_cast<Simulator*>(glfwGetWindowUserPointer(win))->onKey(key, action, mods);
    });
  }
  if (o_.ui) {
    auto layer = ui::ImGuiLayer::create(*ctx_, renderer_->renderPass(), 0, image_count, window_ ? window_->handle() : nullptr);
    if (!layer) return layer.error();
    imgui_ = std::move(*layer);
  }

  // The panel's state.
  presets_ = std::make_unique<ui::PresetStore>(ui::defaultPresetDirectory());
  ui_.params = params_;
  ui_.bur = drill_name_;
  ui_.level = initial_.frame.level;
  ui_.task = o_.task;
  ui_.pedal_present = script_.has_value() || pedal_ != nullptr;
  ui_.presets = presets_->list();
  ui_.force.max_force_n = params_.device.max_force_n;

  if (!o_.out.empty()) {
    std::error_code ec;
    fs::create_directories(o_.out, ec);
    if (ec) return makeError(o_.out, "cannot create the output folder: " + ec.message());
  }
  std::sort(o_.shots_s.begin(), o_.shots_s.end());
  return startSegment();
}

// ---- 4. input ------------------------------------------------------------------------------------------

void Simulator::onMouseButton(int button, int action, int mods) {
  const bool down = action == GLFW_PRESS;
  if (down && imgui_ && imgui_->wantsMouse()) return;
  if (button == GLFW_MOUSE_BUTTON_LEFT) {
    dragging_pen_ = down && input_ != nullptr;
    // Shift holds the mirror: the drill hand and the mirror hand take turns on one mouse.
    if (input_ && down) input_->setActive((mods & GLFW_MOD_SHIFT) ? PenRole::Mirror : PenRole::Drill);
  } else if (button == GLFW_MOUSE_BUTTON_RIGHT) {
    orbiting_ = down;
  } else if (button == GLFW_MOUSE_BUTTON_MIDDLE) {
    panning_ = down;
  }
}

void Simulator::onCursor(double x, double y) {
  const double dx = x - cursor_x_, dy = y - cursor_y_;
  cursor_x_ = x;
  cursor_y_ = y;
  if (dragging_pen_ && input_) input_->drag(float(dx), float(dy));
  if (orbiting_) camera_.orbit(float(-dx * 0.008), float(dy * 0.008));
  if (panning_) {
    const VkExtent2D e = window_->framebufferExtent();
    const float mm = camera_.mmPerPixel(camera_.distance(), int(std::max(1u, e.height)));
    camera_.pan(float(-dx) * mm, float(dy) * mm);
  }
}

void Simulator::onScroll(double, double dy) {
  if (imgui_ && imgui_->wantsMouse()) return;
  GLFWwindow* w = window_->handle();
  const bool ctrl = glfwGetKey(w, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS;
  const bool alt = glfwGetKey(w, GLFW_KEY_LEFT_ALT) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_ALT) == GLFW_PRESS;
  const bool shift = glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
  if (alt) {
    camera_.zoom(float(std::pow(1.1, dy)));
  } else if (ctrl && input_) {
    input_->wheelPedal(float(dy));
    ui_.turbine_speed = input_->pedal();
  } else if (input_) {
    input_->setActive(shift ? PenRole::Mirror : PenRole::Drill);
    input_->wheel(float(dy));
  }
}

void Simulator::onKey(int key, int action, int mods) {
  if (action == GLFW_RELEASE) return;
  if (imgui_ && imgui_->wantsKeyboard()) return;
  const Vec3 c = box_.centre();
  const float radius = float(0.5 * norm(box_.hi - box_.lo) * 1.25);
  auto view = [&](render::ViewPreset p) { camera_.setView(p, render::toGlm(c), radius); };
  switch (key) {
    case GLFW_KEY_1: view(render::ViewPreset::Occlusal); break;
    case GLFW_KEY_2: view(render::ViewPreset::Buccal); break;
    case GLFW_KEY_3: view(render::ViewPreset::Lingual); break;
    case GLFW_KEY_4: view(render::ViewPreset::Mesial); break;
    case GLFW_KEY_5: view(render::ViewPreset::Distal); break;
    case GLFW_KEY_ESCAPE: quit_ = true; break;
    default: break;
  }
  if (!input_) return;
  const PenRole role = (mods & GLFW_MOD_SHIFT) ? PenRole::Mirror : PenRole::Drill;
  input_->setActive(role);
  constexpr double kStep = 3.0 * kPi / 180.0;
  switch (key) {
    case GLFW_KEY_PAGE_UP: input_->setPedal(input_->pedal() + 0.1); break;
    case GLFW_KEY_PAGE_DOWN: input_->setPedal(input_->pedal() - 0.1); break;
    case GLFW_KEY_SPACE: input_->setPedal(input_->pedal() > 0 ? 0.0 : 1.0); break;
    case GLFW_KEY_LEFT: input_->rotate(-kStep, 0); break;
    case GLFW_KEY_RIGHT: input_->rotate(kStep, 0); break;
    case GLFW_KEY_UP: input_->rotate(0, kStep); break;
    case GLFW_KEY_DOWN: input_->rotate(0, -kStep); break;
    case GLFW_KEY_R:
      input_->reset(PenRole::Drill, drillStartGrip(box_, 3.0));
      input_->reset(PenRole::Mirror, mirrorGrip(box_, render::fromGlm(camera_.eye())));
      break;
    default: break;
  }
  ui_.turbine_speed = input_->pedal();
}

// ---- 5. one frame --------------------------------------------------------------------------------------

render::FrameState Simulator::frameState(const HapticState& state, VkExtent2D extent) const {
  render::FrameState fs;
  const float aspect = float(extent.width) / float(std::max(1u, extent.height));
  fs.view = camera_.view();
  // The parameter window covers the right edge: the view's centre moves into the rest, so that the
  // tooth sits in the middle of what the student sees.
  const float shift_ndc = -float(sceneShiftPx()) * 2.0f / float(std::max(1u, extent.width));
  fs.projection = glm::translate(glm::mat4(1.0f), glm::vec3(shift_ndc, 0.0f, 0.0f)) * camera_.projection(aspect);
  fs.eye = camera_.eye();
  // A lamp above and behind the operator's shoulder: from the eye, raised toward +z.
  const render::CameraBasis b = camera_.basis();
  fs.light_dir = glm::normalize(-b.forward + 0.6f * b.up + 0.25f * b.right);
  fs.tooth_frame = view_.frame;
  fs.looks = ui_.params.looks;
  const ToolState& drill = state.tools[size_t(PenRole::Drill)];
  const ToolState& mirror = state.tools[size_t(PenRole::Mirror)];
  fs.drill_shown = drill.present;
  fs.drill = drill.tool;
  fs.bur = drill_name_;
  fs.drill_force_n = norm(drill.display.force);
  fs.max_force_n = ui_.params.device.max_force_n;
  fs.mirror_shown = mirror_tool_.has_value() && mirror.present;
  fs.mirror = mirror.tool;
  if (score_shown_ && !last_actions_.score_image_rect.empty()) {
    fs.overlay_shown = true;
    fs.overlay_rect = last_actions_.score_image_rect;
  }
  return fs;
}

// Where the test and the reader find things in a screenshot: projected points of the frame's state.
Status Simulator::writeShot(const RgbImage& image, const std::string& stem, const render::FrameState& fs,
                            VkExtent2D extent) {
  const std::string png = outPath(stem + ".png");
  if (Status st = writePng(png, image); !st) return st;
  out_.written.push_back(png);
  const int w = int(extent.width), h = int(extent.height);
  const float shift = float(sceneShiftPx());
  auto point = [&](const Vec3& p) {
    const glm::vec3 q = camera_.project(render::toGlm(p), w, h);
    return nlohmann::json::array({q.x - shift, q.y});
  };
  nlohmann::ordered_json j;
  j["loop_time_s"] = loopTime();
  j["width"] = w;
  j["height"] = h;
  j["windowed"] = !headless_;
  j["bur_tip_px"] = point(fs.drill.position);
  j["bur_shank_px"] = point(fs.drill.apply({0.0, 0.0, 4.0}));  // on the shank, below the handpiece's nose
  if (fs.mirror_shown) {
    const Vec3 centre = fs.mirror.position;
    const glm::vec3 pc = camera_.project(render::toGlm(centre), w, h);
    // The face's on-screen half-extent: the farthest of a few rim points from the centre.
    double radius_px = 0;
    for (int k = 0; k < 8; ++k) {
      const double a = 2 * kPi * k / 8;
      const Vec3 rim = fs.mirror.apply({10.85 * std::cos(a), 10.85 * std::sin(a), 0.0});
      const glm::vec3 pr = camera_.project(render::toGlm(rim), w, h);
      radius_px = std::max(radius_px, double(glm::length(glm::vec2(pr.x - pc.x, pr.y - pc.y))));
    }
    j["mirror_centre_px"] = nlohmann::json::array({pc.x - shift, pc.y});
    j["mirror_radius_px"] = radius_px;
    j["mirror_faces_eye"] = glm::dot(render::toGlm(fs.mirror.applyDirection({0, 0, 1})), fs.eye - render::toGlm(centre)) > 0;
  }
  j["tooth_centre_px"] = point(box_.centre());
  j["removed_mm3"] = out_.removed_mm3 + (segment_.loop ? segment_.loop->latest().removed_mm3 : 0.0);
  if (imgui_ && !last_actions_.score_image_rect.empty()) {
    const PixelRect& r = last_actions_.score_image_rect;
    j["score_image_rect"] = {r.x, r.y, r.width, r.height};
  }
  j["panel_shown"] = imgui_.has_value();
  if (panel_rect_[2] > 0) j["panel_rect"] = panel_rect_;
  const std::string text = j.dump(2) + "\n";
  return writeFileAtomic(outPath(stem + ".json"), text);
}

Status Simulator::drawFrame(bool shot_due, const std::string& shot_stem, bool frame_due, const std::string& frame_stem) {
  VkExtent2D extent;
  render::RenderImage target;
  uint32_t index = 0;
  if (swapchain_) {
    VkExtent2D fb = window_->framebufferExtent();
    if (fb.width == 0 || fb.height == 0) {  // minimised: nothing to draw
      if (imgui_) imgui_->discardFrame();
      ui::Window::waitEvents(0.05);
      return Ok{};
    }
    if (fb.width != swapchain_->extent().width || fb.height != swapchain_->extent().height) {
      renderer_->forgetTargets();
      if (Status st = swapchain_->recreate(fb); !st) return st;
    }
    auto ok = swapchain_->acquire(&index);
    if (!ok) return ok.error();
    if (!*ok) {
      renderer_->forgetTargets();
      if (imgui_) imgui_->discardFrame();
      return swapchain_->recreate(window_->framebufferExtent());
    }
    extent = swapchain_->extent();
    target = render::RenderImage{swapchain_->image(index), swapchain_->view(index), swapchain_->format(), extent};
  } else {
    target = offscreen_->image();
    extent = target.extent;
  }
  const HapticState state = segment_.loop ? segment_.loop->latest() : last_state_;
  const render::FrameState fs = frameState(state, extent);
  Status recorded = Ok{};
  Status submitted = gpu::submitAndWait(*ctx_, "frame", [&](gpu::Commands& cmds) -> Status {
    recorded = renderer_->recordFrame(cmds.cmd(), target, *surfaces_, fs, [&](VkCommandBuffer cb) {
      if (imgui_) imgui_->render(cb);
    });
    renderer_->markSubmitted(cmds.serial());
    return recorded;
  });
  if (!submitted) return submitted;
  if (shot_due || frame_due) {
    const VkImageLayout layout = swapchain_ ? VK_IMAGE_LAYOUT_PRESENT_SRC_KHR : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    auto image = render::readImage(*ctx_, target, layout);
    if (!image) return image.error();
    if (shot_due)
      if (Status st = writeShot(*image, shot_stem, fs, extent); !st) return st;
    if (frame_due) {
      const std::string png = outPath(frame_stem + ".png");
      if (Status st = writePng(png, *image); !st) return st;
      out_.written.push_back(png);
    }
  }
  if (swapchain_) {
    auto presented = swapchain_->present(index);
    if (!presented) return presented.error();
    if (!*presented) {
      renderer_->forgetTargets();
      return swapchain_->recreate(window_->framebufferExtent());
    }
  }
  return Ok{};
}

Status Simulator::scoreNow() {
  if (!task_) return Ok{};
  // Scored, saved and drawn as compacted, the layout a saved and reloaded tooth has, so that the
  // picture equals the one `replay` and `score` draw from the files, pixel for pixel.
  view_.voxels.compact();
  // The statistics come from the session when one segment holds the whole cut.
  std::optional<SessionRecording> session;
  ScoreFiles files = scoreFiles("initial.dvol", "final.dvol", "");
  files.no_session_reason = segments_ > 1 ? "the cut spans " + std::to_string(segments_) + " segments, and no one session holds it"
                                          : "no session was recorded (no --out folder)";
  if (segments_ == 1 && !o_.out.empty()) {
    auto read = readSessionFile(outPath("session.dses"));
    if (read) {
      session = std::move(*read);
      files = scoreFiles(outPath("initial.dvol"), outPath("final.dvol"), outPath("session.dses"));
    } else {
      files.no_session_reason = read.message();
    }
  }
  auto score = scoreCut(*task_, initial_, view_, nullptr, session ? &*session : nullptr, files);
  if (!score) return score.error();
  ui_.score.valid = true;
  ui_.score.total = score->total;
  ui_.score.total_max = score->total_max;
  ui_.score.rows.clear();
  // One row per component ("removal 49.8 / 50"), the deductions, then the volumes a teacher asks about first.
  char text[64];
  if (auto c = score->report.find("components"); c != score->report.end())
    for (const auto& [name, part] : c->items()) {
      if (part["points"].is_number())
        std::snprintf(text, sizeof text, "%.1f / %d", part["points"].get<double>(), part.value("max", 0));
      else
        std::snprintf(text, sizeof text, "not scored");
      ui_.score.rows.push_back({name, text});
    }
  if (auto d = score->report.find("deductions"); d != score->report.end())
    for (const auto& [name, part] : d->items())
      if (part.contains("points") && part["points"].is_number()) {
        std::snprintf(text, sizeof text, "-%.1f", part["points"].get<double>());
        ui_.score.rows.push_back({name, text});
      }
  if (auto r = score->report.find("caries_remaining_mm3"); r != score->report.end() && r->is_number()) {
    std::snprintf(text, sizeof text, "%.3f mm^3", r->get<double>());
    ui_.score.rows.push_back({"caries left", text});
  }
  ui_.score.rows.push_back({"pulp exposed", score->report.value("pulp_exposed", false) ? "yes" : "no"});
  const RgbImage picture = scorePicture(*task_, initial_, view_, *score, nullptr);
  ui_.score.image_width = picture.width;
  ui_.score.image_height = picture.height;
  if (Status st = renderer_->setOverlayImage(picture); !st) return st;
  score_shown_ = true;
  out_.score = score->total;
  note(score->summary);
  for (const std::string& w : score->warnings) note("warning: " + w);
  if (!o_.out.empty()) {
    if (Status st = saveTooth(outPath("final.dvol"), view_); !st) return st;
    if (Status st = writeScoreReport(outPath("score.json"), score->report); !st) return st;
    if (Status st = writePng(outPath("score.png"), picture); !st) return st;
    for (const char* f : {"final.dvol", "score.json", "score.png"}) out_.written.push_back(outPath(f));
  }
  return Ok{};
}

Status Simulator::handleActions(ui::PanelActions& a) {
  ui::applyPresetActions(a, *presets_, ui_);
  if (a.params_changed) {
    params_ = ui_.params;
    if (segment_.recorder) segment_.recorder->setParams(params_);
    else if (segment_.loop) segment_.loop->setParams(params_);
  }
  if (a.normal_mode_changed) surfaces_->setNormalMode(params_.view.normals);
  if (a.speed_changed && input_) input_->setPedal(ui_.turbine_speed);
  if (a.task_changed) {
    auto task = builtinTask(ui_.task);
    if (!task) note(task.message());
    else task_ = std::move(*task);
  }
  const bool running = segment_.loop != nullptr;
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
  if (a.level_changed && !o_.tooth.empty()) {
    note("the voxel level applies to the built-in molar; " + o_.tooth + " keeps its own grid");
    ui_.level = initial_.frame.level;
  }
  if (a.reset || (a.level_changed && o_.tooth.empty())) {
    if (running)
      if (Status st = endSegment("reset"); !st) return st;
    if (a.level_changed) {
      o_.level = ui_.level;
      if (Status st = loadTooth(); !st) return st;
    } else {
      cut_ = initial_;
      view_ = initial_;
    }
    if (Status st = surfaces_->build(view_.voxels); !st) return st;
    score_shown_ = false;
    ui_.score = {};
    if (Status st = startSegment(); !st) return st;
  }
  if (a.score) {
    if (segment_.loop)
      if (Status st = endSegment("scored"); !st) return st;
    if (Status st = scoreNow(); !st) return st;
  }
  return Ok{};
}

Status Simulator::frame() {
  const auto t0 = Clock::now();
  if (window_) {
    ui::Window::pollEvents();
    if (window_->closeRequested()) quit_ = true;
  }
  // Lockstep: the haptic loop catches up with this frame's loop time.
  if (lockstep_ && segment_.loop) {
    const double frame_t = double(out_.frames) / o_.fps;
    HapticLoop& loop = *segment_.loop;
    const double rate = params_.device.rate_hz;
    while (segment_t0_ + double(loop.stepsRun()) / rate < frame_t - 1e-9) {
      loop.step();
      // Back to back, the loop outruns the disk; let the recorder keep up.
      while (segment_.recorder && loop.droppedRecords() == 0 && segment_.recorder->stepsWritten() + 8192 < loop.stepsRun())
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  const double t = loopTime();
  // Screenshots and frames due at this loop time.
  bool shot_due = false, frame_due = false;
  std::string shot_stem, frame_stem;
  if (!o_.out.empty() && next_shot_ < o_.shots_s.size() && t >= o_.shots_s[next_shot_] - 1e-9) {
    shot_due = true;
    shot_stem = "shot-" + std::to_string(++next_shot_);
    while (next_shot_ < o_.shots_s.size() && t >= o_.shots_s[next_shot_] - 1e-9) ++next_shot_;
  }
  if (!o_.out.empty() && o_.frame_every_s > 0 && t >= next_frame_s_ - 1e-9) {
    frame_due = true;
    char name[32];
    std::snprintf(name, sizeof name, "frame-%05d", frames_written_++);
    frame_stem = name;
    next_frame_s_ += o_.frame_every_s;
  }
  if (final_shot_due_) {
    shot_due = true;
    shot_stem = "shot-final";
    final_shot_due_ = false;
  }
  // Headless, a frame nobody will see is not drawn: the edits wait, and the steps run back to back.
  const bool draw = !headless_ || shot_due || frame_due || (o_.bench_frames > 0 && t >= o_.bench_from_s - 1e-9);
  // A headless frame's time starts here: the haptic steps the frame loop ran for it are not drawing.
  const auto draw_t0 = Clock::now();

  // The loop's voxel edits reach this copy of the tooth at once; the changed bricks are re-meshed
  // when the frame is drawn.
  batch_.clear();
  edits_.drain(&batch_);
  if (!batch_.empty()) applyVoxelEdits(view_.voxels, batch_, &pending_dirty_);
  if (draw && !pending_dirty_.empty()) {
    // Frames skipped headless leave the same brick listed by several drains.
    auto key = [](const BrickCoord& b) { return std::tuple(b.z, b.y, b.x); };
    std::sort(pending_dirty_.begin(), pending_dirty_.end(), [&](const BrickCoord& a, const BrickCoord& b) { return key(a) < key(b); });
    pending_dirty_.erase(std::unique(pending_dirty_.begin(), pending_dirty_.end(),
                                     [&](const BrickCoord& a, const BrickCoord& b) { return key(a) == key(b); }),
                         pending_dirty_.end());
    gpu::SurfaceUpdateStats st;
    if (Status u = surfaces_->update(view_.voxels, pending_dirty_, &st); !u) return u;
    pending_dirty_.clear();
    remesh_sum_ms_ += st.total_ms;
    ++remesh_count_;
    ui_.stats.triangles = st.triangles;
    ui_.stats.remesh_ms = st.total_ms;
  }

  const HapticState state = segment_.loop ? segment_.loop->latest() : last_state_;
  const ToolState& drill = state.tools[size_t(PenRole::Drill)];
  ui_.force.force_n = norm(drill.display.force);
  ui_.force.contact = drill.contacts > 0;
  ui_.force.max_force_n = ui_.params.device.max_force_n;
  if (ui_.pedal_present) ui_.turbine_speed = state.pedal;
  serviceDevices();
  updateSound(state);
  const double wall = std::chrono::duration<double>(Clock::now() - rate_t0_).count();
  const uint64_t steps_now = steps_done_ + (segment_.loop ? segmentSteps() : 0);
  if (wall > 0.5) {
    ui_.stats.haptic_rate_hz = double(steps_now - rate_steps_) / wall;
    rate_steps_ = steps_now;
    rate_t0_ = Clock::now();
  }

  // The panel.
  ui::PanelActions actions;
  if (!draw) {
    // nothing shown: no panel either
  } else if (imgui_) {
    const VkExtent2D e = window_ ? window_->framebufferExtent() : offscreen_->image().extent;
    imgui_->newFrame(int(e.width), int(e.height), lockstep_ ? 1.0 / o_.fps : msSince(last_frame_) / 1000.0);
    actions = ui::drawParamPanel(ui_);
    ui::drawOverlay(ui_);
    if (ImGuiWindow* panel = ImGui::FindWindowByName("Parameters"))
      panel_rect_ = {int(panel->Pos.x), int(panel->Pos.y), int(panel->Size.x), int(panel->Size.y)};
    if (input_ && window_) input_->setViewport(int(std::max(1u, e.width)), int(std::max(1u, e.height)));
  } else if (input_) {
    input_->setViewport(o_.width, o_.height);
  }

  if (draw) {
    last_actions_ = actions;
    if (Status st = drawFrame(shot_due, shot_stem, frame_due, frame_stem); !st) return st;
    if (Status st = handleActions(actions); !st) return st;
    ++out_.drawn;
    // Windowed, the time from frame to frame (the frame rate); headless, the frame's own time.
    frame_ms_.push_back(headless_ ? msSince(draw_t0) : msSince(last_frame_));
    ui_.stats.frame_ms = msSince(t0);
    last_frame_ = Clock::now();
  }
  ++out_.frames;

  // The end: the script played out (and scored when asked), or the time given.
  if (o_.exit_after_s > 0 && t >= o_.exit_after_s - 1e-9) quit_ = true;
  if (o_.bench_frames > 0 && out_.drawn >= uint64_t(o_.bench_frames)) quit_ = true;
  if (script_ && segment_.loop && t >= script_end_s_ + 0.2) {
    if (Status st = endSegment("completed"); !st) return st;
    if (o_.score_at_end)
      if (Status st = scoreNow(); !st) return st;
    // One more frame shows the end (and the score); headless then stops.
    if (!o_.out.empty()) final_shot_due_ = true;
    if ((headless_ && o_.exit_after_s <= 0) || o_.exit_at_end) quit_after_final_ = true;
  }
  if (quit_after_final_ && !final_shot_due_ && !segment_.loop) quit_ = true;
  // Stopped, loop time stands still; headless it follows the frames, so that --exit-after ends it.
  if (headless_ && !segment_.loop) segment_t0_ = std::max(segment_t0_, double(out_.frames) / o_.fps);
  return Ok{};
}

Result<SimulatorOutcome> Simulator::run() {
  run_t0_ = Clock::now();
  last_frame_ = run_t0_;
  if (Status st = setUp(); !st) return st.error();
  Status result = Ok{};
  while (!quit_) {
    if (Status st = frame(); !st) {
      result = st;
      break;
    }
  }
  // Whatever happened, the loop stops and the recording is closed, so that no drilling is lost.
  if (Status st = endSegment(result ? "completed" : "error"); !st && result) result = st;
  closeDevices();
  if (sound_ && sound_->offline()) {
    if (Status st = sound_->finish(); !st && result) result = st;
    else if (st) out_.written.push_back(o_.audio_out);
  }
  if (ctx_) (void)ctx_->waitIdle();  // teardown: a failure here changes nothing the user keeps
  if (!result) return result.error();
  // With validation on (DENTSIM_VALIDATION=1, as in the tests), any error fails the run.
  if (ctx_ && ctx_->validationEnabled() && ctx_->validationErrorCount() > 0)
    return makeError("gpu", std::to_string(ctx_->validationErrorCount()) + " Vulkan validation errors; the last: " +
                                ctx_->lastValidationMessage());
  if (!o_.out.empty() && out_.score < 0) {
    if (Status st = saveTooth(outPath("final.dvol"), view_); !st) return st.error();
    out_.written.push_back(outPath("final.dvol"));
  }
  out_.wall_s = std::chrono::duration<double>(Clock::now() - run_t0_).count();
  out_.haptic_steps = steps_done_;
  // Over the drilling only: set-up (voxelizing, point shells, pipelines) is not the loop's.
  const double drilling_s = std::chrono::duration<double>(Clock::now() - haptic_t0_).count();
  out_.haptic_rate_hz = drilling_s > 0 ? double(steps_done_) / drilling_s : 0.0;
  if (!frame_ms_.empty()) {
    // The first frames build the pipelines' caches and the panel's layout: a benchmark leaves them out.
    std::vector<double> sorted(frame_ms_.begin() + std::min<ptrdiff_t>(o_.bench_frames > 0 ? 3 : 0, ptrdiff_t(frame_ms_.size()) - 1),
                               frame_ms_.end());
    std::sort(sorted.begin(), sorted.end());
    double sum = 0;
    for (double v : sorted) sum += v;
    out_.frame_ms_mean = sum / double(sorted.size());
    out_.frame_ms_p50 = sorted[sorted.size() / 2];
    out_.frame_ms_p95 = sorted[std::min(sorted.size() - 1, size_t(0.95 * double(sorted.size())))];
  }
  out_.remesh_ms_mean = remesh_count_ ? remesh_sum_ms_ / double(remesh_count_) : 0.0;
  out_.triangles = ui_.stats.triangles;
  return out_;
}

}  // namespace

Result<SimulatorOutcome> runSimulator(const SimulatorOptions& options) {
  Simulator sim(options);
  return sim.run();
}

}  // namespace dentsim::app
