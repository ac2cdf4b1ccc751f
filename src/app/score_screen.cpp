// Scoring the simulator's cut for the score screen and its files.
#include "app/score_screen.h"

#include <filesystem>
#include <optional>

#include "io/session_file.h"
#include "ui/score_rows.h"
#include "volume/tooth_file.h"

namespace dentsim::app {

Result<ScreenScore> scoreForScreen(const Task& task, const ToothVolume& initial, ToothVolume& final_, const ScoredCut& cut,
                                   const std::string& out) {
  auto path = [&](const char* name) { return (std::filesystem::path(out) / name).string(); };
  final_.voxels.compact();
  std::optional<SessionRecording> session;
  ScoreFiles files = scoreFiles(cut.initial_file.empty() ? "initial.dvol" : cut.initial_file, "final.dvol", "");
  files.no_session_reason = cut.no_session_reason;
  if (!cut.session_file.empty()) {
    auto read = readSessionFile(cut.session_file);
    if (read) {
      session = std::move(*read);
      files = scoreFiles(cut.initial_file, path("final.dvol"), cut.session_file);
    } else {
      files.no_session_reason = read.message();
    }
  }
  auto score = scoreCut(task, initial, final_, nullptr, session ? &*session : nullptr, files);
  if (!score) return score.error();
  ScreenScore s;
  s.picture = scorePicture(task, initial, final_, *score, nullptr);
  s.panel = ui::scoreSummaryOf(*score);
  s.panel.image_width = s.picture.width;
  s.panel.image_height = s.picture.height;
  s.total = score->total;
  s.summary = score->summary;
  s.warnings = score->warnings;
  s.report = score->report;
  if (!out.empty()) {
    if (Status st = saveTooth(path("final.dvol"), final_); !st) return st.error();
    if (Status st = writeScoreReport(path("score.json"), score->report); !st) return st.error();
    if (Status st = writePng(path("score.png"), s.picture); !st) return st.error();
    for (const char* f : {"final.dvol", "score.json", "score.png"}) s.written.push_back(path(f));
  }
  return s;
}

}  // namespace dentsim::app
