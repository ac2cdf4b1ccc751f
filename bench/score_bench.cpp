// The score benchmark: `task validate`'s attempts at each task, and their JSON, Markdown and SVG.
#include "bench/score_bench.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "bench/svg_plot.h"

namespace dentsim::bench {

Result<ScoreBenchResult> runScoreBench(const ToothVolume& molar, const std::vector<Task>& tasks,
                                       const ValidationSettings& settings,
                                       const std::function<void(const std::string&)>& progress) {
  ScoreBenchResult out;
  out.level = molar.voxels.level();
  out.voxel_mm = molar.frame.voxel_mm;
  for (const Task& task : tasks) {
    ValidationSettings s = settings;
    s.time_from_professional = settings.time_from_professional || task.level != out.level;
    auto v = validateTask(task, molar, s, progress);
    if (!v) return v.error();
    out.tasks.push_back(std::move(*v));
  }
  return out;
}

std::vector<std::string> scoreBenchFailures(const ScoreBenchResult& result) {
  std::vector<std::string> out;
  for (const TaskValidation& v : result.tasks)
    for (const std::string& f : v.failures) out.push_back(v.task.name + ": " + f);
  return out;
}

nlohmann::ordered_json scoreBenchJson(const ScoreBenchResult& result) {
  nlohmann::ordered_json j;
  j["benchmark"] = "scores";
  j["level"] = result.level;
  j["voxel_mm"] = result.voxel_mm;
  nlohmann::ordered_json tasks = nlohmann::ordered_json::array();
  for (const TaskValidation& v : result.tasks) tasks.push_back(validationJson(v));
  j["tasks"] = std::move(tasks);
  j["valid"] = scoreBenchFailures(result).empty();
  return j;
}

std::string scoreBenchMarkdown(const ScoreBenchResult& result) {
  std::ostringstream o;
  char voxel[32];
  std::snprintf(voxel, sizeof voxel, "%.4f", result.voxel_mm);
  o << "# Scores of scripted attempts (level " << result.level << ", " << voxel << " mm voxels)\n\n";
  for (const TaskValidation& v : result.tasks) o << validationMarkdown(v);
  return o.str();
}

std::string scoreBenchSvg(const ScoreBenchResult& result) {
  // One group of bars per attempt, one bar per task; an attempt a task did not run scores no bar.
  std::vector<std::string> categories;
  for (const TaskValidation& v : result.tasks)
    for (const ValidatedAttempt& a : v.attempts)
      if (std::find(categories.begin(), categories.end(), attemptName(a.attempt)) == categories.end())
        categories.push_back(attemptName(a.attempt));
  std::vector<BarSeries> series;
  double expert_min = 100.0;
  for (const TaskValidation& v : result.tasks) {
    BarSeries bars{v.task.name, std::vector<double>(categories.size(), 0.0)};
    for (const ValidatedAttempt& a : v.attempts) {
      bars.values[size_t(std::find(categories.begin(), categories.end(), attemptName(a.attempt)) - categories.begin())] = a.total;
      if (a.attempt == Attempt::Expert) expert_min = std::min(expert_min, a.total);
    }
    series.push_back(std::move(bars));
  }
  return svgBarChart("Scores of scripted attempts, level " + std::to_string(result.level), "score (of 100)", categories,
                     series, 100.0, 20.0, expert_min - 20.0, "expert - 20");
}

}  // namespace dentsim::bench
