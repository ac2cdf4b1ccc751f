// The simulator's help for the student: the controls overlay (first use, F1, Help), "bring to tooth", guidance from the panel with its pull on the overlay, and scripted window input.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "app/simulator_state.h"
#include "core/config_dir.h"
#include "core/text_escape.h"
#include "model/tool_generator.h"
#include "sim/bring_to_tooth.h"
#include "volume/volume_hash.h"

namespace dentsim::app {
namespace {

constexpr double kBringClearanceMm = 0.3;  // "just above": three presses of the lower key

// Where the overlay's "seen" mark lives: the user's config folder, beside the presets. Empty: no
// home, so the overlay shows every run (it cannot remember).
std::string controlsSeenPath() {
  const std::string dir = userConfigDir();
  return dir.empty() ? "" : dir + "/controls-seen";
}

std::string burLine(const std::string& name) {
  const ToolSpec* spec = findTool(name);
  if (!spec) return name;
  char size[48];
  std::snprintf(size, sizeof size, ", head %.1f mm", spec->head_diameter_mm);
  return name + " (" + toolKindName(spec->kind) + size + ")";
}

}  // namespace

double Simulator::secondsSinceStart() const {
  return std::chrono::duration<double>(Clock::now() - stats_.run_t0).count();
}

Status Simulator::setUpHelp() {
  auto inputs = parseScriptedInputs(o_.input);
  if (!inputs) return inputs.error();
  inputs_ = std::move(*inputs);
  if (o_.help != "auto" && o_.help != "show" && o_.help != "hide")
    return makeError("--help-overlay", "\"" + o_.help + "\" is not auto, show or hide");
  const bool virtual_drill = rack_.virtualPen(PenRole::Drill) != nullptr;
  ui_.help.input = model_.script ? ui::DrillInput::Script : virtual_drill ? ui::DrillInput::Mouse : ui::DrillInput::HapticPen;
  ui_.help.device = model_.script ? "the pen script" : virtual_drill ? "the mouse and keys" : o_.devices.drill_pen;
  ui_.help.bur = burLine(model_.drill_name);
  ui_.help.bring_available = ui_.help.input == ui::DrillInput::Mouse && model_.task.has_value();
  // First use: a student at the mouse who has not closed it before. A script or a haptic pen run
  // is a demo or a student who has been shown the device; Help and F1 still show it.
  const std::string seen = controlsSeenPath();
  // Headless, nobody would read it (and a benchmark's frames would draw it).
  const bool first_use = ui_.help.input == ui::DrillInput::Mouse && !headless_ &&
                         (seen.empty() || !std::filesystem::exists(seen));
  ui_.help.shown = o_.help == "show" || (o_.help == "auto" && first_use);
  // Guidance: --guide's path, else the task's professional (its recorded session or its script).
  ui_.guidance.on = !o_.guide.empty();
  ui_.guidance.stiffness_n_per_mm = o_.guide_settings.stiffness_n_per_mm;
  ui_.guidance.max_n = o_.guide_settings.max_force_n;
  helpNewTooth();
  return Ok{};
}

void Simulator::helpNewTooth() {
  pro_pen_.reset();
  pro_pen_tried_ = false;
  if (o_.guide.empty()) {
    panel_guide_.reset();
    panel_guide_tried_ = false;
  }
  ui_.guidance.available = model_.guide.has_value() || (model_.task.has_value() && model_.tooth.builtin()) ||
                           (model_.task && model_.task->ideal);
  ui_.guidance.source = model_.guide ? model_.guide->source
                        : model_.task && model_.task->ideal && model_.task->ideal->kind == IdealKind::Session
                            ? model_.task->ideal->path
                            : "the task's scripted professional";
  if (!ui_.guidance.available) ui_.guidance.source.clear();
  ui_.help.bring_available = ui_.help.input == ui::DrillInput::Mouse && model_.task.has_value();
}

const PenPath* Simulator::professionalPenPath() {
  if (pro_pen_tried_) return pro_pen_ ? &*pro_pen_ : nullptr;
  pro_pen_tried_ = true;
  if (!model_.task) return nullptr;
  auto path = taskAttemptScript(Attempt::Expert);
  if (!path) {
    noteWarning("the task's professional path: " + path.message());
    return nullptr;
  }
  pro_pen_ = std::move(*path);
  return &*pro_pen_;
}

void Simulator::bringToTooth() {
  if (!pens_ || !model_.drill_tool || ui_.help.input != ui::DrillInput::Mouse) return;
  const PenPath* pro = professionalPenPath();
  const std::optional<BringToTooth> at =
      pro ? dentsim::bringToTooth(*pro, *model_.drill_tool, state_.view.voxels, state_.view.frame, kBringClearanceMm)
          : std::nullopt;
  if (!at) {
    note("bring to tooth: the task's professional path does not reach this tooth; move the bur with the mouse");
    return;
  }
  pens_->reset(PenRole::Drill, at->grip);
  pens_->setActive(PenRole::Drill);
  char text[160];
  std::snprintf(text, sizeof text, "the bur is %.1f mm above where the work starts: S lowers it 0.1 mm a press",
                kBringClearanceMm);
  note(text);
}

const GuidePath* Simulator::segmentGuide() {
  if (!ui_.guidance.on || !ui_.guidance.available) return nullptr;
  GuideSettings settings = o_.guide_settings;
  settings.stiffness_n_per_mm = ui_.guidance.stiffness_n_per_mm;
  if (model_.guide) {
    model_.guide->settings = settings;
    return &*model_.guide;
  }
  if (!panel_guide_tried_) {
    panel_guide_tried_ = true;
    if (model_.task && model_.task->ideal && model_.task->ideal->kind == IdealKind::Session) {
      auto g = loadGuidePath(model_.task->ideal->path, settings);
      if (g) panel_guide_ = std::move(*g);
      else noteWarning("guidance: " + g.message());
    } else if (const PenPath* pro = professionalPenPath()) {
      panel_guide_ = guidePathFromScript(*pro, settings, "the task's scripted professional", model_.task->name,
                                         volumeHashHex(model_.initial.voxels, model_.initial.frame));
    }
  }
  if (!panel_guide_) return nullptr;
  panel_guide_->settings = settings;
  return &*panel_guide_;
}

void Simulator::handleHelpActions(const ui::PanelActions& actions) {
  if (actions.bring_to_tooth) bringToTooth();
  if (actions.help_closed) {
    const std::string seen = controlsSeenPath();
    if (seen.empty()) return;
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(seen).parent_path(), ec);
    std::ofstream mark(seen);
    mark << "the controls overlay was closed; dentsim shows it again with Help or F1\n";
    if (!mark) note("could not write " + seen + ": the controls will show again next time");
  }
}

void Simulator::showGuidePull(const HapticState& state, VkExtent2D extent) {
  ui_.guidance.active = state.guided;
  const Vec3 pull = state.guide_n;
  ui_.guidance.pull_n = norm(pull);
  if (!state.guided || ui_.guidance.pull_n <= 0.0 || extent.width == 0 || extent.height == 0) {
    ui_.guidance.pull_px[0] = ui_.guidance.pull_px[1] = 0.0f;
    return;
  }
  // The arrow's direction on screen: the tip and a point 1 mm along the pull, projected.
  const ToolState& drill = state.tools[size_t(PenRole::Drill)];
  const Vec3 tip = drill.tool.position;
  auto project = [&](const Vec3& p, float out[2]) {
    const glm::vec4 c = camera_.projection(float(extent.width) / float(extent.height)) * camera_.view() *
                        glm::vec4(render::toGlm(p), 1.0f);
    if (c.w <= 0.0f) return false;
    out[0] = (c.x / c.w * 0.5f + 0.5f) * float(extent.width) - float(sceneShiftPx());
    out[1] = (c.y / c.w * 0.5f + 0.5f) * float(extent.height);
    return true;
  };
  float a[2], b[2];
  if (!project(tip, a) || !project(tip + pull * (1.0 / ui_.guidance.pull_n), b)) return;
  const float dx = b[0] - a[0], dy = b[1] - a[1], len = std::sqrt(dx * dx + dy * dy);
  ui_.guidance.tip_px[0] = a[0];
  ui_.guidance.tip_px[1] = a[1];
  ui_.guidance.pull_px[0] = len > 1e-3f ? dx / len : 0.0f;
  ui_.guidance.pull_px[1] = len > 1e-3f ? dy / len : 0.0f;
}

bool Simulator::scriptClick(const std::string& widget, bool down) {
  ui::ImGuiLayer* panel = painter_->panel();
  const auto r = rects_.find(widget);
  if (!panel || r == rects_.end()) return false;
  panel->scriptMouse(0.5f * (r->second.min_x + r->second.max_x), 0.5f * (r->second.min_y + r->second.max_y), down);
  return true;
}

Status Simulator::feedScriptedInput() {
  // A frame the panel lays out twice (drawPanel) would spend the scripted mouse on its unseen
  // first layout: a click waits for the next frame.
  const bool relayout = state_.panel_relayout;
  // A click's second frame: the button let go where it was pressed.
  if (!click_widget_.empty()) {
    if (relayout) return Ok{};
    scriptClick(click_widget_, false);
    click_widget_.clear();
    return Ok{};
  }
  // The frame's time, not the loop's: a stopped segment holds loop time still, and an event that
  // waited for it (the click on Reset after Stop) would never come. In lockstep the two agree while
  // a segment runs.
  const double t = lockstep_ ? double(out_.frames) / o_.fps : secondsSinceStart();
  while (next_input_ < inputs_.size() && inputs_[next_input_].t_s <= t) {
    if (inputs_[next_input_].kind == ScriptedInput::Kind::Click && relayout) break;
    const ScriptedInput& in = inputs_[next_input_++];
    switch (in.kind) {
      case ScriptedInput::Kind::Key:
        input_.onKey(in.key, GLFW_PRESS, in.mods);
        input_.onKey(in.key, GLFW_RELEASE, in.mods);
        break;
      case ScriptedInput::Kind::Wheel: input_.scroll(in.dy, in.mods); break;
      case ScriptedInput::Kind::Drag: input_.dragBy(in.dx, in.dy, in.mods); break;
      case ScriptedInput::Kind::Click:
        if (!scriptClick(in.widget, true))
          return makeError("--input", "\"" + escapeControl(in.text) + "\": no widget \"" + escapeControl(in.widget) + "\" on the panel at " +
                                          std::to_string(t) + " s");
        click_widget_ = in.widget;
        return Ok{};  // one click a frame: the next events wait for its release
    }
  }
  return Ok{};
}

}  // namespace dentsim::app
