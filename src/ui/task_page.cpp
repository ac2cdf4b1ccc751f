// The Task page: pickers over UiState::course, the task in use, teacher mode.
#include "ui/task_page.h"

#include <cstdio>
#include <string>

namespace dentsim::ui::panel {
namespace {

// The line a picker shows for the tooth in use: its entry's label, else the file's name.
std::string toothLabel(const UiState& s) {
  for (const ToothChoice& t : s.course.teeth)
    if (t.path == s.tooth && (!t.path.empty() || t.level == s.level)) return t.label;
  if (s.tooth.empty()) return "built-in molar, level " + std::to_string(s.level);
  const size_t slash = s.tooth.find_last_of('/');
  return slash == std::string::npos ? s.tooth : s.tooth.substr(slash + 1);
}

std::string taskLabel(const UiState& s) {
  for (const TaskChoice& t : s.course.tasks)
    if (t.source == s.task) return t.label;
  return s.task;
}

// The student's record at the task in use, under the picker: what the list shows for it, said in full.
void taskRecordLine(const UiState& s) {
  for (const TaskChoice& t : s.course.tasks) {
    if (t.source != s.task || t.attempts == 0) continue;
    char text[160];
    std::snprintf(text, sizeof text, "your best %.1f in %d attempt%s", t.best.value_or(0.0), t.attempts,
                  t.attempts == 1 ? "" : "s");
    std::string line = text;
    if (t.pass_mark) {
      std::snprintf(text, sizeof text, "; pass mark %.0f: %s", *t.pass_mark, t.passed ? "passed" : "not yet passed");
      line += text;
    }
    ImGui::TextUnformatted(line.c_str());
    return;
  }
}

// The tooth: the built-in molar at its levels, the course folder's teeth, or any .dvol by its path.
void toothPicker(const Frame& f) {
  UiState& s = f.state;
  ImGui::TextDisabled("tooth");
  const Probe probe{f};
  const bool opened = ImGui::BeginCombo("tooth", toothLabel(s).c_str());
  probe.record("tooth");
  if (opened) {
    for (size_t i = 0; i < s.course.teeth.size(); ++i) {
      const ToothChoice& t = s.course.teeth[i];
      const bool current = t.path == s.tooth && (!t.path.empty() || t.level == s.level);
      if (ImGui::Selectable(t.label.c_str(), current) && !current) {
        s.tooth = t.path;
        if (t.path.empty()) s.level = t.level;
        f.actions.tooth_changed = true;
      }
      f.record("tooth.item." + std::to_string(i));
      if (!t.path.empty()) tooltip(t.path.c_str());
    }
    ImGui::EndCombo();
  }
  // A fixed buffer: Debian's libimgui has no std::string InputText.
  char buf[512] = {};
  s.tooth_path.copy(buf, sizeof buf - 1);
  const Probe path_probe{f};
  if (ImGui::InputTextWithHint("##tooth_path", "any .dvol by its path", buf, sizeof buf)) s.tooth_path = buf;
  path_probe.record("tooth_path");
  ImGui::SameLine();
  ImGui::BeginDisabled(s.tooth_path.empty());
  if (ImGui::Button("Open")) {
    s.tooth = s.tooth_path;
    f.actions.tooth_changed = true;
  }
  f.record("open_tooth");
  ImGui::EndDisabled();
  errorLine(s.tooth_error);
}

// The task: the built-in ones and the course folder's files; a file that does not load is listed
// with its error and starts nothing.
void taskPicker(const Frame& f) {
  UiState& s = f.state;
  ImGui::Spacing();
  ImGui::TextDisabled("task");
  const Probe probe{f};
  const bool opened = ImGui::BeginCombo("task", taskLabel(s).c_str());
  probe.record("task");
  if (opened) {
    for (size_t i = 0; i < s.course.tasks.size(); ++i) {
      const TaskChoice& t = s.course.tasks[i];
      const std::string line = taskPickerLine(t);  // with the student's best, attempts and passed
      if (ImGui::Selectable(line.c_str(), t.source == s.task)) {
        if (!t.error.empty()) {
          s.task_error = t.error;
        } else if (t.source != s.task) {
          s.task = t.source;
          f.actions.task_changed = true;
        }
      }
      f.record("task.item." + std::to_string(i));
      tooltip(t.error.empty() ? t.title.c_str() : t.error.c_str());
    }
    ImGui::EndCombo();
  }
  taskRecordLine(s);
  if (!s.task_title.empty()) ImGui::TextWrapped("%s", s.task_title.c_str());
  if (!s.task_instructions.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("%s", s.task_instructions.c_str());
    ImGui::PopStyleColor();
  }
  errorLine(s.task_error);
}

// Teacher mode: the current segment becomes the task file's ideal.
void teacherSection(const Frame& f) {
  UiState& s = f.state;
  ImGui::Spacing();
  ImGui::Separator();
  ImGui::Checkbox("teacher mode", &s.teacher);
  f.record("teacher");
  if (!s.teacher) return;
  const char* why_not = !s.task_is_file        ? "A built-in task cannot take an ideal: pick a task file from the course folder."
                        : !s.segment_recorded ? "This segment is not being recorded: press Reset to start a recorded one."
                                              : nullptr;
  ImGui::BeginDisabled(why_not != nullptr);
  f.actions.record_ideal |= ImGui::Button("Record as ideal");
  f.record("record_ideal");
  ImGui::EndDisabled();
  tooltip(why_not ? why_not : "Ends this segment and makes it the task's ideal: every student is scored against it.");
  if (!s.ideal_status.empty()) ImGui::TextWrapped("%s", s.ideal_status.c_str());
}

}  // namespace

void taskPage(const Frame& f) {
  toothPicker(f);
  taskPicker(f);
  teacherSection(f);
}

}  // namespace dentsim::ui::panel
