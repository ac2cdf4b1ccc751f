// The score benchmark: every attempt drilled, recorded and scored; the checks of gap and part; the JSON, Markdown and SVG.
#include "bench/score_bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "bench/svg_plot.h"
#include "eval/cut_score.h"
#include "eval/session_stats.h"
#include "io/session_file.h"
#include "sim/course_paths.h"
#include "sim/session_run.h"
#include "volume/volume_hash.h"

namespace dentsim::bench {

// ---- 1. running the attempts --------------------------------------------------------------------------

namespace {

// The parts of a report: each scored component's points, each deduction as negative points, and
// the pulp's cap as what it took off.
std::vector<std::pair<std::string, double>> reportParts(const nlohmann::ordered_json& report) {
  std::vector<std::pair<std::string, double>> parts;
  double sum = 0.0;
  for (const auto& [name, part] : report["components"].items())
    if (part["points"].is_number()) {
      parts.push_back({name, part["points"].get<double>()});
      sum += parts.back().second;
    }
  for (const auto& [name, part] : report["deductions"].items())
    if (part.contains("points") && part["points"].is_number()) {
      const double points = part["points"].get<double>();
      parts.push_back({name, points == 0.0 ? 0.0 : -points});  // no "-0.0" in the tables
      sum += parts.back().second;
    }
  // The pulp's cap: exposure for a cavity or caries removal, a chamber left closed for an access.
  for (const char* key : {"pulp_exposure", "pulp_unopened"}) {
    const auto& d = report["deductions"];
    if (d.contains(key) && d[key]["applied"].get<bool>())
      parts.push_back({"pulp cap", report["total"].get<double>() - std::clamp(sum, 0.0, report["total_max"].get<double>())});
  }
  return parts;
}

// One attempt drilled and recorded: the cut tooth and its session.
struct Drilled {
  std::string name;            // "<task>-<attempt>"
  ToothVolume tooth;
  SessionRecording session;
};

struct Runner {
  const ToothVolume& molar;
  const ScoreBenchSettings& settings;
  const SimParams params = defaultSimParams();

  Result<Drilled> drill(const Task& task, Attempt attempt) {
    const std::string name = task.name + "-" + attemptName(attempt);
    Result<PenPath> path = taskAttemptPath(exerciseOf(task), attempt, molar.voxels, molar.frame, params);
    if (!path) return makeError(name, path.message());
    Drilled d{name, molar, {}};
    SessionInfo info;
    info.task = task.name;
    ScriptedSessionOptions so;
    so.drill_tool = task.drill_tool;
    const std::string session_path = (std::filesystem::path(settings.work_dir) / (name + ".dses")).string();
    auto outcome = recordScriptedSession(d.tooth, params, *path, session_path, info, so);
    if (!outcome) return makeError(name, outcome.message());
    if (outcome->steps_lost > 0)  // a score from a session with gaps would not be the attempt's
      return makeError(name, "the recorder lost " + std::to_string(outcome->steps_lost) + " steps");
    auto session = readSessionFile(session_path);
    std::error_code ec;
    std::filesystem::remove(session_path, ec);
    if (!session) return session.error();
    d.session = std::move(*session);
    d.tooth.voxels.compact();
    return d;
  }

  Result<AttemptScore> score(const Task& task, Attempt attempt, const Drilled& d, const ToothVolume* ideal) {
    ScoreFiles files = scoreFiles("molar", d.name, d.name + ".dses");
    if (ideal) {
      files.ideal_spec = task.ideal;
      files.ideal_from = "task";
    }
    auto scored = scoreCut(task, molar, d.tooth, ideal, &d.session, files);
    if (!scored) return makeError(d.name, scored.message());
    if (!settings.picture_dir.empty()) {
      const std::string png = (std::filesystem::path(settings.picture_dir) / (d.name + ".png")).string();
      if (Status st = writeScoreImage(png, task, molar, d.tooth, *scored, ideal); !st) return st.error();
    }

    AttemptScore a;
    a.task = task.name;
    a.kind = task.kind;
    a.attempt = attempt;
    const nlohmann::ordered_json& r = scored->report;
    a.report = r;
    a.total = scored->total;
    a.total_max = scored->total_max;
    a.paper_total = r["paper_total"].get<double>();
    a.parts = reportParts(r);
    const auto& s = r["session"];
    a.elapsed_s = s["elapsed_s"].get<double>();
    a.max_force_n = s["max_force_n"].get<double>();
    a.mean_force_n = s["mean_force_n"].get<double>();
    const auto contact = s["contact_samples"].get<uint64_t>();
    a.force_over_percent = contact > 0 ? 100.0 * double(s["force_over"].get<uint64_t>()) / double(contact) : 0.0;
    const auto& v = r["volumes"];
    const double caries_initial = v["caries"]["initial_mm3"].get<double>();
    a.caries_removed_percent = caries_initial > 0 ? 100.0 * v["caries"]["removed_mm3"].get<double>() / caries_initial : 0.0;
    a.healthy_removed_mm3 = v["healthy"]["removed_mm3"].get<double>();
    a.healthy_outside_mm3 = v["healthy"]["container_removed_mm3"].get<double>();
    if (task.kind != TaskKind::Caries) {
      a.undercut_percent = r["components"]["undercut"]["percent_of_ideal"].get<double>();
      a.overcut_percent = r["components"]["overcut"]["percent_of_ideal"].get<double>();
    }
    a.pulp_exposed = r["pulp_exposed"].get<bool>();
    a.final_hash = volumeHashHex(d.tooth.voxels, d.tooth.frame);
    a.warnings = scored->warnings;
    return a;
  }
};

// The task's times from its expert's: the target at target_factor times it, nothing left at failure_factor times it.
Task timedFromExpert(Task task, double expert_s, const ScoreBenchSettings& s) {
  task.target_s = s.target_factor * expert_s;
  if (task.kind == TaskKind::Caries)
    task.failure_s = s.failure_factor * expert_s;
  else
    task.cavity.time_coefficient = 25.0 * 60.0 / ((s.failure_factor - s.target_factor) * expert_s);
  return task;
}

}  // namespace

Result<ScoreBenchResult> runScoreBench(const ToothVolume& molar, const std::vector<Task>& tasks,
                                       const ScoreBenchSettings& settings,
                                       const std::function<void(const std::string&)>& progress) {
  if (settings.work_dir.empty()) return makeError("bench scores", "no folder for the sessions");
  ScoreBenchResult out;
  out.level = molar.voxels.level();
  out.voxel_mm = molar.frame.voxel_mm;
  Runner runner{molar, settings};
  for (const Task& given : tasks) {
    const Task* base = &given;
    // A task's ideal is the same for every attempt: made once, from the task.
    std::optional<ToothVolume> ideal;
    if (base->ideal) {
      if (progress) progress(base->name + ": the ideal");
      std::vector<std::string> warnings;
      auto made = idealForTask(*base, molar, &warnings);
      if (!made) return made.error();
      ideal = std::move(*made);
    }
    Task task = *base;
    std::vector<Attempt> order{Attempt::Expert};
    for (Attempt a : settings.attempts)
      if (a != Attempt::Expert) order.push_back(a);
    for (Attempt a : order) {
      if (progress) progress(task.name + ": " + attemptName(a));
      auto drilled = runner.drill(task, a);
      if (!drilled) return drilled.error();
      // The expert's session sets the task's times; every attempt is scored against them.
      if (a == Attempt::Expert) task = timedFromExpert(task, sessionStats(drilled->session, task).elapsed_s, settings);
      auto scored = runner.score(task, a, *drilled, ideal ? &*ideal : nullptr);
      if (!scored) return scored.error();
      out.scores.push_back(std::move(*scored));
    }
    out.tasks.push_back(task);
  }
  return out;
}

// ---- 2. the checks ----------------------------------------------------------------------------------------

std::vector<std::string> faultParts(TaskKind kind, Attempt attempt) {
  const bool caries = kind == TaskKind::Caries;
  switch (attempt) {
    case Attempt::Expert: return {};
    case Attempt::Overcut: return {caries ? "healthy" : "overcut"};
    // An access stopped early leaves the chamber closed: the cap is its under-cut's cost too.
    case Attempt::Undercut:
      return caries ? std::vector<std::string>{"removal"}
                    : kind == TaskKind::Access ? std::vector<std::string>{"undercut", "pulp cap"}
                                               : std::vector<std::string>{"undercut"};
    case Attempt::Heavy: return {"force"};
    case Attempt::Slow: return {"time"};
    case Attempt::Trench: return caries ? std::vector<std::string>{"removal", "healthy"} : std::vector<std::string>{"undercut", "overcut"};
  }
  return {};
}

std::vector<NoviceCheck> checkNovices(const ScoreBenchResult& result, double min_gap) {
  std::vector<NoviceCheck> out;
  for (const AttemptScore& expert : result.scores) {
    if (expert.attempt != Attempt::Expert) continue;
    const TaskKind kind = expert.kind;
    std::map<std::string, double> base(expert.parts.begin(), expert.parts.end());
    for (const AttemptScore& novice : result.scores) {
      if (novice.task != expert.task || novice.attempt == Attempt::Expert) continue;
      NoviceCheck c;
      c.task = novice.task;
      c.attempt = novice.attempt;
      c.gap = expert.total - novice.total;
      std::map<std::string, double> parts(novice.parts.begin(), novice.parts.end());
      for (const auto& [name, points] : base) parts.try_emplace(name, 0.0);
      for (const auto& [name, points] : parts) {
        const double loss = std::max(0.0, (base.count(name) ? base[name] : 0.0) - points);
        c.lost += loss;
        const std::vector<std::string> fault = faultParts(kind, novice.attempt);
        if (std::find(fault.begin(), fault.end(), name) != fault.end()) c.lost_in_fault += loss;
      }
      c.gap_ok = c.gap >= min_gap;
      c.part_ok = c.lost > 0 && c.lost_in_fault >= 0.5 * c.lost;
      out.push_back(c);
    }
  }
  return out;
}

// ---- 3. the report ------------------------------------------------------------------------------------------

namespace {

std::string fixed(double v, int digits = 1) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

nlohmann::ordered_json taskTimes(const Task& t) {
  nlohmann::ordered_json j = {{"name", t.name}, {"drill", t.drill_tool}, {"target_s", t.target_s}};
  j["kind"] = taskKindName(t.kind);
  if (t.kind == TaskKind::Caries) j["failure_s"] = t.failure_s;
  else j["time_coefficient"] = t.cavity.time_coefficient;
  return j;
}

}  // namespace

nlohmann::ordered_json scoreBenchJson(const ScoreBenchResult& result) {
  nlohmann::ordered_json j;
  j["benchmark"] = "scores";
  j["level"] = result.level;
  j["voxel_mm"] = result.voxel_mm;
  nlohmann::ordered_json times = nlohmann::ordered_json::object();
  for (const Task& t : result.tasks) times[t.name] = taskTimes(t);
  j["tasks"] = std::move(times);
  nlohmann::ordered_json scores = nlohmann::ordered_json::array();
  for (const AttemptScore& a : result.scores) {
    nlohmann::ordered_json s;
    s["task"] = a.task;
    s["kind"] = taskKindName(a.kind);
    s["attempt"] = attemptName(a.attempt);
    s["fault"] = attemptFault(a.attempt);
    s["total"] = a.total;
    s["total_max"] = a.total_max;
    s["paper_total"] = a.paper_total;
    nlohmann::ordered_json parts = nlohmann::ordered_json::object();
    for (const auto& [name, points] : a.parts) parts[name] = points;
    s["parts"] = std::move(parts);
    s["elapsed_s"] = a.elapsed_s;
    s["max_force_n"] = a.max_force_n;
    s["mean_force_n"] = a.mean_force_n;
    s["force_over_percent"] = a.force_over_percent;
    s["caries_removed_percent"] = a.caries_removed_percent;
    s["healthy_removed_mm3"] = a.healthy_removed_mm3;
    s["healthy_outside_zone_mm3"] = a.healthy_outside_mm3;
    if (a.kind != TaskKind::Caries) {
      s["undercut_percent"] = a.undercut_percent;
      s["overcut_percent"] = a.overcut_percent;
    }
    s["pulp_exposed"] = a.pulp_exposed;
    s["final_hash"] = a.final_hash;
    s["warnings"] = a.warnings;
    s["report"] = a.report;
    scores.push_back(std::move(s));
  }
  j["scores"] = std::move(scores);
  nlohmann::ordered_json checks = nlohmann::ordered_json::array();
  for (const NoviceCheck& c : checkNovices(result))
    checks.push_back({{"task", c.task},
                      {"attempt", attemptName(c.attempt)},
                      {"gap", c.gap},
                      {"lost", c.lost},
                      {"lost_in_fault_parts", c.lost_in_fault},
                      {"gap_at_least_20", c.gap_ok},
                      {"lost_mostly_in_fault_parts", c.part_ok}});
  j["checks"] = std::move(checks);
  return j;
}

std::string scoreBenchMarkdown(const ScoreBenchResult& result) {
  std::ostringstream o;
  const std::vector<NoviceCheck> checks = checkNovices(result);
  o << "# Scores of scripted attempts (level " << result.level << ", " << fixed(result.voxel_mm, 4) << " mm voxels)\n\n";
  for (const Task& t : result.tasks) {
    const std::string& task = t.name;
    o << "## " << t.name << ": " << t.title << " (" << taskKindName(t.kind) << ", " << t.drill_tool << ", target "
      << fixed(t.target_s) << " s)\n\n";
    // The parts in the expert's order, then any the novices add.
    std::vector<std::string> names;
    for (const AttemptScore& a : result.scores)
      if (a.task == task)
        for (const auto& [name, points] : a.parts)
          if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    o << "| attempt | fault | total |";
    for (const std::string& n : names) o << " " << n << " |";
    o << " gap to expert | lost in the fault's part | caries removed | healthy removed (outside zone) mm³ | force N, mean (max) |\n";
    o << "|---|---|---|";
    for (size_t i = 0; i < names.size(); ++i) o << "---|";
    o << "---|---|---|---|---|\n";
    for (const AttemptScore& a : result.scores) {
      if (a.task != task) continue;
      o << "| " << attemptName(a.attempt) << " | " << attemptFault(a.attempt) << " | **" << fixed(a.total) << "** |";
      for (const std::string& n : names) {
        auto it = std::find_if(a.parts.begin(), a.parts.end(), [&](const auto& p) { return p.first == n; });
        o << " " << (it == a.parts.end() ? std::string("–") : fixed(it->second)) << " |";
      }
      auto c = std::find_if(checks.begin(), checks.end(), [&](const NoviceCheck& k) { return k.task == task && k.attempt == a.attempt; });
      if (c == checks.end())
        o << " – | – |";
      else
        o << " " << fixed(c->gap) << (c->gap_ok ? "" : " (< 20)") << " | " << fixed(c->lost_in_fault) << " of " << fixed(c->lost)
          << (c->part_ok ? "" : " (not mostly)") << " |";
      o << " " << fixed(a.caries_removed_percent) << "% | " << fixed(a.healthy_removed_mm3, 2) << " (" << fixed(a.healthy_outside_mm3, 2)
        << ") | " << fixed(a.mean_force_n, 2) << " (" << fixed(a.max_force_n, 2) << ") |\n";
    }
    o << "\n";
  }
  return o.str();
}

std::string scoreBenchSvg(const ScoreBenchResult& result) {
  // One group of bars per attempt, one bar per task; an attempt a task did not run scores no bar.
  std::vector<std::string> categories;
  for (const AttemptScore& a : result.scores)
    if (std::find(categories.begin(), categories.end(), attemptName(a.attempt)) == categories.end())
      categories.push_back(attemptName(a.attempt));
  std::vector<BarSeries> series;
  for (const Task& t : result.tasks) {
    BarSeries bars{t.name, std::vector<double>(categories.size(), 0.0)};
    for (const AttemptScore& a : result.scores)
      if (a.task == t.name)
        bars.values[size_t(std::find(categories.begin(), categories.end(), attemptName(a.attempt)) - categories.begin())] = a.total;
    series.push_back(std::move(bars));
  }
  double expert_min = 100.0;
  for (const AttemptScore& a : result.scores)
    if (a.attempt == Attempt::Expert) expert_min = std::min(expert_min, a.total);
  return svgBarChart("Scores of scripted attempts, level " + std::to_string(result.level), "score (of 100)", categories,
                     series, 100.0, 20.0, expert_min - 20.0, "expert - 20");
}

}  // namespace dentsim::bench
