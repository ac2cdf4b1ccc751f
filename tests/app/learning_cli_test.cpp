// Learning records end to end: scored attempts by three students become ten xAPI statements that an independent validator accepts and a stand-in LRS receives exactly once each, also across a run with the LRS down; their score reports name them, so a class report counts each attempt once.
//
// No real LRS could run here (the packaged ones need a database server), so tests/xapi/lrs_recorder.py
// stands in: it records each request's method, path, headers and body, answers 409 for an id it
// has seen, and can refuse everything (503). "Down" is a localhost port where nobody listens.
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "free_port.h"
#include "test_json.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readJsonLines;
namespace fs = std::filesystem;
using test::freePort;
using test::runCommand;
using test::TempDir;

const fs::path kToolsDir = fs::path(DENTSIM_SOURCE_DIR) / "tests" / "xapi";

// The stand-in LRS, started on a free port and stopped at scope exit.
class Recorder {
 public:
  Recorder(const TempDir& dir, const std::string& name, bool refuse) : log_(dir.file(name + ".log")) {
    const std::string port_file = dir.file(name + ".port");
    const auto r = runCommand("python3 " + (kToolsDir / "lrs_recorder.py").string() + " --port-file " + port_file + " --log " + log_ +
                              (refuse ? " --refuse" : "") + " >/dev/null 2>&1 & echo $!");
    pid_ = std::atoi(r.output.c_str());
    // Python's start-up takes a fraction of a second, but a loaded machine can stretch it to
    // seconds: up to 60 s, which only a recorder that never comes up waits out.
    for (int i = 0; i < 1200 && !fs::exists(port_file); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::ifstream(port_file) >> port_;
  }
  ~Recorder() {
    if (pid_ > 0) ::kill(pid_, SIGTERM);
  }
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;
  bool up() const { return port_ > 0; }
  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_) + "/xapi"; }
  std::vector<nlohmann::json> requests() const { return readJsonLines(log_); }

 private:
  std::string log_;
  int pid_ = 0;
  int port_ = 0;
};

bool havePython() { return runCommand("python3 -c 'pass'").exit_code == 0; }


// Four recorded attempts on the level-6 molar with a fast preset: the careful removal and three
// faults, each a different session, so each names a different attempt. The demos are offered no
// Vulkan device, so they drill on the CPU without frames (a second each rather than ten); the
// simulator's own hook is checked by course_cli_test's scored run.
class LearningCli : public ::testing::Test {
 protected:
  void SetUp() override {
    preset_ = dir_.file("fast.json");
    std::ofstream(preset_) << R"({"format":"dentsim-params","version":1,"cutting":{"removal_rate_mm3_per_s":40},)"
                              R"("point_shell":{"head_spacing_mm":0.1,"shank_spacing_mm":0.2}})";
    config_ = dir_.file("learning.json");
    std::ofstream(config_) << R"({"course": "cons-101", "home_page": "https://school.example",
      "activity_base": "https://school.example/xapi", "outbox": "outbox.jsonl"})";
    outbox_ = dir_.file("outbox.jsonl");
  }
  // dentsim with the LRS credentials in the environment, never on the command line, and the default
  // config and outbox places inside the test's folder, so that a config in the user's home plays no part.
  test::CommandResult dentsim(const std::string& args, const std::string& env = "") const {
    return runCommand(env + "DENTSIM_LRS_USERNAME=lab DENTSIM_LRS_PASSWORD='s3cret pw' XDG_CONFIG_HOME=" + dir_.file("xdg-config") +
                      " XDG_DATA_HOME=" + dir_.file("xdg-data") + " DENTSIM_CONFIG= " + std::string(DENTSIM_BINARY) + " " + args);
  }
  std::string session(int i) const { return dir_.file("d" + std::to_string(i) + "/session.dses"); }
  std::string demoDir(int i) const { return dir_.file("d" + std::to_string(i)); }
  test::CommandResult scoreAs(const std::string& student, int i, const std::string& lrs) const {
    return dentsim("score --task caries --initial " + demoDir(i) + "/initial.dvol --final " + demoDir(i) + "/final.dvol --session " +
                   session(i) + " -o " + dir_.file("s.json") + " --png " + dir_.file("s.png") + " --student " + student +
                   " --config " + config_ + " --lrs " + lrs);
  }

  TempDir dir_;
  std::string preset_, config_, outbox_;
};

TEST_F(LearningCli, TenAttemptsByThreeStudentsReachTheLrsOnceEachAcrossADownedLrs) {
  if (!havePython()) GTEST_SKIP() << "python3 is needed for the stand-in LRS";
  const std::string down = "http://127.0.0.1:" + std::to_string(freePort()) + "/xapi";
  // Each demo records its own attempt as it scores it, with the LRS down: pending, a warning, success.
  // (The cheapest four of the scripted attempts: together about 7 s of CPU.)
  const test::NoLeakCheckForGpuChild no_leak_check;  // the Vulkan loader looks for a device before the CPU path
  const char* attempts[] = {"expert", "undercut", "trench", "heavy"};
  const char* demo_students[] = {"s1001", "s1002", "s1003", "s1001"};
  for (int i = 0; i < 4; ++i) {
    const auto r = dentsim("demo --headless --level 6 --mirror none --no-sound --attempt " + std::string(attempts[i]) + " --params " +
                               preset_ + " --out " + demoDir(i) + " --student " + demo_students[i] + " --config " + config_ +
                               " --lrs " + down,
                           "VK_ICD_FILENAMES=/nonexistent.json ");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    ASSERT_NE(r.output.find("the demo runs on the CPU"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("learning record "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("dentsim: warning: LRS " + down), std::string::npos) << r.output;
  }
  ASSERT_EQ(readJsonLines(outbox_).size(), 4u);
  // Each demo's score report names its statement, so that a class report counts the attempt once.
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(test::readJson(demoDir(i) + "/score.json").value("statement_id", ""), readJsonLines(outbox_)[size_t(i)]["id"]) << i;

  // Six more by `score`, the first while the LRS is still down: s1001 ends with four, the others three.
  const std::vector<std::pair<std::string, int>> plan = {{"s1002", 0}, {"s1003", 0}, {"s1001", 1},
                                                         {"s1003", 1}, {"s1001", 2}, {"s1002", 2}};
  const auto first = scoreAs(plan[0].first, plan[0].second, down);
  ASSERT_EQ(first.exit_code, 0) << first.output;  // a dead LRS never fails the score
  EXPECT_NE(first.output.find("5 statement(s) stay pending"), std::string::npos) << first.output;
  EXPECT_FALSE(fs::exists(outbox_ + ".sent"));

  // The LRS comes up: the next run sends its own statement and the five that waited.
  Recorder lrs(dir_, "lrs", false);
  ASSERT_TRUE(lrs.up());
  for (size_t k = 1; k < plan.size(); ++k) {
    const auto r = scoreAs(plan[k].first, plan[k].second, lrs.url());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
    if (k == 1) {
      EXPECT_EQ(lrs.requests().size(), 6u) << r.output;
    }
  }
  // The first attempt scored again by its student: the same id, neither added nor sent again.
  const auto again = scoreAs("s1001", 0, lrs.url());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("already in"), std::string::npos) << again.output;
  const auto flush = dentsim("outbox send --config " + config_ + " --lrs " + lrs.url());
  EXPECT_EQ(flush.exit_code, 0) << flush.output;
  EXPECT_NE(flush.output.find("nothing pending"), std::string::npos) << flush.output;

  // Ten statements, ten ids, three students, each delivered exactly once with the xAPI headers.
  const std::vector<nlohmann::json> statements = readJsonLines(outbox_);
  ASSERT_EQ(statements.size(), 10u);
  std::set<std::string> ids;
  std::map<std::string, int> per_student;
  for (const auto& s : statements) {
    ids.insert(s["id"].get<std::string>());
    per_student[s["actor"]["account"]["name"].get<std::string>()] += 1;
    EXPECT_EQ(s["object"]["id"], "https://school.example/xapi/courses/cons-101/tasks/caries_removal");
    EXPECT_EQ(s["actor"]["account"]["homePage"], "https://school.example");
  }
  EXPECT_EQ(ids.size(), 10u);
  EXPECT_EQ(per_student, (std::map<std::string, int>{{"s1001", 4}, {"s1002", 3}, {"s1003", 3}}));
  const std::vector<nlohmann::json> requests = lrs.requests();
  ASSERT_EQ(requests.size(), 10u);
  std::set<std::string> received;
  for (const auto& q : requests) {
    EXPECT_EQ(q["method"], "POST");
    EXPECT_EQ(q["path"], "/xapi/statements");
    EXPECT_EQ(q["headers"]["x-experience-api-version"], "1.0.3");
    EXPECT_EQ(q["headers"]["content-type"], "application/json");
    EXPECT_EQ(q["headers"]["authorization"], "Basic bGFiOnMzY3JldCBwdw==");  // base64 of "lab:s3cret pw"
    received.insert(nlohmann::json::parse(q["body"].get<std::string>())["id"].get<std::string>());
  }
  EXPECT_EQ(received, ids);
  // `score` names the statement in its report too: the last one scored is s1001's first attempt.
  EXPECT_EQ(test::readJson(dir_.file("s.json")).value("statement_id", ""), statements[0]["id"]);
  // The class report of this folder: the demos' four score reports and the ten statements are ten attempts.
  const auto page = dentsim("report " + demoDir(0) + " " + demoDir(1) + " " + demoDir(2) + " " + demoDir(3) + " " + outbox_ +
                            " -o " + dir_.file("class.html"));
  ASSERT_EQ(page.exit_code, 0) << page.output;
  EXPECT_NE(page.output.find("10 attempts by 3 students at 1 tasks"), std::string::npos) << page.output;
  EXPECT_NE(page.output.find("(4 score reports and their statements counted once)"), std::string::npos) << page.output;

  // An independent validator (npm's xapi-validation) accepts all ten.
  if (runCommand("node --version").exit_code != 0) GTEST_SKIP() << "node is not installed: the statements were not validated";
  const auto valid = runCommand("node " + (kToolsDir / "validate_statements.js").string() + " " + outbox_);
  if (valid.exit_code == 3) GTEST_SKIP() << valid.output;
  EXPECT_EQ(valid.exit_code, 0) << valid.output;
  EXPECT_NE(valid.output.find("10 statements, 0 problems"), std::string::npos) << valid.output;
}

TEST_F(LearningCli, RefusedStatementsStayPendingUntilAnLrsTakesThem) {
  if (!havePython()) GTEST_SKIP() << "python3 is needed for the stand-in LRS";
  std::ofstream(outbox_) << R"({"id":"6f1c1a0e-0000-5000-8000-000000000001","verb":{"id":"x"}})" "\n"
                         << R"({"id":"6f1c1a0e-0000-5000-8000-000000000002","verb":{"id":"x"}})" "\n";
  {
    Recorder refusing(dir_, "refusing", true);
    ASSERT_TRUE(refusing.up());
    const auto r = dentsim("outbox send --config " + config_ + " --lrs " + refusing.url());
    EXPECT_EQ(r.exit_code, 1) << r.output;  // asked to send, and could not
    EXPECT_NE(r.output.find("HTTP 503; 2 statement(s) stay pending"), std::string::npos) << r.output;
    EXPECT_EQ(refusing.requests().size(), 2u);  // a refusal is per statement: both were tried
  }
  const auto status = dentsim("outbox status --config " + config_);
  EXPECT_NE(status.output.find("2 statement(s), 2 pending"), std::string::npos) << status.output;
  Recorder lrs(dir_, "lrs", false);
  ASSERT_TRUE(lrs.up());
  const auto r = dentsim("outbox send --config " + config_ + " --lrs " + lrs.url());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("learning records: 2 sent to"), std::string::npos) << r.output;
  EXPECT_EQ(lrs.requests().size(), 2u);
  EXPECT_NE(dentsim("outbox status --config " + config_).output.find("2 statement(s), 0 pending"), std::string::npos);
}

TEST_F(LearningCli, MalformedConfigIsOneLineNamingFileAndKey) {
  const std::string bad = dir_.file("bad.json");
  std::ofstream(bad) << R"({"student": "s1", "lrs": "ftp://x"})";
  test::expectCleanFailure(dentsim("outbox status --config " + bad), bad, "lrs: \"ftp://x\" does not start with http:// or https://");
  test::expectCleanFailure(dentsim("outbox send --config " + dir_.file("missing.json")), "missing.json", "");
  // --lrs on the command line is checked as the config's is.
  test::expectCleanFailure(dentsim("outbox send --config " + config_ + " --lrs lrs.example"), "--lrs", "does not start with http://");
}

}  // namespace
}  // namespace dentsim
