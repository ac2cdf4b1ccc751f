// Task validation: the professional's session, the derived attempts drilled and scored, the checks, and the JSON and Markdown of the result.
//
// Contents
//   1. Which part each fault should cost
//   2. The professional's session
//   3. Drilling and scoring the attempts
//   4. The checks
//   5. JSON and Markdown
#include "eval/task_validation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "eval/cut_score.h"
#include "eval/session_stats.h"
#include "eval/task_ideal.h"
#include "eval/task_kinds.h"
#include "io/session_file.h"
#include "sim/course_paths.h"
#include "sim/session_run.h"
#include "sim/sim_params.h"
#include "volume/volume_hash.h"

namespace dentsim {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

// ---- 1. which part each fault should cost ------------------------------------------------------------

std::vector<Attempt> kindAttempts(TaskKind kind) {
  if (kind == TaskKind::Crown) return {kCrownAttempts.begin(), kCrownAttempts.end()};
  return {kAttempts.begin(), kAttempts.end()};
}

namespace {

// A crown's faults, each in its own criterion (eval/crown_score.h); the under-cut and the token
// leave every criterion short.
std::vector<std::string> crownFaultParts(Attempt attempt) {
  switch (attempt) {
    case Attempt::Overtaper: return {"taper"};
    case Attempt::Shallow: return {"occlusal_reduction"};
    // An undercut beyond the task's tolerance caps the total as well as costing its criterion.
    case Attempt::WallUndercut: return {"undercut", "undercut cap"};
    case Attempt::ThinMargin: return {"margin_width"};
    case Attempt::Nick: return {"adjacent"};
    case Attempt::Undercut:
    case Attempt::Token:
      return {"occlusal_reduction", "axial_reduction", "taper", "height", "margin_width", "margin_line", "undercut"};
    default: return {};
  }
}

}  // namespace

std::vector<std::string> faultParts(TaskKind kind, Attempt attempt) {
  if (kind == TaskKind::Crown) return crownFaultParts(attempt);
  const bool caries = kind == TaskKind::Caries;
  // A chamber the kind must open and did not is the pulp cap's (eval/task_kinds.h's pulp rule).
  const bool must_open = taskKindRow(kind).pulp == PulpRule::MustOpen;
  switch (attempt) {
    case Attempt::Expert: return {};
    case Attempt::Overcut: return {caries ? "healthy" : "overcut"};
    // An access stopped early leaves the chamber closed: the cap is its under-cut's cost too.
    case Attempt::Undercut:
    case Attempt::Token:
      return caries ? std::vector<std::string>{"removal"}
                    : must_open ? std::vector<std::string>{"undercut", "pulp cap"}
                                : std::vector<std::string>{"undercut"};
    // dentsim cuts at a rate set by the tissue, the bur and the turbine, not by the force: a hand
    // that presses harder drives the bur past where the professional's stopped, into healthy tissue
    // (docs/SCORING.md section 13).
    case Attempt::Heavy: return {"force", caries ? "healthy" : "overcut"};
    case Attempt::Slow: return {"time"};
    case Attempt::Tilted: return {"parallel"};
    // The wrong place leaves the ideal standing and cuts beside it.
    case Attempt::Trench:
      return caries ? std::vector<std::string>{"removal", "healthy"}
                    : must_open ? std::vector<std::string>{"undercut", "overcut", "pulp cap"}
                                : std::vector<std::string>{"undercut", "overcut"};
    // A crown's own faults are not run at the other kinds.
    case Attempt::Overtaper:
    case Attempt::Shallow:
    case Attempt::WallUndercut:
    case Attempt::ThinMargin:
    case Attempt::Nick: return {};
  }
  return {};
}

// ---- 2. the professional's session ---------------------------------------------------------------------

namespace {

// Records `path` drilled on `tooth` (edited in place) into `file` and reads it back.
Result<SessionRecording> recordAndRead(ToothVolume& tooth, const SimParams& params, const PenPath& path,
                                       const std::string& file, const Task& task, const std::string& mirror_tool) {
  SessionInfo info;
  info.task = task.name;
  ScriptedSessionOptions so;
  so.drill_tool = task.drill_tool;
  so.mirror_tool = mirror_tool;
  auto outcome = recordScriptedSession(tooth, params, path, file, info, so);
  if (!outcome) return outcome.error();
  // A score from a session with gaps would not be the attempt's.
  if (outcome->steps_lost > 0) return makeError(file, "the recorder lost " + std::to_string(outcome->steps_lost) + " steps");
  auto session = readSessionFile(file);
  std::error_code ec;
  fs::remove(file, ec);
  return session;
}

}  // namespace

Result<SessionRecording> professionalSession(const Task& task, const ToothVolume& tooth, const std::string& work_dir,
                                             std::string* from) {
  const std::string where = "task " + task.name;
  if (task.ideal && task.ideal->kind == IdealKind::Session) {
    *from = "the ideal session " + fs::path(task.ideal->path).filename().string();
    return readSessionFile(task.ideal->path);
  }
  if (task.ideal && task.ideal->kind == IdealKind::Volume)
    return makeError(where, "the ideal is a volume file, which holds no motion to derive attempts from: record the "
                            "professional and set it with dentsim task set-ideal TASK --session PROF.dses");
  // The built-in professional: the task's path, or the careful caries removal.
  const SimParams params = defaultSimParams();
  auto path = taskAttemptPath(exerciseOf(task), Attempt::Expert, tooth.voxels, tooth.frame, params);
  if (!path) return makeError(where, path.message());
  ToothVolume cut = tooth;
  *from = task.ideal ? "the built-in path " + task.ideal->path + ", recorded" : "the built-in caries removal, recorded";
  return recordAndRead(cut, params, *path, (fs::path(work_dir) / (task.name + "-professional.dses")).string(), task, "");
}

// ---- 3. drilling and scoring the attempts ----------------------------------------------------------------

namespace {

// The parts of a report: each scored component's points, each deduction as negative points, and
// a pulp cap as what it took off.
std::vector<std::pair<std::string, double>> reportParts(const ScoreReportSummary& report) {
  std::vector<std::pair<std::string, double>> parts;
  double sum = 0.0;
  for (const ScoreReportPart& part : report.parts) {
    if (!part.points) continue;
    const double points = part.deduction && *part.points != 0.0 ? -*part.points : *part.points;  // no "-0.0" in the tables
    parts.push_back({part.name, points});
    sum += points;
  }
  for (const char* key : {"pulp_exposure", "pulp_unopened", "undercut_cap"})
    for (const ScoreReportPart& cap : report.parts)
      if (cap.deduction && cap.name == key && cap.applied.value_or(false))
        parts.push_back({std::string(key) == "undercut_cap" ? "undercut cap" : "pulp cap",
                         report.total - std::clamp(sum, 0.0, report.total_max.value_or(100.0))});
  return parts;
}

// Everything an attempt shows is read from the report's summary, as the learning record and the
// class report read it, so that the benchmark's figures cannot drift from the report's keys.
ValidatedAttempt attemptOf(Attempt a, const SessionScore& scored, const ToothVolume& final_tooth) {
  ValidatedAttempt v;
  v.attempt = a;
  v.summary = scored.reported;
  v.total = scored.total;
  v.total_max = scored.total_max;
  v.paper_total = v.summary.paper_total.value_or(0.0);
  v.parts = reportParts(v.summary);
  // Every attempt is scored with its recorded session, so its report has the session's statistics.
  const ScoreReportSession session = v.summary.session.value_or(ScoreReportSession{});
  v.elapsed_s = session.elapsed_s.value_or(0.0);
  v.mean_force_n = session.mean_force_n.value_or(0.0);
  v.max_force_n = session.max_force_n.value_or(0.0);
  if (v.summary.agreement) v.agreement_percent = v.summary.agreement->within_percent;
  v.pulp_exposed = scored.pulp_exposed;
  v.final_hash = volumeHashHex(final_tooth.voxels, final_tooth.frame);
  return v;
}

double partOf(const ValidatedAttempt& a, const std::string& name) {
  for (const auto& [n, p] : a.parts)
    if (n == name) return p;
  return 0.0;
}

FaultCheck compare(const ValidatedAttempt& expert, const ValidatedAttempt& fault, TaskKind kind, double pass_mark) {
  FaultCheck c;
  c.attempt = fault.attempt;
  c.gap = expert.total - fault.total;
  c.passes = fault.total >= pass_mark * fault.total_max / 100.0;
  std::vector<std::string> names;
  for (const auto& [n, p] : expert.parts) names.push_back(n);
  for (const auto& [n, p] : fault.parts)
    if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  const std::vector<std::string> own = faultParts(kind, fault.attempt);
  // A part earned in proportion to the work done is compared at its own measure, the table's part
  // (table_points): the share of the ideal cut scales every such part alike and is the under-cut's
  // to show, while the table's part names what was done wrong in what was cut.
  std::map<std::string, double> loss;
  const auto measure = [](const ValidatedAttempt& a, const std::string& n) {
    for (const ScoreReportPart& part : a.summary.parts)
      if (!part.deduction && part.name == n && part.table_points) return *part.table_points;
    return partOf(a, n);
  };
  for (const std::string& n : names) loss[n] = std::max(0.0, measure(expert, n) - measure(fault, n));
  double most = 0.0;
  for (const auto& [n, l] : loss) {
    c.lost += l;
    // A cut beyond where it belongs (over-cut, healthy tissue) that reaches an adjacent tooth is the
    // same fault: the adjacent-tooth deduction, present only on a tooth with neighbours, is its part too.
    // So it is for a tilted bur: in a proximal box its side swings past the wall at the contact, the
    // commonest way a class II nicks the neighbour.
    const bool beyond = std::find(own.begin(), own.end(), "overcut") != own.end() ||
                        std::find(own.begin(), own.end(), "healthy") != own.end() ||
                        std::find(own.begin(), own.end(), "parallel") != own.end();
    const bool is_own = std::find(own.begin(), own.end(), n) != own.end() || (n == "adjacent" && beyond);
    if (is_own) c.lost_in_fault += l;
    else c.most_lost_elsewhere = std::max(c.most_lost_elsewhere, l);
    if (l > most) {
      most = l;
      c.most_lost_part = n;
    }
  }
  return c;
}

std::string fixed(double v, int digits = 1) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

std::string joined(const std::vector<std::string>& parts, const char* sep) {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : sep) + p;
  return out;
}

// Each check that fails, one line naming the attempt and the part.
void check(TaskValidation& v) {
  const ValidatedAttempt& expert = v.attempts.front();
  if (expert.total < v.expert_floor * expert.total_max / 100.0) {
    std::string weakest;
    double lowest = 1e9;
    for (const auto& [n, p] : expert.parts)
      if (p < lowest) lowest = p, weakest = n;
    v.failures.push_back("expert: scores " + fixed(expert.total) + ", below " + fixed(v.expert_floor, 0) +
                         " (its weakest part: " + weakest + " " + fixed(lowest) + ")");
  }
  for (size_t i = 1; i < v.attempts.size(); ++i) {
    const FaultCheck c = compare(expert, v.attempts[i], v.task.kind, v.pass_mark);
    v.faults.push_back(c);
    const std::string name = attemptName(c.attempt);
    const std::string own = joined(faultParts(v.task.kind, c.attempt), " and ");
    if (c.gap < v.min_gap)
      v.failures.push_back(name + ": loses " + fixed(c.gap) + " points against the expert, not " + fixed(v.min_gap, 0) +
                           " (" + own + " lost " + fixed(c.lost_in_fault) + ")");
    if (!c.mostInOwnPart())
      v.failures.push_back(name + ": loses most in " + (c.most_lost_part.empty() ? "no part" : c.most_lost_part) + " (" +
                           fixed(c.most_lost_elsewhere) + " points), not in its own part " + own + " (" + fixed(c.lost_in_fault) +
                           ")");
    const bool must_fail = c.attempt == Attempt::Undercut || c.attempt == Attempt::Token || c.attempt == Attempt::Trench;
    if (must_fail && c.passes)
      v.failures.push_back(name + ": passes at " + fixed(v.attempts[i].total) + " (pass mark " + fixed(v.pass_mark, 0) +
                           "), though " + own + " lost " + fixed(c.lost_in_fault));
  }
}

}  // namespace

FaultCheck compareWithExpert(const ValidatedAttempt& expert, const ValidatedAttempt& fault, TaskKind kind, double pass_mark) {
  return compare(expert, fault, kind, pass_mark);
}

Result<TaskValidation> validateTask(const Task& task, const ToothVolume& tooth, const ValidationSettings& settings,
                                    const std::function<void(const std::string&)>& progress) {
  if (settings.work_dir.empty()) return makeError("task validate", "no folder for the sessions");
  TaskValidation v;
  v.task = task;
  v.pass_mark = task.pass_mark.value_or(settings.default_pass_mark);
  v.expert_floor = settings.expert_floor;
  v.min_gap = task.kind == TaskKind::Crown ? settings.crown_min_gap : settings.min_gap;
  const std::string where = "task " + task.name;
  if (progress) progress(task.name + ": the professional");
  auto pro_session = professionalSession(task, tooth, settings.work_dir, &v.professional);
  if (!pro_session) return pro_session.error();
  // A heavy hand presses past the task's own force limit, whatever the professional pressed.
  const DerivedAttemptSettings derive = derivedSettingsFor(task.force_error_n, settings.derive);
  auto pro = professionalPath(*pro_session, where + ": professional's session", derive);
  if (!pro) return pro.error();
  // The session's length as the time part measures it (eval/session_stats.h).
  v.professional_s = sessionStats(*pro_session, v.task).elapsed_s;
  if (settings.time_from_professional) {
    v.task = timedFromProfessional(v.task, v.professional_s);
    v.timed_here = true;
  }
  const Task& scored_task = v.task;
  auto params = parseSimParams(pro_session->info.params_json, where + ": professional's parameters");
  if (!params) return params.error();

  // The professional's session replayed: its removal over time says where "half the cutting" is,
  // and its final tooth is the ideal of a built-in path (drilled the same way, with the same bur).
  if (progress) progress(task.name + ": the professional replayed");
  ToothVolume pro_final = tooth;
  std::vector<std::pair<double, double>> removal;  // (loop time [s], removed [mm^3])
  ReplayOptions replay;
  replay.observe = [&](const HapticState& st) { removal.emplace_back(st.t_s, st.removed_mm3); };
  auto replayed = replaySession(*pro_session, pro_final, replay);
  if (!replayed) return makeError(where + ": professional's session", replayed.message());
  if (!removal.empty() && removal.back().second > 0) {
    const double half = derive.undercut_share * removal.back().second;
    for (const auto& [t, removed] : removal)
      if (removed >= half) {
        pro->half_removed_s = t;
        break;
      }
  }
  std::optional<ToothVolume> ideal;
  if (task.ideal && task.ideal->kind == IdealKind::BuiltinPath) {
    pro_final.voxels.compact();
    ideal = std::move(pro_final);
  } else if (task.ideal) {
    if (progress) progress(task.name + ": the ideal");
    std::vector<std::string> warnings;
    auto made = idealForTask(task, tooth, &warnings);
    if (!made) return made.error();
    ideal = std::move(*made);
  }

  std::vector<Attempt> order{Attempt::Expert};
  const std::vector<Attempt> own = kindAttempts(task.kind);
  for (Attempt a : settings.attempts.empty() ? own : settings.attempts) {
    if (a == Attempt::Expert || std::find(order.begin(), order.end(), a) != order.end()) continue;
    if (std::find(own.begin(), own.end(), a) == own.end()) {
      v.skipped.push_back(std::string(attemptName(a)) + ": not an attempt at a " + taskKindName(task.kind) + " task");
      continue;
    }
    if (a == Attempt::Tilted && task.kind == TaskKind::Caries) {
      v.skipped.push_back("tilted: a caries removal has no bur-angle part to lose");
      continue;
    }
    order.push_back(a);
  }
  for (Attempt a : order) {
    const std::string name = task.name + "-" + attemptName(a);
    if (progress) progress(task.name + ": " + attemptName(a));
    const PenPath path = derivedAttemptPath(*pro, a, scored_task.insertion_axis, tooth.frame.tooth, derive);
    ToothVolume cut = tooth;
    auto session = recordAndRead(cut, *params, path, (fs::path(settings.work_dir) / (name + ".dses")).string(), task,
                                 pro_session->info.mirror_tool);
    if (!session) return makeError(name, session.message());
    cut.voxels.compact();
    ScoreFiles files = scoreFiles(task.name + " tooth", name, name + ".dses");
    if (ideal) {
      files.ideal_spec = task.ideal;
      files.ideal_from = "task";
    }
    auto scored = scoreCut(scored_task, tooth, cut, ideal ? &*ideal : nullptr, &*session, files);
    if (!scored) return makeError(name, scored.message());
    if (!settings.picture_dir.empty()) {
      const std::string png = (fs::path(settings.picture_dir) / (name + ".png")).string();
      if (Status st = writeScoreImage(png, scored_task, tooth, cut, *scored, ideal ? &*ideal : nullptr); !st) return st.error();
    }
    v.attempts.push_back(attemptOf(a, *scored, cut));
  }
  check(v);
  return v;
}

// ---- 5. JSON and Markdown -----------------------------------------------------------------------------------

ojson validationJson(const TaskValidation& v) {
  ojson j;
  j["task"] = v.task.name;
  j["kind"] = taskKindName(v.task.kind);
  j["pass_mark"] = v.pass_mark;
  j["target_s"] = v.task.target_s;
  j["times_from_this_professional"] = v.timed_here;
  j["professional"] = {{"source", v.professional}, {"elapsed_s", v.professional_s}};
  ojson attempts = ojson::array();
  for (const ValidatedAttempt& a : v.attempts) {
    ojson s;
    s["attempt"] = attemptName(a.attempt);
    s["fault"] = attemptFault(a.attempt);
    s["total"] = a.total;
    s["total_max"] = a.total_max;
    s["paper_total"] = a.paper_total;
    ojson parts = ojson::object();
    for (const auto& [name, points] : a.parts) parts[name] = points;
    s["parts"] = std::move(parts);
    s["completion"] = a.summary.completion_share ? ojson(*a.summary.completion_share) : ojson(nullptr);
    s["elapsed_s"] = a.elapsed_s;
    s["mean_force_n"] = a.mean_force_n;
    s["max_force_n"] = a.max_force_n;
    s["surface_within_percent"] = a.agreement_percent ? ojson(*a.agreement_percent) : ojson(nullptr);
    s["pulp_exposed"] = a.pulp_exposed;
    s["final_hash"] = a.final_hash;
    attempts.push_back(std::move(s));
  }
  j["attempts"] = std::move(attempts);
  ojson checks = ojson::array();
  for (const FaultCheck& c : v.faults)
    checks.push_back({{"attempt", attemptName(c.attempt)},
                      {"own_parts", faultParts(v.task.kind, c.attempt)},
                      {"gap", c.gap},
                      {"lost", c.lost},
                      {"lost_in_own_parts", c.lost_in_fault},
                      {"most_lost_part", c.most_lost_part},
                      {"most_lost_in_another_part", c.most_lost_elsewhere},
                      {"most_in_own_part", c.mostInOwnPart()},
                      {"passes", c.passes}});
  j["checks"] = std::move(checks);
  j["skipped"] = v.skipped;
  j["failures"] = v.failures;
  j["valid"] = v.valid();
  return j;
}

namespace {

// A task file's text in the table and on the terminal: control bytes as \xNN (no escape sequence
// reaches a terminal, no line break a table) and '|' escaped for Markdown.
std::string markdownText(const std::string& s) {
  std::string out;
  for (const unsigned char c : s) {
    if (c < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", unsigned(c));
      out += hex;
    } else {
      if (c == '|') out += '\\';
      out += char(c);
    }
  }
  return out;
}

}  // namespace

std::string validationMarkdown(const TaskValidation& v) {
  std::ostringstream o;
  o << "## " << v.task.name << ": " << markdownText(v.task.title) << "\n\n";
  o << taskKindName(v.task.kind) << ", " << v.task.drill_tool << ", target " << fixed(v.task.target_s) << " s, pass mark "
    << fixed(v.pass_mark, 0) << "; professional: " << markdownText(v.professional) << ", " << fixed(v.professional_s) << " s"
    << (v.timed_here ? " (the times set from it by set-ideal's rule)" : "") << "\n\n";
  std::vector<std::string> names;
  for (const ValidatedAttempt& a : v.attempts)
    for (const auto& [n, p] : a.parts)
      if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  o << "| attempt | fault | total |";
  for (const std::string& n : names) o << " " << n << " |";
  o << " done | time s | surface ±0.2 mm | gap | lost in own part | passes |\n|---|---|---|";
  for (size_t i = 0; i < names.size(); ++i) o << "---|";
  o << "---|---|---|---|---|---|\n";
  for (const ValidatedAttempt& a : v.attempts) {
    o << "| " << attemptName(a.attempt) << " | " << attemptFault(a.attempt) << " | **" << fixed(a.total) << "** |";
    for (const std::string& n : names) {
      auto it = std::find_if(a.parts.begin(), a.parts.end(), [&](const auto& p) { return p.first == n; });
      o << " " << (it == a.parts.end() ? std::string("–") : fixed(it->second)) << " |";
    }
    const std::optional<double> done = a.summary.completion_share;
    o << " " << (done ? fixed(100.0 * *done, 0) + "%" : std::string("–")) << " | "
      << fixed(a.elapsed_s) << " | " << (a.agreement_percent ? fixed(*a.agreement_percent) + "%" : std::string("–")) << " |";
    auto c = std::find_if(v.faults.begin(), v.faults.end(), [&](const FaultCheck& k) { return k.attempt == a.attempt; });
    if (c == v.faults.end())
      o << " – | – | " << (a.total >= v.pass_mark * a.total_max / 100.0 ? "yes" : "no") << " |\n";
    else
      o << " " << fixed(c->gap) << " | " << fixed(c->lost_in_fault) << " of " << fixed(c->lost) << " | " << (c->passes ? "yes" : "no")
        << " |\n";
  }
  o << "\n";
  for (const std::string& s : v.skipped) o << "- not run: " << s << "\n";
  if (v.valid())
    o << "**valid**: the expert clears " << fixed(v.expert_floor, 0) << ", every fault loses at least " << fixed(v.min_gap, 0)
      << " points, most in its own part, and no unfinished or misplaced attempt passes.\n";
  else
    for (const std::string& f : v.failures) o << "- **fails**: " << f << "\n";
  o << "\n";
  return o.str();
}

}  // namespace dentsim
