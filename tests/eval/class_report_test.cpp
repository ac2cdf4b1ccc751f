// Tests of the class report's reading and model (attempt_reader, class_report) and of its page's text, plots and escaping (class_report_html).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "eval/attempt_reader.h"
#include "eval/class_report.h"
#include "eval/class_report_html.h"
#include "eval/cut_score.h"

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

TEST(StatementInput, AMalformedLineIsNamedByFileAndLine) {
  const std::string good = statement(account("s01", "Ann"), "caries_removal", "passed", 80, "2026-11-27T08:00:00Z");
  auto broken = parseStatements(good + "\n{\"actor\": \n", "o.jsonl", ".", 0.0, nullptr);
  ASSERT_FALSE(broken.ok());
  EXPECT_EQ(broken.message(), "o.jsonl:2: not a JSON statement (malformed JSON)");
  auto range = parseStatements(statement(account("s01", "Ann"), "t", "passed", 180, "2026-11-27T08:00:00Z"), "o.jsonl", ".", 0, nullptr);
  ASSERT_FALSE(range.ok());
  EXPECT_EQ(range.message(), "o.jsonl:1: result.score.raw: not a number in [0, 100]");
  auto no_actor = parseStatements(R"({"verb":{"id":"x/passed"},"object":{"id":"x/t"},"result":{"score":{"raw":5}}})", "o.jsonl", ".", 0, nullptr);
  ASSERT_FALSE(no_actor.ok());
  EXPECT_EQ(no_actor.message(), "o.jsonl:1: actor: missing or not an object");
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
  const char* ids[] = {"a", "b", "a", ""};  // the third repeats the first; a score report has no id
  for (size_t i = 0; i < all.size(); ++i) {
    all[i].student = "s";
    all[i].task = "caries_removal";
    all[i].statement_id = ids[i];
    all[i].time_s = double(i);
  }
  const ClassReport r = buildClassReport(std::move(all), {});
  EXPECT_EQ(r.attempts.size(), 3u);
  EXPECT_EQ(r.duplicates, 1);
  EXPECT_EQ(r.attempts[2].time_s, 3.0);
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
  const std::string html = classReportHtml(with_picture, {{"p.png", {1, 2, 3}}});
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
