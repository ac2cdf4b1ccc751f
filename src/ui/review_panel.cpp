// The Score page's review buttons and comparison table, and the first-run name prompt.
#include "ui/review_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "io/learning_config.h"

namespace dentsim::ui {
namespace {

// What a part added to the total: a component's points, a deduction's points taken off.
std::optional<double> contribution(const AttemptPart& p) {
  if (!p.points) return std::nullopt;
  return p.deduction ? -*p.points : *p.points;
}

std::optional<double> partValue(const ClassAttempt& a, const std::string& name) {
  for (const AttemptPart& p : a.parts)
    if (p.name == name) return contribution(p);
  return std::nullopt;
}

}  // namespace

std::vector<CompareRow> compareRows(const ClassAttempt& now, const std::vector<ClassAttempt>& before) {
  std::vector<std::string> names;
  for (const AttemptPart& p : now.parts) names.push_back(p.name);
  for (const ClassAttempt& b : before)
    for (const AttemptPart& p : b.parts)
      if (std::find(names.begin(), names.end(), p.name) == names.end()) names.push_back(p.name);
  std::vector<CompareRow> rows;
  auto finish = [&](CompareRow r) {
    if (r.now && !r.before.empty() && r.before.back()) r.change = *r.now - *r.before.back();
    rows.push_back(std::move(r));
  };
  CompareRow total{"total", {}, now.score, std::nullopt};
  for (const ClassAttempt& b : before) total.before.push_back(b.score);
  finish(std::move(total));
  for (const std::string& n : names) {
    CompareRow r{n, {}, partValue(now, n), std::nullopt};
    for (const ClassAttempt& b : before) r.before.push_back(partValue(b, n));
    finish(std::move(r));
  }
  return rows;
}

}  // namespace dentsim::ui

namespace dentsim::ui::panel {
namespace {

void valueCell(const std::optional<double>& v) {
  if (!v) {
    ImGui::TextDisabled("-");
    return;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", *v);
  ImGui::TextUnformatted(text);
}

// The change as "+2.5" in green or "-1.0" in red; a change under a twentieth of a point is none.
void changeCell(const std::optional<double>& c) {
  if (!c) return;
  char text[32];
  if (std::fabs(*c) < 0.05) {
    ImGui::TextDisabled("=");
    return;
  }
  std::snprintf(text, sizeof text, "%+.1f", *c);
  ImGui::TextColored(*c > 0 ? ImVec4(0.30f, 0.85f, 0.35f, 1.0f) : ImVec4(0.95f, 0.35f, 0.30f, 1.0f), "%s", text);
}

// One button of the review, disabled with its reason as the tooltip.
bool reviewButton(const Frame& f, const char* label, const char* key, const ReviewButton& b, const char* what) {
  ImGui::BeginDisabled(!b.available);
  const bool pressed = ImGui::Button(label);
  f.record(key);
  ImGui::EndDisabled();
  tooltip(b.available ? what : b.why_not.c_str());
  return pressed && b.available;
}

// This attempt against the last ones at the task: what improved, what did not.
void compareTable(const Frame& f) {
  const ReviewView& r = f.state.review;
  if (!r.now) return;
  ImGui::Spacing();
  ImGui::TextDisabled("this attempt against your last ones");
  if (r.before.empty()) {
    ImGui::TextWrapped("%s", r.records_note.empty() ? "Your first recorded attempt at this task." : r.records_note.c_str());
    return;
  }
  const std::vector<CompareRow> rows = compareRows(*r.now, r.before);
  const int columns = 3 + int(r.before.size());
  if (!ImGui::BeginTable("review.compare", columns, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) return;
  // Widths given, not measured: a table measures its columns a frame late, and a screenshot of the
  // frame a score first shows would catch it at one character wide.
  // Six columns in the panel's 380 px: a longer part name is cut, a number never.
  const float number = ImGui::CalcTextSize("-100.0").x;
  ImGui::TableSetupColumn("part", ImGuiTableColumnFlags_WidthFixed, ImGui::CalcTextSize("undercut_").x);
  for (size_t i = 0; i < r.before.size(); ++i) {
    // Counted back from this attempt: "-1" is the one just before it.
    const std::string head = std::to_string(-int(r.before.size() - i));
    ImGui::TableSetupColumn(head.c_str(), ImGuiTableColumnFlags_WidthFixed, number);
  }
  ImGui::TableSetupColumn("now", ImGuiTableColumnFlags_WidthFixed, number);
  ImGui::TableSetupColumn("+/-", ImGuiTableColumnFlags_WidthFixed, number);
  ImGui::TableHeadersRow();
  for (const CompareRow& row : rows) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(row.label.c_str());
    for (const std::optional<double>& v : row.before) {
      ImGui::TableNextColumn();
      valueCell(v);
    }
    ImGui::TableNextColumn();
    valueCell(row.now);
    ImGui::TableNextColumn();
    changeCell(row.change);
  }
  ImGui::EndTable();
  f.record("review.table");
}

}  // namespace

void reviewSection(const Frame& f) {
  const ReviewView& r = f.state.review;
  ImGui::Spacing();
  ImGui::Separator();
  ImGui::TextDisabled("review");
  ReviewActions& a = f.actions.review;
  a.replay |= reviewButton(f, "Replay", "review.replay", r.replay,
                           "Plays this attempt again in this window, with its timeline and speeds.");
  ImGui::SameLine();
  a.replay_ghost |= reviewButton(f, "Replay with the ghost", "review.ghost", r.ghost,
                                 "Plays this attempt with the professional's tools beside yours, at the same task time.");
  a.retry_guided |= reviewButton(f, "Retry with guidance", "review.guided", r.guided,
                                 "Starts again on the uncut tooth, a spring pulling the bur along the professional's path.");
  compareTable(f);
}

void studentPrompt(const Frame& f) {
  StudentView& s = f.state.student;
  if (!s.ask) return;
  // Not modal, and it takes no keyboard until clicked: the keys and the mouse still drill, so a
  // student who ignores it loses nothing but the record. At the bottom of the view, where nothing
  // else is drawn, beside the panel.
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(display.x * 0.5f - 190.0f, display.y - 10.0f), ImGuiCond_Always, ImVec2(0.5f, 1.0f));
  const ImGuiWindowFlags flags = ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoFocusOnAppearing;
  if (ImGui::Begin("Who is drilling?", nullptr, flags)) {
    ImGui::TextUnformatted("Your student number or login, so that your attempts are kept as yours:");
    // A fixed buffer: Debian's libimgui has no std::string InputText.
    char buf[kMaxStudentIdBytes + 1] = {};
    s.typed.copy(buf, sizeof buf - 1);
    ImGui::SetNextItemWidth(260.0f);
    const bool enter = ImGui::InputText("##student", buf, sizeof buf, ImGuiInputTextFlags_EnterReturnsTrue);
    s.typed = buf;
    f.record("student.name");
    ImGui::SameLine();
    ImGui::BeginDisabled(s.typed.empty());
    const bool ok = ImGui::Button("Keep");
    f.record("student.ok");
    ImGui::EndDisabled();
    if ((ok || enter) && !s.typed.empty()) f.actions.review.name_given = s.typed;
    errorLine(s.error);
    if (!s.where.empty()) {
      const std::string where = "kept for the next runs in " + s.where;
      ImGui::TextDisabled("%s", where.c_str());
    }
  }
  ImGui::End();
}

}  // namespace dentsim::ui::panel
