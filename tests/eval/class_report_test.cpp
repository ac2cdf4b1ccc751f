// Tests of the class report's reading and model (attempt_reader, class_report) and of its page's text, plots, points lost and escaping (class_report_html).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "eval/attempt_reader.h"
#include "eval/class_report.h"
#include "eval/class_report_html.h"
#include "eval/cut_score.h"
#include "eval/learning_record.h"
#include "test_support.h"

namespace dentsim {
namespace {

size_t countOf(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// A statement as the outbox writes it; `extra` goes into result (",\"success\":false").
std::string statement(const std::string& actor, const std::string& task, const std::string& verb, double raw,
                      const std::string& when, const std::string& extra = "") {
  return "{\"actor\":" + actor + ",\"verb\":{\"id\":\"http://adlnet.gov/expapi/verbs/" + verb +
         "\"},\"object\":{\"id\":\"https://dentsim.example/tasks/" + task + "\",\"definition\":{\"name\":{\"en-US\":\"Title of " +
         task + "\"}}},\"result\":{\"score\":{\"raw\":" + std::to_string(raw) + ",\"min\":0,\"max\":100}" + extra +
         "},\"timestamp\":\"" + when + "\"}";
}
std::string account(const std::string& id, const std::string& name) {
  return "{\"name\":\"" + name + "\",\"account\":{\"homePage\":\"https://school.example\",\"name\":\"" + id + "\"}}";
}

TEST(IsoTime, ReadsUtcOffsetsAndFractionsAndRefusesImpossibleDates) {
  EXPECT_EQ(parseIsoTime("1970-01-01T00:00:00Z"), 0.0);
  EXPECT_EQ(parseIsoTime("1969-12-31T00:00:00Z"), -86400.0);
  EXPECT_EQ(parseIsoTime("2026-11-27T08:15:30Z"), 1795767330.0);      // by Python's datetime
  EXPECT_EQ(parseIsoTime("2026-11-27T08:15:30"), 1795767330.0);       // no zone: UTC
  EXPECT_EQ(parseIsoTime("2026-11-27T09:15:30+01:00"), 1795767330.0);
  EXPECT_EQ(parseIsoTime("2026-11-27T03:15:30-0500"), 1795767330.0);
  EXPECT_EQ(parseIsoTime("2000-02-29T23:59:59Z"), 951868799.0);       // a leap day
  EXPECT_DOUBLE_EQ(*parseIsoTime("2026-11-27T08:15:30.25Z"), 1795767330.25);
  for (const char* bad : {"2026-02-29T00:00:00Z", "2026-13-01T00:00:00Z", "2026-11-27", "2026-11-27T08:15Z",
                          "2026-11-27T08:15:30Q", "yesterday", ""})
    EXPECT_FALSE(parseIsoTime(bad)) << bad;
}

TEST(IsoDuration, ReadsDaysHoursMinutesAndFractionalSeconds) {
  EXPECT_DOUBLE_EQ(*parseIsoDuration("PT5M12.5S"), 312.5);
  EXPECT_DOUBLE_EQ(*parseIsoDuration("P1DT2H"), 93600.0);
  EXPECT_DOUBLE_EQ(*parseIsoDuration("PT0S"), 0.0);
  for (const char* bad : {"P", "PT", "5M", "PT5X", "P1M", "PT1H2", ""}) EXPECT_FALSE(parseIsoDuration(bad)) << bad;
}

constexpr const char* kReport =
    R"({"format":"dentsim-score","version":2,"task":{"name":"class2_cavity","kind":"cavity","title":"Class II"},)"
    R"("total":62.5,"total_max":100,"pulp_exposed":true})";

TEST(ScoreReportInput, TakesTheStudentFromTheOptionTheReportOrTheFolders) {
  auto a = parseScoreReport(kReport, "/class/alice/try1/score.json", 1000.0, "/class/alice/try1/score.png", {});
  ASSERT_TRUE(a.ok()) << a.message();
  EXPECT_EQ(a->student, "alice");
  EXPECT_EQ(a->task, "class2_cavity");
  EXPECT_EQ(a->task_title, "Class II");
  EXPECT_EQ(a->task_kind, "cavity");
  EXPECT_DOUBLE_EQ(a->score, 62.5);
  EXPECT_TRUE(a->pulp_exposed);
  EXPECT_EQ(a->time_s, 1000.0);  // the file's time: the report has no timestamp
  EXPECT_EQ(a->picture, "/class/alice/try1/score.png");

  AttemptReadOptions given;
  given.student = "bob";
  EXPECT_EQ(parseScoreReport(kReport, "/class/alice/try1/score.json", 0, "", given)->student, "bob");
  std::string own = kReport;
  own.insert(own.size() - 1, R"(,"student":"carol","timestamp":"1970-01-02T00:00:00Z")");
  auto c = parseScoreReport(own, "/x/y/score.json", 1000.0, "", {});
  ASSERT_TRUE(c.ok()) << c.message();
  EXPECT_EQ(c->student, "carol");
  EXPECT_EQ(c->time_s, 86400.0);
  EXPECT_FALSE(c->guided);
  // A guided attempt's report names its guide.
  std::string guided = kReport;
  guided.insert(guided.size() - 1, R"(,"guided":{"source":"pro.dses","stiffness_n_per_mm":1.0})");
  auto g = parseScoreReport(guided, "/x/y/score.json", 0, "", {});
  ASSERT_TRUE(g.ok()) << g.message();
  EXPECT_TRUE(g->guided);
  std::string bad = kReport;
  bad.insert(bad.size() - 1, R"(,"guided":true)");
  EXPECT_EQ(parseScoreReport(bad, "b.json", 0, "", {}).message(), "b.json: guided: not an object");
}

TEST(ScoreReportInput, BadReportsNameTheFileAndTheField) {
  auto no_total = parseScoreReport(R"({"format":"dentsim-score","task":{"name":"caries_removal"}})", "a/b/score.json", 0, "", {});
  ASSERT_FALSE(no_total.ok());
  EXPECT_EQ(no_total.message(), "a/b/score.json: total: missing or not a number in [0, 100]");
  auto other = parseScoreReport(R"({"format":"something-else"})", "r.json", 0, "", {});
  ASSERT_FALSE(other.ok());
  EXPECT_NE(other.message().find("r.json: not a dentsim score report"), std::string::npos);
  std::string bad_time = kReport;
  bad_time.insert(bad_time.size() - 1, R"(,"timestamp":"soon")");
  EXPECT_NE(parseScoreReport(bad_time, "t.json", 0, "", {}).message().find("t.json: timestamp"), std::string::npos);
}

TEST(StatementInput, ReadEachLineSkipThoseWithoutAScoreAndResolvePictures) {
  const std::string text =
      statement(account("s01", "Ann O'Neil"), "caries_removal", "passed", 81.5, "2026-11-27T08:00:00Z",
                ",\"success\":true,\"duration\":\"PT5M12.5S\",\"extensions\":{\"https://dentsim.example/xapi/pulp-exposed\":false,"
                "\"https://dentsim.example/xapi/score-picture\":\"s01/score.png\"}") +
      "\n\n" +
      statement("{\"mbox\":\"mailto:bo@school.example\"}", "class2_cavity/", "failed", 30, "2026-11-27T09:00:00Z",
                ",\"success\":false,\"extensions\":{\"https://dentsim.example/xapi/pulp-exposed\":true,"
                "\"https://dentsim.example/xapi/guided\":true}") +
      "\n" +
      R"({"actor":{"name":"Ann"},"verb":{"id":"http://adlnet.gov/expapi/verbs/launched"},"object":{"id":"https://dentsim.example/tasks/caries_removal"},"timestamp":"2026-11-27T07:55:00Z"})" +
      "\r\n";
  int skipped = 0;
  auto read = parseStatements(text, "out/outbox.jsonl", "out", 0.0, &skipped);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ(skipped, 1);  // the launch carries no score
  const ClassAttempt& ann = (*read)[0];
  EXPECT_EQ(ann.student, "s01");
  EXPECT_EQ(ann.student_name, "Ann O'Neil");
  EXPECT_EQ(ann.task, "caries_removal");
  EXPECT_EQ(ann.task_title, "Title of caries_removal");
  EXPECT_DOUBLE_EQ(ann.score, 81.5);
  EXPECT_EQ(ann.verb, "passed");
  EXPECT_EQ(ann.success, std::optional<bool>(true));
  EXPECT_DOUBLE_EQ(*ann.duration_s, 312.5);
  EXPECT_FALSE(ann.pulp_exposed);
  EXPECT_FALSE(ann.guided);  // no guided extension: not guided
  EXPECT_EQ(ann.picture, "out/s01/score.png");
  EXPECT_EQ(ann.source, "out/outbox.jsonl:1");
  const ClassAttempt& bo = (*read)[1];
  EXPECT_EQ(bo.student, "mailto:bo@school.example");  // no account, no name: the mailbox
  EXPECT_EQ(bo.task, "class2_cavity");                 // the trailing slash is not a segment
  EXPECT_EQ(bo.verb, "failed");
  EXPECT_TRUE(bo.pulp_exposed);
  EXPECT_TRUE(bo.guided);
  EXPECT_TRUE(bo.picture.empty());
  EXPECT_EQ(bo.source, "out/outbox.jsonl:3");
}

TEST(StatementInput, ReadsTheIdTheTaskKindAndATitleInAnotherLanguage) {
  const std::string text =
      R"({"id":"6f1c0e0a-0000-4000-8000-000000000001","actor":{"account":{"name":"s09"}},"verb":{"id":"x/completed"},)"
      R"("object":{"id":"https://school.example/courses/c1/tasks/access_cavity","definition":{"name":{"fr-FR":"Cavit\u00e9 d'acc\u00e8s"}}},)"
      R"("result":{"score":{"raw":77},"extensions":{"https://dentsim.invalid/xapi/extensions/task-kind":"access"}},"timestamp":"2026-11-27T08:00:00Z"})";
  auto read = parseStatements(text, "o.jsonl", ".", 0.0, nullptr);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read->size(), 1u);
  EXPECT_EQ((*read)[0].statement_id, "6f1c0e0a-0000-4000-8000-000000000001");
  EXPECT_EQ((*read)[0].task_kind, "access");
  EXPECT_EQ((*read)[0].task_title, "Cavit\u00e9 d'acc\u00e8s");
  EXPECT_EQ((*read)[0].student_name, "s09");  // no name: the id
  EXPECT_FALSE((*read)[0].success);           // "completed" says neither
}

// A bad line costs only itself: it is left out with one warning naming the file and line, and the
// statements before and after it are read. A file where no line is a statement is an error.
TEST(StatementInput, ABadLineIsLeftOutWithAWarningNamingFileAndLine) {
  const std::string good = statement(account("s01", "Ann"), "caries_removal", "passed", 80, "2026-11-27T08:00:00Z");
  const std::string later = statement(account("s02", "Bo"), "caries_removal", "failed", 20, "2026-11-27T09:00:00Z");
  std::vector<std::string> warnings;
  int skipped = 0;
  auto read = parseStatements(good + "\n{\"actor\": \n" + later + "\n[1]\n{\"id\":\"torn", "o.jsonl", ".", 0.0, &skipped, &warnings);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ((*read)[0].student, "s01");
  EXPECT_EQ((*read)[1].student, "s02");
  EXPECT_EQ((*read)[1].source, "o.jsonl:3");  // lines keep their numbers past the bad one
  EXPECT_EQ(skipped, 0);                      // bad lines are not statements without a score
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_EQ(warnings[0], "o.jsonl:2: not a JSON statement (malformed JSON); line left out");
  EXPECT_EQ(warnings[1], "o.jsonl:4: not a JSON object; line left out");
  EXPECT_EQ(warnings[2], "o.jsonl:5: not a JSON statement (malformed JSON); line left out");
  // With nobody to warn, the good lines are still read.
  EXPECT_EQ(parseStatements(good + "\n{\"actor\": \n", "o.jsonl", ".", 0.0, nullptr)->size(), 1u);
  // A file name holding a newline or an ESC stays on the warning's one line.
  warnings.clear();
  ASSERT_TRUE(parseStatements(good + "\nx\n", "o\n\x1b[2J.jsonl", ".", 0.0, nullptr, &warnings).ok());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "o\\x0a\\x1b[2J.jsonl:2: not a JSON statement (malformed JSON); line left out");
}

// The same through readAttempts, which the class report calls with a file.
TEST(StatementInput, AnOutboxFileWithABadLineIsReadWithAWarning) {
  test::TempDir dir;
  const std::string path = dir.file("outbox.jsonl");
  std::ofstream(path) << statement(account("s01", "Ann"), "caries_removal", "passed", 80, "2026-11-27T08:00:00Z") << "\n"
                      << "garbage\n"
                      << statement(account("s02", "Bo"), "caries_removal", "passed", 90, "2026-11-27T09:00:00Z") << "\n";
  std::vector<std::string> warnings;
  auto read = readAttempts(path, {}, nullptr, &warnings);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(read->size(), 2u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], path + ":2: not a JSON statement (malformed JSON); line left out");
  // Nothing but bad lines: not an outbox, and the error names the first.
  std::ofstream(path) << "garbage\nmore\n";
  EXPECT_EQ(readAttempts(path, {}, nullptr, nullptr).message(), path + ":1: not a JSON statement (malformed JSON)");
}

TEST(StatementInput, AMalformedLineIsNamedByFileAndLine) {
  auto broken = parseStatements("{\"actor\": \n", "o.jsonl", ".", 0.0, nullptr);
  ASSERT_FALSE(broken.ok());
  EXPECT_EQ(broken.message(), "o.jsonl:1: not a JSON statement (malformed JSON)");
  auto range = parseStatements(statement(account("s01", "Ann"), "t", "passed", 180, "2026-11-27T08:00:00Z"), "o.jsonl", ".", 0, nullptr);
  ASSERT_FALSE(range.ok());
  EXPECT_EQ(range.message(), "o.jsonl:1: result.score.raw: not a number in [0, 100]");
  auto no_actor = parseStatements(R"({"verb":{"id":"x/passed"},"object":{"id":"x/t"},"result":{"score":{"raw":5}}})", "o.jsonl", ".", 0, nullptr);
  ASSERT_FALSE(no_actor.ok());
  EXPECT_EQ(no_actor.message(), "o.jsonl:1: actor: missing or not an object");
}

// A cavity attempt made by hand: 5 of 25 for the under-cut, 20 of 25 for the over-cut (earned for
// the 80 % of the ideal cut), tilt in full, time not scored (no target), 3 points off for force; the
// pulp cap did not apply. Total 50 - 3 = 47 of 75.
constexpr const char* kPartsReport =
    R"({"format":"dentsim-score","version":2,"task":{"name":"class1_cavity","kind":"cavity","title":"Class I"},)"
    R"("total":47,"total_max":75,"statement_id":"0b6c6a57-2f7e-5b2e-9d1a-3c6f2e1d4a01",)"
    R"("components":{"undercut":{"points":5,"max":25,"formula":"25 * ...","completion_share":0.2},"overcut":{"points":20,"max":25,"table_points":25,"earned_share":0.8},)"
    R"("tilt":{"points":25,"max":25},"time":{"points":null,"max":25}},)"
    R"("deductions":{"force":{"points":3,"coefficient":1},"pulp_exposure":{"pulp_exposed":false,"cap":50,"cap_of_100":50,"applied":false}},)"
    R"("session":{"elapsed_s":271.5},"surface_agreement":{"band_mm":0.2,"within_percent":62.5,"beyond_percent":20,"short_percent":17.5,"walls":{}}})";

TEST(ScoreReportInput, ReadsThePartsTheTimeTheAgreementAndTheStatementId) {
  auto a = parseScoreReport(kPartsReport, "/c/ann/1/score.json", 0, "", {});
  ASSERT_TRUE(a.ok()) << a.message();
  EXPECT_EQ(a->statement_id, "0b6c6a57-2f7e-5b2e-9d1a-3c6f2e1d4a01");
  EXPECT_FALSE(a->from_statement);
  EXPECT_EQ(a->total_max, std::optional<double>(75.0));
  ASSERT_EQ(a->parts.size(), 5u);  // four components, then force; the cap that did not apply is left out
  const char* names[] = {"undercut", "overcut", "tilt", "time", "force"};
  for (size_t i = 0; i < 5; ++i) EXPECT_EQ(a->parts[i].name, names[i]);
  EXPECT_EQ(a->parts[0].points, std::optional<double>(5.0));
  EXPECT_EQ(a->parts[0].max, std::optional<double>(25.0));
  EXPECT_FALSE(a->parts[3].points);  // time: not scored
  EXPECT_TRUE(a->parts[4].deduction);
  EXPECT_EQ(a->parts[4].points, std::optional<double>(3.0));
  EXPECT_EQ(a->duration_s, std::optional<double>(271.5));
  ASSERT_TRUE(a->agreement);
  EXPECT_EQ(a->agreement->band_mm, 0.2);
  EXPECT_EQ(a->agreement->within_percent, 62.5);
  // An older report has none of them.
  auto old = parseScoreReport(kReport, "/c/ann/2/score.json", 0, "", {});
  ASSERT_TRUE(old.ok());
  EXPECT_TRUE(old->parts.empty());
  EXPECT_FALSE(old->duration_s);
  EXPECT_FALSE(old->agreement);
  EXPECT_TRUE(old->statement_id.empty());
  // An agreement with no samples (no ideal surface to measure at) is none, not 0 %.
  std::string unmeasured = kReport;
  unmeasured.insert(unmeasured.size() - 1, R"(,"surface_agreement":{"band_mm":0.2,"samples":0,"within_percent":0})");
  EXPECT_FALSE(parseScoreReport(unmeasured, "u.json", 0, "", {})->agreement);
  std::string bad = kReport;
  bad.insert(bad.size() - 1, R"(,"statement_id":7)");
  EXPECT_EQ(parseScoreReport(bad, "b.json", 0, "", {}).message(), "b.json: statement_id: not a string");
}

TEST(ScoreReportInput, PartsAreReadLenientlyAndAnAppliedCapIsKept) {
  const auto components = nlohmann::ordered_json::parse(
      R"({"removal":{"points":40,"max":50},"note":"text","odd":{"max":10},"half":{"points":"x","max":10}})");
  const auto deductions = nlohmann::ordered_json::parse(R"({"pulp_exposure":{"cap":50,"applied":true},"healthy":{"points":null},"x":[1]})");
  const std::vector<AttemptPart> parts = readParts(components, deductions);
  ASSERT_EQ(parts.size(), 3u);  // removal; the cap that applied; healthy not scored
  EXPECT_EQ(parts[0].name, "removal");
  EXPECT_EQ(parts[1].name, "pulp_exposure");
  EXPECT_EQ(parts[1].cap, std::optional<double>(50.0));
  EXPECT_FALSE(parts[1].points);
  EXPECT_EQ(parts[2].name, "healthy");
  EXPECT_FALSE(parts[2].points);
  // What each cost: 10 of 50 is a fifth; a cap is all; a deduction counts against the whole score.
  EXPECT_EQ(pointsLost(parts[0]), std::optional<double>(10.0));
  EXPECT_EQ(lostShare(parts[0], 100.0), std::optional<double>(0.2));
  EXPECT_EQ(lostShare(parts[1], 100.0), std::optional<double>(1.0));
  EXPECT_FALSE(lostShare(parts[2], 100.0));
  AttemptPart force;
  force.name = "force";
  force.deduction = true;
  force.points = 3.0;
  EXPECT_EQ(lostShare(force, 75.0), std::optional<double>(0.04));
  EXPECT_EQ(lostShare(force, std::nullopt), std::optional<double>(0.03));  // out of 100 when not said
}

// A statement built from the hand-made report carries its parts, time and agreement, so that an
// attempt read only from an outbox shows them too.
TEST(StatementInput, ReadsThePartsTimeAndAgreementTheStatementCarries) {
  Task t;
  t.name = "class1_cavity";
  t.kind = TaskKind::Cavity;
  t.title = "Class I";
  LearnerContext l;
  l.student = "s01";
  AttemptFacts f;
  f.attempt_key = "00000000deadbeef";
  f.timestamp = "2026-11-27T08:00:00Z";
  auto st = buildStatement(t, nlohmann::ordered_json::parse(kPartsReport), l, f);
  ASSERT_TRUE(st.ok()) << st.message();
  auto read = parseStatements(st->dump(), "o.jsonl", ".", 0.0, nullptr);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read->size(), 1u);
  const ClassAttempt& a = (*read)[0];
  EXPECT_TRUE(a.from_statement);
  EXPECT_EQ(a.statement_id, statementId("00000000deadbeef", "class1_cavity", "s01"));
  EXPECT_EQ(a.total_max, std::optional<double>(75.0));
  ASSERT_EQ(a.parts.size(), 5u);
  EXPECT_EQ(a.parts[0].name, "undercut");
  EXPECT_EQ(a.parts[0].points, std::optional<double>(5.0));
  EXPECT_EQ(a.parts[1].earned_share, std::optional<double>(0.8));
  EXPECT_FALSE(a.parts[3].points);
  EXPECT_TRUE(a.parts[4].deduction);
  EXPECT_DOUBLE_EQ(*a.duration_s, 271.5);
  ASSERT_TRUE(a.agreement);
  EXPECT_EQ(a.agreement->within_percent, 62.5);
}

// Six attempts, counted by hand: alice 40 then 70 at caries removal, bob 95 (pulp exposed) at
// caries removal and 55 (failed) at class II, carol 80 with the pulp open at the access cavity
// (the exercise), and carol 45 at caries removal. Pass marks: 50 for all, 60 for class II.
ClassReport sampleReport() {
  auto attempt = [](std::string student, std::string task, double score, double t) {
    ClassAttempt a;
    a.student = a.student_name = std::move(student);
    a.task = a.task_title = std::move(task);
    a.score = score;
    a.time_s = t;
    a.verb = "scored";
    a.source = a.student + "@" + std::to_string(int(t));
    return a;
  };
  std::vector<ClassAttempt> all;
  all.push_back(attempt("alice", "caries_removal", 70, 2000));
  all.push_back(attempt("alice", "caries_removal", 40, 1000));
  all.push_back(attempt("bob", "caries_removal", 95, 1500));
  all.back().pulp_exposed = true;
  all.push_back(attempt("bob", "class2_cavity", 55, 3000));
  all.back().verb = "failed";
  all.push_back(attempt("carol", "access_cavity", 80, 2500));  // a statement's task: the kind is looked up
  all.back().pulp_exposed = true;
  all.push_back(attempt("carol", "caries_removal", 45, 3500));
  all.back().success = true;  // said to pass, yet below the mark: flagged for the mark alone
  ClassReportOptions options;
  options.pass_mark = 50;
  options.task_pass_marks["class2_cavity"] = 60;
  return buildClassReport(std::move(all), options);
}

// Without a mark from the teacher, a built-in task brings its own (70 in the course files), and a
// task dentsim does not know has none; the teacher's class-wide mark still wins over the task's.
TEST(ClassReportModel, ABuiltInTasksOwnPassMarkIsTheFallback) {
  ClassReportOptions none;
  auto own = builtinTask("class2_cavity");
  ASSERT_TRUE(own.ok()) << own.message();
  ASSERT_TRUE(own->pass_mark.has_value());
  EXPECT_EQ(passMarkFor(none, "class2_cavity"), own->pass_mark);
  EXPECT_EQ(passMarkFor(none, "a_task_of_my_own"), std::nullopt);
  ClassReportOptions forty;
  forty.pass_mark = 40;
  EXPECT_EQ(passMarkFor(forty, "class2_cavity"), std::optional<double>(40.0));
  ClassAttempt a;
  a.student = a.student_name = "dan";
  a.task = a.task_title = "class2_cavity";
  a.score = *own->pass_mark - 1;
  a.time_s = 1000;
  a.verb = "scored";
  a.source = "dan@1000";
  const ClassReport r = buildClassReport({a}, none);
  ASSERT_EQ(r.flags.size(), 1u) << "just below the task's own mark";
}

TEST(ClassReportModel, CountsAttemptsPerStudentAndTaskAndBinsTheScores) {
  const ClassReport r = sampleReport();
  ASSERT_EQ(r.attempts.size(), 6u);
  EXPECT_EQ(r.first_s, 1000.0);
  EXPECT_EQ(r.last_s, 3500.0);
  ASSERT_EQ(r.students.size(), 3u);
  EXPECT_EQ(r.students[0].id, "alice");
  EXPECT_EQ(r.students[0].attempts, 2);
  EXPECT_EQ(r.students[0].tasks, 1);
  EXPECT_EQ(r.students[1].attempts, 2);
  EXPECT_EQ(r.students[1].tasks, 2);
  ASSERT_EQ(r.tasks.size(), 3u);  // by name: access, caries, class II
  const TaskSummary& access = r.tasks[0];
  const TaskSummary& caries = r.tasks[1];
  const TaskSummary& class2 = r.tasks[2];
  EXPECT_EQ(access.name, "access_cavity");
  EXPECT_EQ(caries.name, "caries_removal");
  EXPECT_EQ(caries.attempts, 4);
  // 40 -> bin 4, 45 -> bin 4, 70 -> bin 7, 95 -> bin 9.
  const std::array<int, kScoreBins> bins{0, 0, 0, 0, 2, 0, 0, 1, 0, 1};
  EXPECT_EQ(caries.bins, bins);
  EXPECT_EQ(caries.min, 40.0);
  EXPECT_EQ(caries.median, 45.0);  // nearest rank: the 2nd of 4
  EXPECT_EQ(caries.max, 95.0);
  EXPECT_EQ(caries.students, (std::vector<std::string>{"alice", "bob", "carol"}));
  EXPECT_EQ(class2.pass_mark, std::optional<double>(60.0));
  EXPECT_EQ(caries.pass_mark, std::optional<double>(50.0));
  EXPECT_EQ(scoreBin(100.0), 9);
  EXPECT_EQ(scoreBin(0.0), 0);
  EXPECT_EQ(scoreBin(9.99), 0);
  // alice's caries attempts, oldest first.
  const std::vector<size_t> mine = attemptsOf(r, "alice", "caries_removal");
  ASSERT_EQ(mine.size(), 2u);
  EXPECT_EQ(r.attempts[mine[0]].score, 40.0);
  EXPECT_EQ(r.attempts[mine[1]].score, 70.0);
}

TEST(ClassReportModel, FlagsPulpExposureFailuresAndScoresBelowThePassMark) {
  const ClassReport r = sampleReport();
  // In time order: alice 40 (mark), bob 95 (pulp), bob 55 (mark of 60, failed), carol 45 (mark);
  // carol's open pulp in the access cavity is the exercise, not a fault.
  ASSERT_EQ(r.flags.size(), 4u);
  auto flagged = [&](size_t i) { return r.attempts[r.flags[i].attempt]; };
  EXPECT_EQ(flagged(0).source, "alice@1000");
  EXPECT_EQ(r.flags[0].reasons, (std::vector<std::string>{"below the pass mark of 50"}));
  EXPECT_EQ(flagged(1).source, "bob@1500");
  EXPECT_EQ(r.flags[1].reasons, (std::vector<std::string>{"pulp exposed"}));
  EXPECT_EQ(flagged(2).source, "bob@3000");
  EXPECT_EQ(r.flags[2].reasons, (std::vector<std::string>{"below the pass mark of 60", "failed"}));
  EXPECT_EQ(flagged(3).source, "carol@3500");
  EXPECT_EQ(r.attempts[3].task_kind, "access");  // carol at 2500 s
}

TEST(ClassReportModel, AStatementGivenTwiceCountsOnce) {
  std::vector<ClassAttempt> all(4);
  const char* ids[] = {"a", "b", "a", ""};  // the third repeats the first; the fourth, a report, has no id
  for (size_t i = 0; i < all.size(); ++i) {
    all[i].student = "s";
    all[i].task = "caries_removal";
    all[i].statement_id = ids[i];
    all[i].from_statement = i < 3;
    all[i].time_s = double(i);
  }
  const ClassReport r = buildClassReport(std::move(all), {});
  EXPECT_EQ(r.attempts.size(), 3u);
  EXPECT_EQ(r.duplicates, 1);
  EXPECT_EQ(r.attempts[2].time_s, 3.0);
}

// A score report and the statement with its id are one attempt, in whichever order they come: the
// row keeps the report's score, picture and parts, and takes the statement's student, time and verdict.
TEST(ClassReportModel, AReportAndItsStatementCountOnceAndOtherIdsApart) {
  ClassAttempt report;
  report.student = report.student_name = "try-folder";
  report.task = report.task_title = "class1_cavity";
  report.score = 52;
  report.time_s = 5000;  // the file's time, copied later
  report.verb = "scored";
  report.picture = "ann/1/score.png";
  report.parts.resize(1);
  report.parts[0].name = "undercut";
  report.parts[0].points = 5.0;
  report.parts[0].max = 25.0;
  report.source = "ann/1/score.json";
  report.statement_id = "id-1";
  ClassAttempt statement;
  statement.from_statement = true;
  statement.student = "s01";
  statement.student_name = "Ann";
  statement.task = statement.task_title = "class1_cavity";
  statement.score = 52;
  statement.time_s = 1000;
  statement.verb = "failed";
  statement.success = false;
  statement.duration_s = 271.5;
  statement.source = "outbox.jsonl:1";
  statement.statement_id = "id-1";
  for (bool statement_first : {false, true}) {
    std::vector<ClassAttempt> both = statement_first ? std::vector<ClassAttempt>{statement, report} : std::vector<ClassAttempt>{report, statement};
    const ClassReport r = buildClassReport(both, {});
    ASSERT_EQ(r.attempts.size(), 1u);
    EXPECT_EQ(r.merged, 1);
    EXPECT_EQ(r.duplicates, 0);
    const ClassAttempt& a = r.attempts[0];
    EXPECT_EQ(a.student, "s01");
    EXPECT_EQ(a.student_name, "Ann");
    EXPECT_EQ(a.time_s, 1000.0);
    EXPECT_EQ(a.verb, "failed");
    EXPECT_EQ(a.picture, "ann/1/score.png");
    EXPECT_EQ(a.parts.size(), 1u);
    EXPECT_EQ(a.duration_s, std::optional<double>(271.5));  // the report had none: the statement's
    EXPECT_EQ(a.source, "ann/1/score.json, outbox.jsonl:1");
    ASSERT_EQ(r.flags.size(), 1u);  // failed, by the statement's verdict
  }
  // Scored again to another total since: the report's score stands and the old verdict is not shown.
  ClassAttempt rescored = report;
  rescored.score = 75;
  EXPECT_EQ(buildClassReport({rescored, statement}, {}).attempts[0].verb, "scored");
  // Two different attempts: two rows.
  ClassAttempt other = statement;
  other.statement_id = "id-2";
  const ClassReport two = buildClassReport({report, other}, {});
  EXPECT_EQ(two.attempts.size(), 2u);
  EXPECT_EQ(two.merged, 0);
  // The same report twice (a copied folder) is a copy.
  const ClassReport copied = buildClassReport({report, report, statement}, {});
  EXPECT_EQ(copied.attempts.size(), 1u);
  EXPECT_EQ(copied.duplicates, 1);
}

TEST(ClassReportModel, ListsStudentsByNameWhateverTheCase) {
  std::vector<ClassAttempt> all(3);
  const char* names[] = {"Chlo\u00e9", "ben", "Ana"};
  for (size_t i = 0; i < all.size(); ++i) {
    all[i].student = "id" + std::to_string(i);
    all[i].student_name = names[i];
    all[i].task = "caries_removal";
  }
  const ClassReport r = buildClassReport(std::move(all), {});
  ASSERT_EQ(r.students.size(), 3u);
  EXPECT_EQ(r.students[0].name, "Ana");
  EXPECT_EQ(r.students[1].name, "ben");  // a plain byte order puts it after "Chlo\u00e9"
  EXPECT_EQ(r.students[2].id, "id0");
}

TEST(ClassReportHtml, EscapesEverythingThatCameFromAFile) {
  EXPECT_EQ(htmlEscape(R"(<b>"Tom" & 'Jerry'</b>)"), "&lt;b&gt;&quot;Tom&quot; &amp; &#39;Jerry&#39;&lt;/b&gt;");
  ClassAttempt a;
  a.student = "<script>alert(1)</script>";
  a.student_name = "Eve \"<img src=x>\"";
  a.task = "caries_removal";
  a.task_title = "Caries & <co>";
  a.score = 50;
  a.verb = "scored";
  a.source = "a<b>.json";
  const std::string html = classReportHtml(buildClassReport({a}, {}), {});
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<img src=x>"), std::string::npos);
  EXPECT_EQ(html.find("<co>"), std::string::npos);
  EXPECT_NE(html.find("Eve &quot;&lt;img src=x&gt;&quot;"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(html.find("Caries &amp; &lt;co&gt;"), std::string::npos);
}

TEST(ClassReportHtml, NamesAreBidiIsolatedAndShortened) {
  ClassAttempt a;
  a.student = "s1";
  a.student_name = "Ada \u202e";  // an unclosed right-to-left override: "76.1" after it would read "1.67"
  a.task = "caries_removal";
  a.task_title = "Caries";
  a.score = 76.1;
  a.verb = "scored";
  ClassAttempt b = a;
  b.student = "s2";
  b.student_name = std::string(100000, 'w');
  const std::string html = classReportHtml(buildClassReport({a, b}, {}), {});
  // In tables and captions the name sits in <bdi>; in SVG text and attributes between FSI and PDI.
  EXPECT_NE(html.find("<td><bdi>Ada \u202e</bdi></td>"), std::string::npos);
  EXPECT_NE(html.find("<figcaption><bdi>Ada \u202e</bdi> \u2014 <bdi>Caries</bdi> \u2014 76.1 \u2014 "), std::string::npos);
  EXPECT_NE(html.find("<title>\u2068Ada \u202e\u2069: 76.1 on "), std::string::npos);
  EXPECT_EQ(countOf(html, "Ada \u202e"), countOf(html, "Ada \u202e</bdi>") + countOf(html, "Ada \u202e\u2069"));
  // The 100 kB name is shown as its first 120 bytes: the page stays far smaller than the name.
  EXPECT_NE(html.find("<bdi>" + std::string(120, 'w') + "\u2026</bdi>"), std::string::npos);
  EXPECT_EQ(html.find(std::string(121, 'w')), std::string::npos);
}

// The hand-made report: the under-cut lost 20 of 25 (a deep colour), the over-cut 5, tilt none,
// time not scored, force 3 of the 75 off; its time and agreement are shown, and an older report
// shows dashes where it says nothing.
TEST(ClassReportHtml, EachAttemptShowsWhichPartLostPointsItsTimeAndItsAgreement) {
  auto a = parseScoreReport(kPartsReport, "/c/ann/1/score.json", 0, "", {});
  ASSERT_TRUE(a.ok()) << a.message();
  const std::string parts = partsHtml(*a);
  EXPECT_NE(parts.find(R"(<span class="part lost lost-3" data-part="undercut" data-lost="20.00" title="undercut 5.0 of 25">)"),
            std::string::npos) << parts;
  EXPECT_NE(parts.find(R"x(<span class="part lost lost-1" data-part="overcut" data-lost="5.00" title="overcut 20.0 of 25 (80 % earned)">)x"),
            std::string::npos) << parts;
  EXPECT_NE(parts.find(R"(<span class="part kept" data-part="tilt" data-lost="0.00")"), std::string::npos) << parts;
  EXPECT_NE(parts.find(R"(<span class="part unscored" data-part="time" data-lost="" title="time not scored">)"), std::string::npos);
  EXPECT_NE(parts.find(R"(<span class="part lost lost-1 deduction" data-part="force" data-lost="3.00" title="force 3.0 off">)"),
            std::string::npos) << parts;
  EXPECT_NE(parts.find(R"(aria-label="parts: undercut 5.0 of 25; overcut 20.0 of 25 (80 % earned); tilt 25.0 of 25; time not scored; force 3.0 off")"),
            std::string::npos) << parts;
  EXPECT_NE(parts.find("<span class=\"why\">undercut \u221220.0, overcut \u22125.0, force \u22123.0; not scored: time</span>"), std::string::npos) << parts;
  EXPECT_EQ(countOf(parts, "data-part="), 5u);

  auto old = parseScoreReport(kReport, "/c/bob/1/score.json", 0, "", {});
  ASSERT_TRUE(old.ok());
  EXPECT_EQ(partsHtml(*old), "\u2014");
  const std::string html = classReportHtml(buildClassReport({*a, *old}, {}), {});
  EXPECT_NE(html.find(">4:32<"), std::string::npos);  // 271.5 s, to the second
  EXPECT_NE(html.find(">62.5 % within \u00b10.20 mm<"), std::string::npos);
  // bob's row: no parts, no time, no agreement.
  EXPECT_NE(html.find("<td class=\"parts\">\u2014</td><td class=\"num\">\u2014</td><td class=\"num\">\u2014</td>"),
            std::string::npos);
  // A part's name from a file is escaped like every other text.
  ClassAttempt odd = *a;
  odd.parts[0].name = "<b>x\"";
  EXPECT_EQ(partsHtml(odd).find("<b>"), std::string::npos);
  EXPECT_NE(partsHtml(odd).find("data-part=\"&lt;b&gt;x&quot;\""), std::string::npos);
}

// Each distinct picture goes into the page once: the six attempts name the same picture by two
// paths (equal bytes) and another picture once; the first showing of each embeds it, the others link
// to it by its id. A picture past the cap is a link to its file, its path escaped.
TEST(ClassReportHtml, EachDistinctPictureIsEmbeddedOnceAndOthersLinked) {
  ClassReport r = sampleReport();
  ASSERT_EQ(r.attempts.size(), 6u);
  const char* names[6] = {"a.png", "a.png", "copy-of-a.png", "b.png", "a.png", "far/x \"<y>.png"};
  for (size_t i = 0; i < 6; ++i) r.attempts[i].picture = names[i];
  ReportPictures pictures;
  EXPECT_TRUE(pictures.add("a.png", {1, 2, 3}));
  EXPECT_FALSE(pictures.add("copy-of-a.png", {1, 2, 3}));  // the same bytes: no second copy
  EXPECT_TRUE(pictures.add("b.png", {4, 5, 6}));
  pictures.linked.insert("far/x \"<y>.png");
  EXPECT_EQ(pictures.pngs.size(), 2u);
  EXPECT_EQ(pictures.count(), 4u);
  const std::string html = classReportHtml(r, pictures);
  EXPECT_EQ(countOf(html, "data:image/png;base64,AQID"), 1u);
  EXPECT_EQ(countOf(html, "data:image/png;base64,BAUG"), 1u);
  EXPECT_EQ(countOf(html, "\" id=\"pic-0\" src=\"data:image/png;base64,AQID\">"), 1u);
  EXPECT_EQ(countOf(html, "\" id=\"pic-1\" src=\"data:image/png;base64,BAUG\">"), 1u);
  EXPECT_EQ(countOf(html, "<a class=\"samepic\" href=\"#pic-0\">"), 3u);
  EXPECT_EQ(countOf(html, "<a class=\"samepic\""), 3u);
  EXPECT_EQ(countOf(html, "<a class=\"filepic\""), 1u);
  EXPECT_NE(html.find("/far/x%20%22%3Cy%3E.png\">far/x &quot;&lt;y&gt;.png</a>"), std::string::npos);
  EXPECT_EQ(html.find("<y>"), std::string::npos);
  EXPECT_EQ(countOf(html, "no picture"), 0u);
}

TEST(ClassReportHtml, Base64MatchesTheStandardsVectors) {
  auto b64 = [](const std::string& s) { return base64({reinterpret_cast<const uint8_t*>(s.data()), s.size()}); };
  // RFC 4648, section 10.
  EXPECT_EQ(b64(""), "");
  EXPECT_EQ(b64("f"), "Zg==");
  EXPECT_EQ(b64("fo"), "Zm8=");
  EXPECT_EQ(b64("foo"), "Zm9v");
  EXPECT_EQ(b64("foob"), "Zm9vYg==");
  EXPECT_EQ(b64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(b64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::vector<uint8_t>{0xff, 0xfe, 0x3e}), "//4+");
}

TEST(ClassReportHtml, PlotsOneLinePerStudentAndOneBarPerFilledBin) {
  const ClassReport r = sampleReport();
  const TaskSummary& caries = r.tasks[1];
  const std::string plot = progressSvg(r, caries);
  EXPECT_EQ(countOf(plot, "<polyline"), 3u);  // alice, bob, carol
  EXPECT_EQ(countOf(plot, "<circle"), 4u);    // one dot per attempt
  EXPECT_EQ(countOf(plot, "class=\"pass\""), 1u);
  EXPECT_NE(plot.find(studentColour(0)), std::string::npos);
  const std::string bars = histogramSvg(caries);
  EXPECT_EQ(countOf(bars, "<rect"), 3u);      // bins 4, 7 and 9
  EXPECT_NE(bars.find(">2</text>"), std::string::npos);  // bin 4 holds two
  // The page: a plot pair per task, the flagged table's rows, a place for each attempt's picture.
  ClassReport with_picture = r;
  with_picture.attempts[0].picture = "p.png";
  ReportPictures one;
  one.add("p.png", {1, 2, 3});
  const std::string html = classReportHtml(with_picture, one);
  EXPECT_EQ(countOf(html, "<svg class=\"progress\""), 3u);
  EXPECT_EQ(countOf(html, "<svg class=\"histogram\""), 3u);
  EXPECT_EQ(countOf(html, "<tr class=\"flagged\">"), 4u);
  EXPECT_EQ(countOf(html, "<figure>"), 6u);
  EXPECT_EQ(countOf(html, "src=\"data:image/png;base64,AQID\""), 1u);
  EXPECT_EQ(countOf(html, "no picture"), 5u);
  EXPECT_EQ(countOf(html, "(guided)"), 0u);
  // A guided attempt says so in the table, its dot's title and its picture's caption.
  with_picture.attempts[0].guided = true;
  const std::string guided = classReportHtml(with_picture, {});
  EXPECT_EQ(countOf(guided, "(guided)"), 1u);
  EXPECT_EQ(countOf(guided, ", guided</title>"), 1u);
  EXPECT_EQ(countOf(guided, "\u2014 guided</figcaption>"), 1u);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));  // the SVG namespace is the only URL
  EXPECT_EQ(html.find("https://"), std::string::npos);
}

}  // namespace
}  // namespace dentsim
