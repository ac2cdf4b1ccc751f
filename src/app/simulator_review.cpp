// The simulator's student and review: the records the picker and the Score page show, the first-run name, and after a score this attempt's replay (with the professional's ghost) in the same window and a retry with guidance.
//
// The records are the learning-record statements the run's own scores add to the outbox
// (app/learning_cli.h): this file only reads them (eval/student_records.h), after a score and when
// the course's list is made again, never in the frame loop's every frame. A review's replay runs
// its own frame loop in this window (app/replay_viewer.h, with this run as its host) while the
// segment is stopped, so the haptic loop is idle and nothing is recorded meanwhile; the tooth's
// surfaces are built again from the run's tooth when it returns.
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "app/commands.h"
#include "app/replay_viewer.h"
#include "app/simulator_state.h"
#include "app/tool_placement.h"
#include "eval/learning_record.h"
#include "eval/student_records.h"
#include "io/session_file.h"

namespace dentsim::app {
namespace {

// How many frames a scripted click waits for its widget before it is given up with a warning: a
// script naming a widget that never shows must not hold the run open for ever.
constexpr int kClickWaitFrames = 600;

std::string activityOf(const SimStudentOptions& st, const std::string& task) {
  return taskActivityIri(st.activity_base.empty() ? kDefaultActivityBase : st.activity_base, st.course_id, task);
}

}  // namespace

// ---- the student and the records ----------------------------------------------------------------------

void Simulator::setUpStudent() {
  const SimStudentOptions& st = o_.student;
  ui_.student.id = st.id;
  ui_.student.where = st.config_path;
  // A window a student sits at: nobody named yet, and no script drilling for them.
  ui_.student.ask = st.student_start && st.id.empty() && painter_->windowed() && painter_->panel() && !model_.script;
  showRecords();
  if (!st.student_start) return;
  // The course as the picker lists it, on the terminal too: what a student (or a test) reads first.
  const std::string who = st.id.empty() ? "no student named" : "student " + st.id;
  std::printf("course %s (%s):\n", ui_.course.folder.c_str(), who.c_str());
  for (const ui::TaskChoice& t : ui_.course.tasks)
    if (!t.builtin) std::printf("  %s%s\n", ui::taskPickerLine(t).c_str(), t.source == model_.task_source ? "  <- now" : "");
  std::fflush(stdout);
}

void Simulator::showRecords() {
  for (ui::TaskChoice& t : ui_.course.tasks) {
    t.attempts = 0;
    t.best.reset();
    t.passed = false;
  }
  ui_.review.before.clear();
  const SimStudentOptions& st = o_.student;
  if (ui_.student.id.empty() || st.outbox.empty()) return;
  auto records = readStudentRecords(st.outbox, ui_.student.id);
  if (!records) {
    noteWarning("your records were not read: " + records.message());
    return;
  }
  // One line for a damaged outbox: the class report and `outbox status` say more.
  if (!records->warnings.empty())
    warn(records->warnings.front() + (records->warnings.size() > 1 ? " (and more)" : ""));
  for (ui::TaskChoice& t : ui_.course.tasks) {
    if (t.name.empty()) continue;
    const TaskRecord r = taskRecord(*records, activityOf(st, t.name));
    t.attempts = r.attempts;
    t.best = r.best;
    t.passed = taskPassed(r, t.pass_mark);
  }
  // The Score page's last attempts at the task in use, this one left out.
  if (!ui_.review.now || !model_.task) return;
  const auto it = records->by_activity.find(activityOf(st, model_.task->name));
  if (it == records->by_activity.end()) return;
  std::vector<ClassAttempt> earlier;
  for (const ClassAttempt& a : it->second)
    if (review_.statement_id.empty() || a.statement_id != review_.statement_id) earlier.push_back(a);
  const size_t first = earlier.size() > kRecentAttempts ? earlier.size() - kRecentAttempts : 0;
  ui_.review.before.assign(earlier.begin() + long(first), earlier.end());
}

// ---- after a score ------------------------------------------------------------------------------------

void Simulator::prepareReview(const std::string& session_file, const std::string& no_session_reason,
                              const nlohmann::ordered_json& report) {
  review_.session = session_file;
  review_.statement_id = report.contains("statement_id") && report["statement_id"].is_string()
                             ? report["statement_id"].get<std::string>()
                             : "";
  ui::ReviewView& v = ui_.review;
  v = {};
  const bool window = painter_->windowed() && painter_->panel() != nullptr;
  if (session_file.empty())
    v.replay = {false, "No recorded session to replay: " + (no_session_reason.empty() ? "none was kept" : no_session_reason) +
                           ". Start the run with --out to keep one."};
  else if (!window)
    v.replay = {false, "A run without a window has nowhere to replay: use dentsim replay " + session_file + "."};
  else
    v.replay = {true, ""};
  if (!v.replay.available)
    v.ghost = v.replay;
  else if (ghostSource().empty())
    v.ghost = {false, "No professional's session: the task has no recorded ideal (a teacher's Record as ideal) and no --ghost was given."};
  else
    v.ghost = {true, ""};
  // The guide the panel's guidance switch would turn on (app/simulator_help.cpp).
  if (ui_.guidance.available)
    v.guided = {true, ""};
  else
    v.guided = {false, "No professional's path to follow: the task has no recorded ideal or scripted path, and no --guide was given."};
  auto now = parseScoreReport(report.dump(), "this attempt", 0.0, "", AttemptReadOptions{});
  if (now) v.now = std::move(*now);
  if (ui_.student.id.empty()) v.records_note = "No student named, so no attempts are kept to compare with (give --student).";
  showRecords();
}

Status Simulator::handleReview(const ui::ReviewActions& a) {
  if (!a.name_given.empty()) {
    if (Status st = keepStudentName(o_.student.config_path, a.name_given); !st) {
      ui_.student.error = st.message();
      ui_.student.typed.clear();
    } else {
      // From now on this run's records are the student's (recordAttempt reads the config again).
      ui_.student.ask = false;
      ui_.student.error.clear();
      ui_.student.id = a.name_given;
      note("student: " + a.name_given + " (kept in " + o_.student.config_path + ")");
      showRecords();
    }
  }
  if (a.replay || a.replay_ghost)
    if (Status st = reviewReplay(a.replay_ghost); !st) return st;
  if (a.retry_guided)
    if (Status st = retryGuided(); !st) return st;
  return Ok{};
}

Status Simulator::reviewReplay(bool with_ghost) {
  if (review_.session.empty() || (with_ghost && ghostSource().empty())) return Ok{};
  auto session = readSessionFile(review_.session);
  if (!session) {
    noteWarning("no replay: " + session.message());
    return Ok{};
  }
  ToothVolume tooth = model_.initial;
  ReplayViewerOptions vo;
  vo.title = review_.session;
  vo.force_threshold_n = model_.task ? model_.task->force_error_n : 3.0;
  vo.exit_at_end = o_.end.exit_at_end;  // a scripted review returns at the replay's end
  vo.lockstep = lockstep_;
  vo.fps = o_.fps;
  if (with_ghost) {
    vo.ghost = ghostSource();
    vo.ghost_opacity = ui_.ghost_opacity;
  }
  ++review_.reviews;
  if (!o_.out.empty() && !o_.review.shots_s.empty()) {
    vo.out = outPath("review-" + std::to_string(review_.reviews));
    std::error_code ec;
    std::filesystem::create_directories(vo.out, ec);
    vo.shots_s = o_.review.shots_s;
  }
  // Leave the review when the run is asked to end now (the window closed, Ctrl-C, Escape), not
  // for an end it already had in view (--exit-at-end waiting for these scripted clicks).
  const bool ending = end_.quit();
  const ReplayHost host{painter_.get(), &camera_, [this, ending] { return (end_.quit() && !ending) || !end_.reason().empty(); }};
  vo.host = &host;
  note(std::string("review: replaying ") + review_.session + (with_ghost ? " with the professional's ghost" : ""));
  // The mouse turns the view while the replay plays, and leaves the stopped pens where they were.
  input_.setPens(nullptr);
  auto rc = runReplayViewer(*session, tooth, vo, false);
  input_.setPens(pens_.get());
  // The run's own tooth back on screen, whatever the replay left there.
  if (Status st = painter_->surfaces().build(state_.view.voxels); !st) return st;
  state_.panel_relayout = true;
  if (!rc) noteWarning("the replay stopped: " + rc.message());
  return Ok{};
}

Status Simulator::retryGuided() {
  if (!ui_.guidance.available) return Ok{};
  if (segments_.running())
    if (Status st = endSegment("retry with guidance"); !st) return st;
  ui_.guidance.on = true;  // the next segment starts with the guide (segmentGuide)
  if (Status st = rebuildTooth(false); !st) return st;
  if (pens_) pens_->reset(PenRole::Drill, drillStartGrip(model_.box, 3.0));
  note("retry with guidance: the uncut tooth again, a spring pulling the bur along the professional's path");
  return startSegment();
}

// ---- scripted clicks after the score ------------------------------------------------------------------

bool Simulator::reviewHolds() const {
  // The window closing or Ctrl-C ends the run with a reason; only a quiet end (--exit-at-end) waits.
  // A click still pressed is let go, and carried out, in the next frame.
  return (review_.next_click < o_.review.presses.size() || !review_.clicking.empty()) && end_.reason().empty();
}

void Simulator::clickAfterScore() {
  // A frame laid out twice (drawPanel) would spend the scripted mouse on its unseen first layout.
  if (!painter_->panel() || state_.panel_relayout) return;
  // A click's second frame: the button let go where it was pressed.
  if (!review_.clicking.empty()) {
    scriptClick(review_.clicking, false);
    review_.clicking.clear();
    return;
  }
  if (!ui_.score.valid || review_.next_click >= o_.review.presses.size()) return;
  const std::string& widget = o_.review.presses[review_.next_click];
  if (!scriptClick(widget, true)) {
    if (++review_.waited_frames > kClickWaitFrames) {
      noteWarning("--after-score-click: no widget \"" + widget + "\" showed on the panel; not clicked");
      ++review_.next_click;
      review_.waited_frames = 0;
    }
    return;
  }
  review_.clicking = widget;
  review_.waited_frames = 0;
  ++review_.next_click;
}

}  // namespace dentsim::app
