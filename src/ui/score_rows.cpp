// Formats a score's lines for the score screen.
#include "ui/score_rows.h"

#include <cstdio>

namespace dentsim::ui {

ScoreSummary scoreSummaryOf(const SessionScore& score) {
  ScoreSummary s;
  s.valid = true;
  s.total = score.total;
  s.total_max = score.total_max;
  char text[64];
  // The parts first, then the deductions that were scored: the lines come in that order.
  for (const ScoreLine& line : score.lines) {
    if (line.deduction) {
      if (!line.points) continue;
      std::snprintf(text, sizeof text, "-%.1f", *line.points);
    } else if (line.points) {
      std::snprintf(text, sizeof text, "%.1f / %d", *line.points, int(line.max));
    } else {
      std::snprintf(text, sizeof text, "not scored");
    }
    // A criterion graded against a range (a crown's) shows what was measured before its points.
    s.rows.push_back({line.name, line.detail.empty() ? std::string(text) : line.detail + "  " + text});
  }
  if (score.caries_remaining_mm3) {
    std::snprintf(text, sizeof text, "%.3f mm^3", *score.caries_remaining_mm3);
    s.rows.push_back({"caries left", text});
  }
  s.rows.push_back({"pulp exposed", score.pulp_exposed ? "yes" : "no"});
  return s;
}

}  // namespace dentsim::ui
