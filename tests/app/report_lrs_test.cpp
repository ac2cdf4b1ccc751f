// Tests of `dentsim report --lrs`: three students' statements sent to a real LRS and read back from it give the same page as `report` on their three outboxes, read one page or two statements at a time; --since leaves out what the LRS stored before; a course's statements only; errors are one line.
//
// The LRS is Learning Locker's statement service (npm xapi-statements, tests/real_lrs.h), started by
// each test and stopped after it. The stand-in tests/xapi/lrs_recorder.py serves only the one fault
// the real LRS never shows: an answer that is not JSON.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "free_port.h"
#include "real_lrs.h"
#include "test_support.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;
using test::runCommand;
using test::TempDir;

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The page with its "from" cells emptied. They say where each attempt was read: "outbox.jsonl:2" for
// an outbox, "LRS <url>:5" for the LRS; nothing else on the page may differ between the two.
// (Not std::regex: GCC's -O1 sanitizer build warns falsely inside <regex>, and that build treats
// warnings as errors.)
std::string withoutSources(std::string html) {
  const std::string open = "<td class=\"from\">";
  for (size_t at = html.find(open); at != std::string::npos; at = html.find(open, at + open.size())) {
    const size_t text = at + open.size(), end = html.find('<', text);
    if (end == std::string::npos) break;
    html.erase(text, end - text);
  }
  return html;
}

// One recorded attempt (the careful removal) scored twice for each of three students of course
// cons-101, once with its session and once without (the final tooth then names the attempt, so the
// two are two statements), into one outbox per student, plus the same for a student of another
// course. Made once for the suite, and only by the tests that need them (ctest runs each test in a
// process of its own): the demo drills on the CPU without frames (VK_ICD_FILENAMES points nowhere).
class ReportLrs : public ::testing::Test {
 protected:
  // The learning-record config every run of the suite reads (DENTSIM_CONFIG): the course and its IRIs.
  static void SetUpTestSuite() {
    suite_dir_ = std::make_unique<TempDir>();
    outboxes_made_.reset();  // a new folder each time the suite runs (--gtest_repeat), so made again
    std::ofstream(suite_dir_->file("learning.json")) << R"({"course": "cons-101", "activity_base": "https://school.example/xapi"})";
  }
  static void TearDownTestSuite() { suite_dir_.reset(); }

  // Makes the four outboxes the first time in the suite's folder; empty when they are there, else
  // what went wrong.
  static std::string makeOutboxes() {
    if (!outboxes_made_) outboxes_made_ = [] {
      const TempDir& d = *suite_dir_;
      std::ofstream(d.file("fast.json")) << R"({"format":"dentsim-params","version":1,"cutting":{"removal_rate_mm3_per_s":40},)"
                                            R"("point_shell":{"head_spacing_mm":0.1,"shank_spacing_mm":0.2}})";
      const test::NoLeakCheckForGpuChild no_leak_check;  // the Vulkan loader looks for a device before the CPU path
      const std::string demo = d.file("demo");
      const auto r = runCommand("VK_ICD_FILENAMES=/nonexistent.json DENTSIM_CONFIG= XDG_CONFIG_HOME=" + d.file("xdg") + " " +
                                std::string(DENTSIM_BINARY) + " demo --headless --level 6 --mirror none --no-sound --attempt expert --params " +
                                d.file("fast.json") + " --out " + demo);
      if (r.exit_code != 0) return r.output;
      const char* students[] = {"s2001", "s2002", "s2003", "s9009"};
      for (int s = 0; s < 4; ++s)
        for (const std::string& session : {" --session " + demo + "/session.dses", std::string()}) {
          const auto scored = dentsim("score --task caries --initial " + demo + "/initial.dvol --final " + demo + "/final.dvol" + session +
                                      " -o " + d.file("s.json") + " --student " + students[s] + " --outbox " + outbox(s) +
                                      (s == 3 ? " --course other-course" : ""));
          if (scored.exit_code != 0) return scored.output;
        }
      return std::string();
    }();
    return *outboxes_made_;
  }

  // Student k's outbox (k = 3: the other course's student).
  static std::string outbox(int k) { return suite_dir_->file("outbox" + std::to_string(k) + "/outbox.jsonl"); }
  // dentsim with the suite's config, the LRS credentials in the environment, nothing from the user's home.
  static test::CommandResult dentsim(const std::string& args) {
    return runCommand("DENTSIM_LRS_USERNAME=lab DENTSIM_LRS_PASSWORD='s3cret pw' DENTSIM_CONFIG=" + suite_dir_->file("learning.json") +
                      " XDG_CONFIG_HOME=" + suite_dir_->file("xdg") + " " + std::string(DENTSIM_BINARY) + " " + args);
  }
  // Each outbox in turn to the LRS, as each student's PC sends its own: a copy in this test's folder,
  // without the sent log that another test's sending left beside the suite's outbox.
  void send(const test::RealLrs& lrs, std::initializer_list<int> students) const {
    for (int k : students) {
      const std::string copy = dir_.file("pc" + std::to_string(k) + ".jsonl");
      fs::copy_file(outbox(k), copy, fs::copy_options::overwrite_existing);
      const auto r = dentsim("outbox send --outbox " + copy + " --lrs " + lrs.url());
      ASSERT_EQ(r.exit_code, 0) << r.output;
      ASSERT_NE(r.output.find("learning records: 2 sent"), std::string::npos) << r.output;
    }
  }

  TempDir dir_;
  static std::unique_ptr<TempDir> suite_dir_;  // the outboxes, shared by the suite's tests
  static std::optional<std::string> outboxes_made_;  // makeOutboxes' answer for this folder
};

std::unique_ptr<TempDir> ReportLrs::suite_dir_;
std::optional<std::string> ReportLrs::outboxes_made_;

TEST_F(ReportLrs, TheLrsGivesTheSamePageAsTheThreeOutboxesInOnePageOrTwoStatementsAtATime) {
  if (const std::string why = test::RealLrs::missing(); !why.empty()) GTEST_SKIP() << why;
  ASSERT_EQ(makeOutboxes(), "");
  test::RealLrs lrs(dir_, "lrs", "lab", "s3cret pw");
  ASSERT_TRUE(lrs.up()) << lrs.log();
  send(lrs, {0, 1, 2, 3});
  const auto from_files = dentsim("report " + outbox(0) + " " + outbox(1) + " " + outbox(2) + " -o " + dir_.file("files.html"));
  ASSERT_EQ(from_files.exit_code, 0) << from_files.output;
  EXPECT_NE(from_files.output.find("6 attempts by 3 students at 1 tasks"), std::string::npos) << from_files.output;
  // The course comes from the config, as it does for sending; s9009's other course is not asked for.
  const auto from_lrs = dentsim("report --lrs " + lrs.url() + " -o " + dir_.file("lrs.html"));
  ASSERT_EQ(from_lrs.exit_code, 0) << from_lrs.output;
  EXPECT_NE(from_lrs.output.find("read 6 statement(s) of course cons-101 from LRS " + lrs.url() + " in 1 request(s)"), std::string::npos)
      << from_lrs.output;
  EXPECT_NE(from_lrs.output.find("6 attempts by 3 students at 1 tasks"), std::string::npos) << from_lrs.output;
  const std::string page = readText(dir_.file("lrs.html"));
  EXPECT_EQ(withoutSources(page), withoutSources(readText(dir_.file("files.html"))));
  EXPECT_NE(page.find("<td class=\"from\">LRS " + lrs.url() + ":6</td>"), std::string::npos);
  EXPECT_EQ(page.find("s9009"), std::string::npos);
  // Two a request: the LRS's "more" links are followed to the end, and the page is the same to the byte.
  const auto paged = dentsim("report --lrs " + lrs.url() + " --lrs-page-size 2 -o " + dir_.file("paged.html"));
  ASSERT_EQ(paged.exit_code, 0) << paged.output;
  EXPECT_NE(paged.output.find("read 6 statement(s) of course cons-101 from LRS " + lrs.url() + " in 3 request(s)"), std::string::npos)
      << paged.output;
  EXPECT_EQ(readText(dir_.file("paged.html")), page);
  EXPECT_EQ(lrs.requests("GET", "/xAPI/statements?activity=", 200), 1 + 3);
  // The other course by --course: its one student alone.
  const auto other = dentsim("report --lrs " + lrs.url() + " --course other-course -o " + dir_.file("other.html"));
  ASSERT_EQ(other.exit_code, 0) << other.output;
  EXPECT_NE(other.output.find("2 attempts by 1 students"), std::string::npos) << other.output;
}

TEST_F(ReportLrs, SinceLeavesOutWhatTheLrsStoredBefore) {
  if (const std::string why = test::RealLrs::missing(); !why.empty()) GTEST_SKIP() << why;
  ASSERT_EQ(makeOutboxes(), "");
  test::RealLrs lrs(dir_, "lrs", "lab", "s3cret pw");
  ASSERT_TRUE(lrs.up()) << lrs.log();
  send(lrs, {0});
  // When the LRS stored the first student's last statement, by its own clock: the next ones come after.
  std::string read_error;
  const std::vector<nlohmann::json> first = lrs.statements(&read_error);
  ASSERT_EQ(first.size(), 2u) << read_error;
  const std::string stored = first.back()["stored"].get<std::string>();
  send(lrs, {1, 2});
  const auto later = dentsim("report --lrs " + lrs.url() + " --since " + stored + " -o " + dir_.file("later.html"));
  ASSERT_EQ(later.exit_code, 0) << later.output;
  EXPECT_NE(later.output.find("read 4 statement(s)"), std::string::npos) << later.output;
  const auto files = dentsim("report " + outbox(1) + " " + outbox(2) + " -o " + dir_.file("files.html"));
  ASSERT_EQ(files.exit_code, 0) << files.output;
  EXPECT_EQ(withoutSources(readText(dir_.file("later.html"))), withoutSources(readText(dir_.file("files.html"))));
  // A date alone is midnight UTC: a day long past takes all six, one to come none.
  const auto all = dentsim("report --lrs " + lrs.url() + " --since 2000-01-01 -o " + dir_.file("all.html"));
  EXPECT_NE(all.output.find("read 6 statement(s)"), std::string::npos) << all.output;
  test::expectCleanFailure(dentsim("report --lrs " + lrs.url() + " --since 2999-01-01 -o " + dir_.file("none.html")), "LRS",
                           "no scored attempt", dir_.file("none.html"));
  test::expectCleanFailure(dentsim("report --lrs " + lrs.url() + " --since yesterday -o " + dir_.file("bad.html")), "--since \"yesterday\"",
                           "not a date", dir_.file("bad.html"));
}

// Each failure is one line naming the LRS, with the credentials never shown, and no page written.
TEST_F(ReportLrs, AnLrsThatCannotBeReadIsOneLine) {
  if (const std::string why = test::RealLrs::missing(); !why.empty()) GTEST_SKIP() << why;
  const std::string page = dir_.file("page.html");
  const std::string down = "http://127.0.0.1:" + std::to_string(test::freePort()) + "/xAPI";
  test::expectCleanFailure(dentsim("report --lrs " + down + " -o " + page), "LRS " + down, "not reachable", page);
  // The real LRS, given a password it does not know: 401, in its words.
  test::RealLrs lrs(dir_, "lrs", "lab", "another pw");
  ASSERT_TRUE(lrs.up()) << lrs.log();
  const auto refused = dentsim("report --lrs " + lrs.url() + " -o " + page);
  test::expectCleanFailure(refused, "LRS " + lrs.url(), "HTTP 401 (Unauthorised)", page);
  EXPECT_EQ(refused.output.find("s3cret"), std::string::npos) << refused.output;
  // An answer that is not JSON: the stand-in, since the real LRS never sends one.
  if (runCommand("python3 -c pass").exit_code == 0) {
    const std::string port_file = dir_.file("recorder.port");
    const auto started = runCommand("python3 " + (fs::path(DENTSIM_SOURCE_DIR) / "tests" / "xapi" / "lrs_recorder.py").string() +
                                    " --port-file " + port_file + " --log " + dir_.file("recorder.log") +
                                    " --get-status 200 --get-body '<html>%s%n</html>' >/dev/null 2>&1 & echo $!");
    const int pid = std::atoi(started.output.c_str());
    for (int i = 0; i < 1200 && !fs::exists(port_file); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    int port = 0;
    std::ifstream(port_file) >> port;
    const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/xapi";
    test::expectCleanFailure(dentsim("report --lrs " + url + " -o " + page), "LRS " + url, "is not JSON", page);
    if (pid > 0) ::kill(pid, SIGTERM);
  }
  // Nothing to read from, and an LRS option without --lrs.
  test::expectCleanFailure(dentsim("report -o " + page), "report", "--lrs", page);
  const auto since_alone = dentsim("report " + dir_.file("outbox.jsonl") + " --since 2000-01-01 -o " + page);
  EXPECT_NE(since_alone.exit_code, 0) << since_alone.output;
  EXPECT_NE(since_alone.output.find("--lrs"), std::string::npos) << since_alone.output;
}

}  // namespace
}  // namespace dentsim
