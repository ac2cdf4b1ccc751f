// The simulator's set-up: options checked, the task, tooth and tools loaded, the camera placed, the pens, the sound, the frames' device and the panel's state; the first segment started.
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/commands.h"
#include "app/first_view.h"
#include "app/simulator_state.h"
#include "app/tool_placement.h"
#include "core/text_escape.h"
#include "eval/cut_score.h"
#include "model/tool_generator.h"
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

// Loads the tooth model_.tooth names; on an error the tooth in use stays.
Status Simulator::loadTooth() {
  auto t = model_.tooth.builtin() ? builtinMolarTooth(model_.tooth.level) : loadToothFileOrAsset(model_.tooth.file);
  if (!t) return t.error();
  const TissueBox box = firstViewBox(t->voxels, t->frame);
  if (box.empty()) return makeError(model_.tooth.name(), "the tooth holds no tissue");
  model_.initial = std::move(*t);
  model_.box = box;
  state_.cut = model_.initial;
  state_.view = model_.initial;
  return Ok{};
}

Status Simulator::loadMirror() {
  model_.mirror_tool.reset();
  if (model_.mirror_name.empty() || o_.devices.mirror_pen == "none") return Ok{};
  auto m = loadToolModel(model_.mirror_name, model_.params.point_shell);
  if (!m) return m.error();
  model_.mirror_tool = std::move(*m);
  return Ok{};
}

Status Simulator::placeCamera() {
  auto view = chooseFirstView(o_.view, model_.task->view, model_.mirror_tool.has_value());
  if (!view) return view.error();
  placeFirstView(camera_, model_.box, *view);
  input_.setViewFixed(view->fixed);
  return Ok{};
}

void Simulator::showTask() {
  // A built-in task started by its short name ("caries") shows as its entry in the list.
  for (const ui::TaskChoice& t : ui_.course.tasks)
    if (t.builtin && t.source == model_.task->name && !model_.task_source.ends_with(".json")) model_.task_source = t.source;
  ui_.task = model_.task_source;
  ui_.task_title = model_.task->title;
  ui_.task_instructions = model_.task->instructions;
  // builtinTask takes a built-in name before a file of that name; no built-in name ends in ".json".
  std::error_code ec;
  ui_.task_is_file = model_.task_source.ends_with(".json") && std::filesystem::is_regular_file(model_.task_source, ec);
  ui_.tooth = model_.tooth.file;
  ui_.level = model_.initial.frame.level;
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
  auto d = loadToolModel(model_.drill_name, model_.params.point_shell);
  if (!d) return d.error();
  model_.drill_tool = std::move(*d);
  return Ok{};
}

// The task's own preparation as the careful dentist does it (or with one fault): derived from the
// professional's recorded session as `task validate` derives it (sim/session_attempts.h) for a
// teacher's task, else the task's exercise (course_paths.h) with the bur this run holds.
Result<PenPath> Simulator::taskAttemptScript(Attempt attempt) const {
  if (model_.task->ideal && model_.task->ideal->kind == IdealKind::Session) {
    auto session = readSessionFile(model_.task->ideal->path);
    if (!session) return session.error();
    const DerivedAttemptSettings derive = derivedSettingsFor(model_.task->force_error_n);
    auto pro = professionalPath(*session, model_.task->ideal->path, derive);
    if (!pro) return pro.error();
    return derivedAttemptPath(*pro, attempt, model_.task->insertion_axis, model_.initial.frame.tooth, derive);
  }
  Exercise exercise = exerciseOf(*model_.task);
  exercise.bur = model_.drill_name;
  return taskAttemptPath(exercise, attempt, model_.initial.voxels, model_.initial.frame, model_.params);
}

// The pen path both pens play: the task's own preparation (as the careful dentist does it, or with
// one fault) or a script file; a mirror it does not move is held still where the demo holds it.
Status Simulator::setUpScript(const Pose& mirror_start) {
  if (o_.pen_script.empty() && !o_.demo_script) return Ok{};
  if (o_.demo_script) {
    const std::optional<Attempt> attempt = parseAttempt(o_.attempt);
    if (!attempt) return makeError("--attempt", "\"" + o_.attempt + "\" is not one of " + attemptNames());
    auto path = taskAttemptScript(*attempt);
    if (!path) return path.error();
    model_.script = std::move(*path);
  } else {
    auto path = loadPenPath(o_.pen_script);
    if (!path) return path.error();
    model_.script = penPathInSimulationFrame(*path, model_.initial);
    // A first script often starts inside the tooth; say so before anything moves.
    for (const std::string& w : penPathStartWarnings(*model_.script, model_.initial, o_.pen_script))
      warn(w);
  }
  if (o_.wander_mm > 0) model_.script = wanderingPath(*model_.script, o_.wander_mm);
  if (model_.mirror_tool && !hasPen(*model_.script, PenRole::Mirror)) addStillMirror(*model_.script, mirror_start);
  model_.script_end_s = pathEnd(*model_.script);
  return Ok{};
}

Status Simulator::setUp() {
  if (Status st = checkMode(); !st) return st;
  if (Status st = loadPresetAndTask(); !st) return st;
  if (Status st = loadTooth(); !st) return st;
  if (Status st = loadDrill(); !st) return st;
  model_.mirror_name = o_.mirror_tool ? *o_.mirror_tool : model_.task->mirror_tool;
  if (Status st = loadMirror(); !st) return st;
  if (Status st = placeCamera(); !st) return st;
  if (Status st = setUpGhost(); !st) return st;
  if (Status st = setUpPens(); !st) return st;
  end_ = EndRules(o_.end, headless_, model_.script ? std::optional<double>(model_.script_end_s) : std::nullopt);
  auto sound = sound_.open(o_.sound, headless_, [this](const std::string& text) { note(text); });
  if (!sound) return sound.error();
  ui_.sound.output = *sound;
  if (Status st = setUpPainter(); !st) return st;
  setUpPanel();
  if (Status st = setUpHelp(); !st) return st;
  if (o_.teacher)
    if (Status st = recordingFolder(); !st) return st;
  if (!o_.out.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o_.out, ec);
    if (ec) return makeError(o_.out, "cannot create the output folder: " + ec.message());
  }
  return startSegment();
}

// Window or not (a display that does not answer means headless, with a notice), and whether the
// run can end at all.
Status Simulator::checkMode() {
  headless_ = o_.frames.headless;
  if (!headless_) {
    if (std::string why = ui::whyNoDisplay(); !why.empty()) {
      std::printf("dentsim: %s: running headless\n", why.c_str());
      headless_ = true;
    }
  }
  lockstep_ = headless_ || o_.lockstep;
  if (headless_ && o_.end.exit_after_s <= 0 && o_.pen_script.empty() && !o_.demo_script)
    return makeError("run", "headless with the mouse as the pen would never end: give --exit-after or a pen script");
  if (!(o_.fps > 0)) return makeError("run", "--fps must be > 0");
  return rack_.checkNames();
}

// The preset, the task, its bur and the tooth it names (or --tooth and --level).
Status Simulator::loadPresetAndTask() {
  model_.params = defaultSimParams();
  model_.looks = defaultLookParams();
  if (!o_.params.empty()) {
    auto p = ui::loadPreset(o_.params);
    if (!p) return p.error();
    model_.params = std::move(p->sim);
    model_.looks = std::move(p->looks);
  }
  auto task = builtinTask(o_.task);
  if (!task) return task.error();
  model_.task = std::move(*task);
  model_.task_source = o_.task;
  model_.drill_name = o_.bur.empty() ? model_.task->drill_tool : o_.bur;
  auto tooth = ToothChoice::atStart(o_.tooth, o_.level, model_.task->tooth, model_.task->level);
  if (!tooth) return tooth.error();
  model_.tooth = *tooth;
  return Ok{};
}

// The pens: hardware ones map their workspace around the tool's start, turned with the camera; a
// script or the guide's path read first, since the rack's pens play them.
Status Simulator::setUpPens() {
  RackPlacement at;
  at.drill_start = drillStartGrip(model_.box, 3.0);
  at.mirror_start = mirrorGrip(model_.box, render::fromGlm(camera_.eye()));
  const render::CameraBasis basis = camera_.basis();
  at.screen = Quat::fromAxes(render::fromGlm(basis.right), render::fromGlm(basis.up), -render::fromGlm(basis.forward));
  if (Status st = setUpScript(at.mirror_start); !st) return st;
  if (!o_.guide.empty()) {
    auto guide = loadGuidePath(o_.guide, o_.guide_settings);
    if (!guide) return makeError("--guide", guide.message());
    model_.guide = std::move(*guide);
    // A path cut on another tooth leads the bur through other tissue: allowed, but said.
    if (model_.guide->source_tooth_hash != volumeHashHex(model_.initial.voxels, model_.initial.frame))
      noteWarning("--guide " + shownPath(o_.guide) + " was recorded on another tooth (" + model_.guide->source_tooth_hash + ")");
  }
  // A pen failing, leaving or coming back goes into the session being recorded, if any.
  rack_.onPenChange([this](PenRole pen, const std::string& state, const std::string& why) {
    if (SessionRecorder* recorder = segments_.recorder()) recorder->noteDevice(pen, state, why);
  });
  const PenPath* script = model_.script ? &*model_.script : nullptr;
  if (Status st = rack_.open(script, model_.mirror_tool.has_value(), at, model_.params.device, lockstep_); !st) return st;
  if (rack_.hasVirtualPen()) {
    pens_ = std::make_unique<ui::PenInput>(camera_, rack_.virtualPen(PenRole::Drill), rack_.virtualPen(PenRole::Mirror));
    pens_->reset(PenRole::Drill, at.drill_start);
    if (model_.mirror_tool) pens_->reset(PenRole::Mirror, at.mirror_start);
  }
  input_.setPens(pens_.get());
  const ToolSpec* mirror_spec = model_.mirror_tool ? findTool(model_.mirror_name) : nullptr;
  input_.setMirrorDiameter(mirror_spec ? mirror_spec->head_diameter_mm : 0.0);
  return Ok{};
}

// The frames' device, window and panel, and the tooth's first surfaces on it.
Status Simulator::setUpPainter() {
  PainterOptions po;
  po.headless = headless_;
  po.width = o_.frames.width;
  po.height = o_.frames.height;
  po.vsync = o_.frames.vsync;
  po.device = o_.frames.device;
  po.panel = o_.frames.ui;
  po.normals = model_.looks.view.normals;
  po.mesher = o_.frames.mesher;
  auto painter = FramePainter::create(po, [this](ui::Window& w) { input_.attach(w); });
  if (!painter) return painter.error();
  painter_ = std::move(*painter);
  input_.setPanel(painter_->panel());
  out_.device = painter_->context().device().name;
  out_.windowed = !headless_;
  const ToothVolume& tooth = model_.initial;
  if (o_.frames.progressive.value_or(!headless_)) {
    // The coarse copies now, the full copy region by region over the first frames (Simulator::frame).
    const auto t0 = Clock::now();
    if (Status st = painter_->surfaces().beginBuild(state_.view.voxels, state_.view.frame); !st) return st;
    std::printf("tooth: %s, level %d, %.4f mm voxels; coarse copies in %.1f ms on %s, full detail follows\n",
                model_.tooth.name().c_str(), tooth.frame.level, tooth.frame.voxel_mm,
                std::chrono::duration<double, std::milli>(Clock::now() - t0).count(), out_.device.c_str());
    if (!painter_->surfaces().done()) progress_.start("full detail");
  } else {
    gpu::SurfaceUpdateStats stats;
    if (Status st = painter_->surfaces().build(state_.view.voxels, &stats); !st) return st;
    stats_.final_triangles = stats.triangles;
    std::printf("tooth: %s, level %d, %.4f mm voxels; surface %llu triangles in %.1f ms on %s\n", model_.tooth.name().c_str(),
                tooth.frame.level, tooth.frame.voxel_mm, static_cast<unsigned long long>(stats.triangles), stats.total_ms,
                out_.device.c_str());
  }
  return Ok{};
}

// What the panel shows at the start.
void Simulator::setUpPanel() {
  presets_ = std::make_unique<ui::PresetStore>(ui::defaultPresetDirectory());
  ui_.params = model_.params;
  ui_.looks = model_.looks;
  ui_.bur = model_.drill_name;
  ui_.course = ui::listCourse(o_.course);
  if (!ui_.course.error.empty()) note(ui_.course.error);
  showTask();
  ui_.teacher = o_.teacher;
  ui_.pedal_present = model_.script.has_value() || rack_.hasPedal();
  ui_.presets = presets_->list();
  ui_.force.max_force_n = model_.params.device.max_force_n;
  setUpStudent();  // the student's records in the picker, or the first-run prompt (simulator_review.cpp)
}

}  // namespace dentsim::app
