// The simulator's score screen: the cut scored as `dentsim score` would score the saved files, the panel's rows, the picture, and the files beside the session.
#pragma once

#include <string>
#include <vector>

#include "core/result.h"
#include "eval/cut_score.h"
#include "io/png_file.h"
#include "ui/param_panel.h"

namespace dentsim::app {

struct ScreenScore {
  ui::ScoreSummary panel;             // total and rows, with the picture's size
  RgbImage picture;                   // the red/blue score picture
  double total = 0.0;
  std::string summary;                // the terminal's line
  std::vector<std::string> warnings;
  std::vector<std::string> written;   // final.dvol, score.json and score.png in `out`
};

// Scores `final_` against `initial`. It is compacted first, the layout a saved and reloaded tooth
// has, so that the picture equals the one `replay` and `score` draw from the files, pixel for
// pixel. The session's statistics are used when one segment holds the whole cut (`segments` == 1
// and `out` holds session.dses); with an output folder the files are written there.
Result<ScreenScore> scoreForScreen(const Task& task, const ToothVolume& initial, ToothVolume& final_, int segments,
                                   const std::string& out);

}  // namespace dentsim::app
