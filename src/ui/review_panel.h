// The Score page's review (this attempt's replay, the professional's ghost beside it, a retry with guidance, this attempt against the last ones) and the first-run prompt for the student's name.
//
// Immediate mode like the rest of the panel (ui/param_panel.h): the sections edit UiState and raise
// PanelActions::review; the app (app/simulator_review.cpp) carries them out. Widget keys for tests:
// "review.replay", "review.ghost", "review.guided", "review.table"; the prompt's "student.name" and
// "student.ok".
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "eval/attempt_reader.h"
#include "ui/panel_widgets.h"

namespace dentsim::ui {

// One row of the comparison: the total or one part, as it counted toward the total (a component's
// points earned, a deduction's points taken off as a negative number), in each earlier attempt and
// in this one, and the change from the last earlier attempt (positive: better).
struct CompareRow {
  std::string label;                         // "total", or the part's name ("undercut", "time")
  std::vector<std::optional<double>> before; // one per earlier attempt, oldest first; none: not scored then
  std::optional<double> now;                 // none: not scored now
  std::optional<double> change;              // now less the last earlier value; none when either is missing
};

// The total, then each of this attempt's parts in its order, then parts only earlier attempts had.
std::vector<CompareRow> compareRows(const ClassAttempt& now, const std::vector<ClassAttempt>& before);

}  // namespace dentsim::ui

namespace dentsim::ui::panel {

// The review buttons, each disabled with its reason as a tooltip, then the comparison table.
void reviewSection(const Frame& f);

// The small window that asks a student's name on the first run (UiState::student.ask), below the
// view; the name goes out as PanelActions::review.name_given.
void studentPrompt(const Frame& f);

}  // namespace dentsim::ui::panel
