// The simulator's set-up: options checked, the task, tooth and tools loaded, the camera placed, the pens, the sound, the frames' device and the panel's state; the first segment started.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include "app/commands.h"
#include "app/simulator_state.h"
#include "app/tool_placement.h"
#include "core/text_escape.h"
#include "eval/cut_score.h"
#include "sim/course_paths.h"
#include "sim/novice_paths.h"
#include "sim/session_attempts.h"
#include "sim/session_recorder.h"
#include "sim/pen_script.h"
#include "sim/scripted_paths.h"
#include "sim/builtin_tooth.h"
#include "sim/tool_library.h"
#include "ui/course_list.h"
#include "ui/window.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim::app {

void Simulator::note(const std::string& text) {
  std::printf("%s\n", text.c_str());
  // At once, also into a pipe: a score or an error is read while the window is still open.
  std::fflush(stdout);
  ui_.status = text;
}

void Simulator::noteWarning(const std::string& text) {
  warn(text);
  ui_.status = "warning: " + text;
}

// ---- set-up ----------------------------------------------------------------------------------------------

// Loads the tooth that tooth_file_ and o_.level name; on an error the tooth in use stays.
Status Simulator::loadTooth() {
  auto t = builtinTooth() ? builtinMolarTooth(o_.level) : loadToothFileOrAsset(tooth_file_);
  if (!t) return t.error();
  const TissueBox box = tissueBox(t->voxels, t->frame);
  if (box.empty()) return makeError(toothName(), "the tooth holds no tissue");
  initial_ = std::move(*t);
  box_ = box;
  cut_ = initial_;
  view_ = initial_;
  return Ok{};
}

Status Simulator::loadMirror() {
  mirror_tool_.reset();
  if (mirror_name_.empty() || o_.devices.mirror_pen == "none") return Ok{};
  auto m = loadToolModel(mirror_name_, params_.point_shell);
  if (!m) return m.error();
  mirror_tool_ = std::move(*m);
  return Ok{};
}

Status Simulator::placeCamera() {
  // --view, else the task's view, else buccal; a side view is raised 30 degrees (0.52 rad: a view
  // from the chair looks down on a lower crown) unless the task gives its own elevation.
  const std::optional<TaskView>& tv = task_->view;
  const std::string name = !o_.view.empty() ? o_.view : tv ? tv->camera : "buccal";
  auto preset = render::parseViewPreset(name);
  if (!preset) return preset.error();
  const float elevation = o_.view.empty() && tv ? float(tv->elevation_deg * std::numbers::pi / 180.0) : 0.52f;
  const Vec3 c = box_.centre();
  const double radius = 0.5 * norm(box_.hi - box_.lo);
  camera_.setView(*preset, render::toGlm(c), float(radius));
  if (*preset != render::ViewPreset::Occlusal) camera_.orbit(0.0f, elevation);
  // Widened to take in the mirror where it starts.
  if (mirror_tool_) {
    const Vec3 face = mirrorGrip(box_, render::fromGlm(camera_.eye())).apply(-kMirrorGripLocal);
    camera_.setTarget(render::toGlm((c + face) * 0.5));
    camera_.setDistance(camera_.distance() * float((radius + 0.5 * norm(face - c)) / radius) * 0.8f);
  }
  input_.setViewFixed(o_.view.empty() && tv && tv->fixed);
  return Ok{};
}

void Simulator::showTask() {
  // A built-in task started by its short name ("caries") shows as its entry in the list.
  for (const ui::TaskChoice& t : ui_.course.tasks)
    if (t.builtin && t.source == task_->name && !task_source_.ends_with(".json")) task_source_ = t.source;
  ui_.task = task_source_;
  ui_.task_title = task_->title;
  ui_.task_instructions = task_->instructions;
  // builtinTask takes a built-in name before a file of that name; no built-in name ends in ".json".
  std::error_code ec;
  ui_.task_is_file = task_source_.ends_with(".json") && std::filesystem::is_regular_file(task_source_, ec);
  ui_.tooth = tooth_file_;
  ui_.level = initial_.frame.level;
}

Status Simulator::recordingFolder() {
  if (!o_.out.empty()) return Ok{};
  std::string pattern = (std::filesystem::temp_directory_path() / "dentsim-teacher-XXXXXX").string();
  if (!::mkdtemp(pattern.data())) return makeError(pattern, "cannot make a folder for the teacher's sessions");
  o_.out = pattern;
  note("teacher mode: sessions are recorded in " + o_.out);
  return Ok{};
}

Status Simulator::loadDrill() {
  auto d = loadToolModel(drill_name_, params_.point_shell);
  if (!d) return d.error();
  drill_tool_ = std::move(*d);
  return Ok{};
}

// The pen path both pens play: the task's own preparation (as the careful dentist does it, or with
// one fault) or a script file; a mirror it does not move is held still where the demo holds it.
Status Simulator::setUpScript(const Pose& mirror_start) {
  if (o_.pen_script.empty() && !o_.demo_script) return Ok{};
  if (o_.demo_script) {
    const std::optional<Attempt> attempt = parseAttempt(o_.attempt);
    if (!attempt) return makeError("--attempt", "\"" + o_.attempt + "\" is not one of " + attemptNames());
    if (task_->ideal && task_->ideal->kind == IdealKind::Session) {
      // A teacher's task: every attempt is derived from the professional's recorded session, as
      // `task validate` derives it (sim/session_attempts.h).
      auto session = readSessionFile(task_->ideal->path);
      if (!session) return session.error();
      const DerivedAttemptSettings derive = derivedSettingsFor(task_->force_error_n);
      auto pro = professionalPath(*session, task_->ideal->path, derive);
      if (!pro) return pro.error();
      script_ = derivedAttemptPath(*pro, *attempt, task_->insertion_axis, initial_.frame.tooth, derive);
    } else {
      // The task's own exercise (course_paths.h), with the bur this run holds.
      Exercise exercise = exerciseOf(*task_);
      exercise.bur = drill_name_;
      auto path = taskAttemptPath(exercise, *attempt, initial_.voxels, initial_.frame, params_);
      if (!path) return path.error();
      script_ = std::move(*path);
    }
  } else {
    auto path = loadPenPath(o_.pen_script);
    if (!path) return path.error();
    script_ = penPathInSimulationFrame(*path, initial_);
    // A first script often starts inside the tooth; say so before anything moves.
    for (const std::string& w : penPathStartWarnings(*script_, initial_, o_.pen_script))
      warn(w);
  }
  if (o_.wander_mm > 0) script_ = wanderingPath(*script_, o_.wander_mm);
  if (mirror_tool_ && !hasPen(*script_, PenRole::Mirror)) addStillMirror(*script_, mirror_start);
  script_end_s_ = pathEnd(*script_);
  return Ok{};
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
  if (Status st = rack_.checkNames(); !st) return st;

  params_ = defaultSimParams();
  looks_ = defaultLookParams();
  if (!o_.params.empty()) {
    auto p = ui::loadPreset(o_.params);
    if (!p) return p.error();
    params_ = std::move(p->sim);
    looks_ = std::move(p->looks);
  }
  auto task = builtinTask(o_.task);
  if (!task) return task.error();
  task_ = std::move(*task);
  task_source_ = o_.task;
  drill_name_ = o_.bur.empty() ? task_->drill_tool : o_.bur;
  tooth_file_ = !o_.tooth.empty() ? o_.tooth : task_->tooth == kBuiltinMolarTooth ? "" : task_->tooth;
  // A level asked for only builds the built-in molar; a file (or a task's embedded tooth) keeps its grid.
  if (o_.level != 0 && !tooth_file_.empty())
    return makeError("--level", "applies only to the built-in molar; the tooth " + tooth_file_ + " keeps its own grid");
  if (o_.level == 0) o_.level = task_->level;  // the task's level, when none was asked for
  if (Status st = loadTooth(); !st) return st;
  if (Status st = loadDrill(); !st) return st;
  mirror_name_ = o_.mirror_tool ? *o_.mirror_tool : task_->mirror_tool;
  if (Status st = loadMirror(); !st) return st;
  if (Status st = placeCamera(); !st) return st;
  if (Status st = setUpGhost(); !st) return st;

  // The pens: hardware ones map their workspace around the tool's start, turned with the camera.
  RackPlacement at;
  at.drill_start = drillStartGrip(box_, 3.0);
  at.mirror_start = mirrorGrip(box_, render::fromGlm(camera_.eye()));
  const render::CameraBasis basis = camera_.basis();
  at.screen = Quat::fromAxes(render::fromGlm(basis.right), render::fromGlm(basis.up), -render::fromGlm(basis.forward));
  if (Status st = setUpScript(at.mirror_start); !st) return st;
  if (!o_.guide.empty()) {
    auto guide = loadGuidePath(o_.guide, o_.guide_settings);
    if (!guide) return makeError("--guide", guide.message());
    guide_ = std::move(*guide);
    // A path cut on another tooth leads the bur through other tissue: allowed, but said.
    if (guide_->source_tooth_hash != volumeHashHex(initial_.voxels, initial_.frame))
      noteWarning("--guide " + shownPath(o_.guide) + " was recorded on another tooth (" + guide_->source_tooth_hash + ")");
  }
  // A pen failing, leaving or coming back goes into the session being recorded, if any.
  rack_.onPenChange([this](PenRole pen, const std::string& state, const std::string& why) {
    if (SessionRecorder* recorder = segments_.recorder()) recorder->noteDevice(pen, state, why);
  });
  if (Status st = rack_.open(script_ ? &*script_ : nullptr, mirror_tool_.has_value(), at, params_.device, lockstep_); !st)
    return st;
  if (rack_.hasVirtualPen()) {
    pens_ = std::make_unique<ui::PenInput>(camera_, rack_.virtualPen(PenRole::Drill), rack_.virtualPen(PenRole::Mirror));
    pens_->reset(PenRole::Drill, at.drill_start);
    if (mirror_tool_) pens_->reset(PenRole::Mirror, at.mirror_start);
  }
  input_.setPens(pens_.get());
  RunSoundOptions so;
  so.sound = o_.sound;
  so.audio_out = o_.audio_out;
  so.turbine_wav = o_.turbine_wav;
  so.cutting_wav = o_.cutting_wav;
  so.recorded_rpm = o_.recorded_rpm;
  auto sound = sound_.open(so, headless_, [this](const std::string& text) { note(text); });
  if (!sound) return sound.error();
  ui_.sound.output = *sound;

  PainterOptions po;
  po.headless = headless_;
  po.width = o_.width;
  po.height = o_.height;
  po.vsync = o_.vsync;
  po.device = o_.device;
  po.panel = o_.ui;
  po.normals = looks_.view.normals;
  po.mesher = o_.mesher;
  auto painter = FramePainter::create(po, [this](ui::Window& w) { input_.attach(w); });
  if (!painter) return painter.error();
  painter_ = std::move(*painter);
  input_.setPanel(painter_->panel());
  out_.device = painter_->context().device().name;
  out_.windowed = !headless_;
  if (o_.progressive.value_or(!headless_)) {
    // The coarse copies now, the full copy region by region over the first frames (Simulator::frame).
    const auto t0 = Clock::now();
    if (Status st = painter_->surfaces().beginBuild(view_.voxels, view_.frame); !st) return st;
    std::printf("tooth: %s, level %d, %.4f mm voxels; coarse copies in %.1f ms on %s, full detail follows\n",
                toothName().c_str(), initial_.frame.level, initial_.frame.voxel_mm,
                std::chrono::duration<double, std::milli>(Clock::now() - t0).count(), out_.device.c_str());
    if (!painter_->surfaces().done()) progress_.start("full detail");
  } else {
    gpu::SurfaceUpdateStats stats;
    if (Status st = painter_->surfaces().build(view_.voxels, &stats); !st) return st;
    final_triangles_ = stats.triangles;
    std::printf("tooth: %s, level %d, %.4f mm voxels; surface %llu triangles in %.1f ms on %s\n", toothName().c_str(),
                initial_.frame.level, initial_.frame.voxel_mm, static_cast<unsigned long long>(stats.triangles),
                stats.total_ms, out_.device.c_str());
  }

  // The panel's state.
  presets_ = std::make_unique<ui::PresetStore>(ui::defaultPresetDirectory());
  ui_.params = params_;
  ui_.looks = looks_;
  ui_.bur = drill_name_;
  ui_.course = ui::listCourse(o_.course);
  if (!ui_.course.error.empty()) note(ui_.course.error);
  showTask();
  ui_.teacher = o_.teacher;
  ui_.pedal_present = script_.has_value() || rack_.hasPedal();
  ui_.presets = presets_->list();
  ui_.force.max_force_n = params_.device.max_force_n;

  if (o_.teacher)
    if (Status st = recordingFolder(); !st) return st;
  if (!o_.out.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o_.out, ec);
    if (ec) return makeError(o_.out, "cannot create the output folder: " + ec.message());
  }
  return startSegment();
}

}  // namespace dentsim::app
