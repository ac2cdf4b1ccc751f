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
  nlohmann::ordered_json report;      // the "dentsim-score" report (the learning record reads it)
};

// The recorded files a score may use: the session that holds the whole cut, when one does.
struct ScoredCut {
  std::string initial_file;       // the saved tooth the cut started from; empty: none saved
  std::string session_file;       // the one session holding the whole cut; empty: none
  std::string no_session_reason;  // why there is none ("the cut spans 3 segments, ...")
};

// Scores `final_` against `initial`. It is compacted first, the layout a saved and reloaded tooth
// has, so that the picture equals the one `replay` and `score` draw from the files, pixel for
// pixel. The session's statistics are used when `cut` names one; with an output folder the files
// (final.dvol, score.json, score.png) are written there.
Result<ScreenScore> scoreForScreen(const Task& task, const ToothVolume& initial, ToothVolume& final_, const ScoredCut& cut,
                                   const std::string& out);

}  // namespace dentsim::app
