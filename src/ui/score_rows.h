// The score screen's rows, made from a score's parts and volumes as the scorer returns them (no JSON is read back).
#pragma once

#include "eval/cut_score.h"
#include "ui/param_panel.h"

namespace dentsim::ui {

// Total and rows: each part "49.8 / 50" (or "not scored"; a crown's criteria lead with their detail,
// "13.3 deg mesiodistal (10-20 deg) within  15.0 / 15"), each deduction scored "-1.2", then the
// caries left (caries removal) and whether the pulp is exposed. The picture's size is the caller's.
ScoreSummary scoreSummaryOf(const SessionScore& score);

}  // namespace dentsim::ui
