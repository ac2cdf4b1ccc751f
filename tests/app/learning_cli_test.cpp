// Learning records end to end: scored attempts by three students become ten xAPI statements that an independent validator accepts and a real LRS stores exactly once each, also across a run with the LRS down, and that read back from it equal what was sent; a malformed statement is refused by the LRS and kept with its reason; the credentials reach it; their score reports name them, so a class report counts each attempt once.
//
// The LRS is real: Learning Locker's statement service (npm xapi-statements, tests/real_lrs.h),
// started by each test on a free port and stopped after it. The stand-in tests/xapi/lrs_recorder.py
// remains only for the faults the real one cannot be made to show: an LRS that answers 503 to
// everything, and one that takes a minute per answer. "Down" is a localhost port where nobody listens.
#include <gtest/gtest.h>

#include <signal.h>

#include <algorithm>
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
#include "real_lrs.h"
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

// The stand-in LRS, started on a free port and stopped at scope exit: only for an LRS that refuses
// everything (503) or answers slowly, which the real one (test::RealLrs) cannot be made to do.
class Recorder {
 public:
  // `options`: more of lrs_recorder.py's options ("--slow-after 1 --delay 60").
  Recorder(const TempDir& dir, const std::string& name, bool refuse, const std::string& options = "") : log_(dir.file(name + ".log")) {
    const std::string port_file = dir.file(name + ".port");
    const auto r = runCommand("python3 " + (kToolsDir / "lrs_recorder.py").string() + " --port-file " + port_file + " --log " + log_ +
                              (refuse ? " --refuse" : "") + " " + options + " >/dev/null 2>&1 & echo $!");
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
  // The same with credentials in it, as a careless config might give them.
  std::string urlWithCredentials(const std::string& password, const std::string& token) const {
    return "http://bob:" + password + "@127.0.0.1:" + std::to_string(port_) + "/xapi?token=" + token;
  }
  std::vector<nlohmann::json> requests() const { return readJsonLines(log_); }

 private:
  std::string log_;
  int pid_ = 0;
  int port_ = 0;
};

bool havePython() { return runCommand("python3 -c 'pass'").exit_code == 0; }

// The fields of a statement that dentsim sent and the LRS changed or dropped, as "path: sent X, stored Y"
// lines; none when every field sent is stored as sent. The LRS adds fields of its own (stored,
// authority, an objectType where the sender left it implicit), and those are not dentsim's to compare.
void differences(const nlohmann::json& sent, const nlohmann::json& stored, const std::string& path, std::vector<std::string>* out) {
  if (sent.is_object() && stored.is_object()) {
    for (const auto& [key, value] : sent.items()) {
      if (!stored.contains(key)) {
        out->push_back(path + "." + key + ": sent, not stored");
        continue;
      }
      differences(value, stored[key], path + "." + key, out);
    }
    return;
  }
  if (sent.is_array() && stored.is_array() && sent.size() == stored.size()) {
    for (size_t i = 0; i < sent.size(); ++i) differences(sent[i], stored[i], path + "[" + std::to_string(i) + "]", out);
    return;
  }
  // Numbers compare by value: 1 sent may come back as 1.0.
  if (sent != stored) out->push_back(path + ": sent " + sent.dump() + ", stored " + stored.dump());
}


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
  if (const std::string why = test::RealLrs::missing(); !why.empty()) GTEST_SKIP() << why;
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
  test::RealLrs lrs(dir_, "lrs", "lab", "s3cret pw");
  ASSERT_TRUE(lrs.up()) << lrs.log();
  for (size_t k = 1; k < plan.size(); ++k) {
    const auto r = scoreAs(plan[k].first, plan[k].second, lrs.url());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
    if (k == 1) {
      EXPECT_EQ(lrs.requests("POST", "/xAPI/statements", 200), 6) << r.output;
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
  // Ten POSTs reached the LRS, each taken (its access log), none refused: every statement once.
  EXPECT_EQ(lrs.requests("POST", "/xAPI/statements", 200), 10);
  EXPECT_EQ(lrs.requests("POST", "/xAPI/statements", 400) + lrs.requests("POST", "/xAPI/statements", 401), 0);
  // Read back with GET (the tests' own reader, two a page), each equals the one in the outbox field
  // by field, and carries as its authority the account of the credentials dentsim sent.
  std::string read_error;
  const std::vector<nlohmann::json> stored = lrs.statements(&read_error, 2);
  ASSERT_EQ(stored.size(), 10u) << read_error;
  std::set<std::string> received;
  for (const auto& back : stored) {
    const std::string id = back["id"].get<std::string>();
    received.insert(id);
    const auto sent = std::find_if(statements.begin(), statements.end(), [&](const nlohmann::json& s) { return s["id"] == id; });
    ASSERT_NE(sent, statements.end()) << id;
    std::vector<std::string> changed;
    differences(*sent, back, "statement", &changed);
    EXPECT_TRUE(changed.empty()) << id << ": " << ::testing::PrintToString(changed);
    EXPECT_EQ(back["authority"]["account"]["name"], "lab") << back.dump();
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

// An LRS that is up but answers 503 to everything (the stand-in: the real one cannot be made to).
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

// A statement the real LRS can store: no score, so a class report passes over it.
std::string validStatement(int n) {
  return R"({"id":"6f1c1a0e-0000-5000-8000-00000000000)" + std::to_string(n) +
         R"(","actor":{"objectType":"Agent","account":{"homePage":"https://school.example","name":"s1"}},)"
         R"("verb":{"id":"http://adlnet.gov/expapi/verbs/completed"},"object":{"id":"https://school.example/xapi/courses/cons-101/tasks/t1"},)"
         R"("version":"1.0.3"})";
}

// A statement the real LRS refuses as malformed (an mbox without "mailto:", its value holding printf
// directives that would crash a format) stays pending in the outbox, and the LRS's reason is kept
// beside it as data: the send names it, `outbox status` shows it, "<outbox>.refused" holds it. The
// good statement before it is taken; the refused one is tried again, and refused again, next time.
TEST_F(LearningCli, AStatementTheRealLrsRefusesStaysPendingWithTheLrsReason) {
  if (const std::string why = test::RealLrs::missing(); !why.empty()) GTEST_SKIP() << why;
  const std::string bad_id = "6f1c1a0e-0000-5000-8000-000000000002";
  std::ofstream(outbox_) << validStatement(1) << "\n"
                         << R"({"id":")" << bad_id
                         << R"(","actor":{"mbox":"%s%n@example.org"},"verb":{"id":"http://adlnet.gov/expapi/verbs/completed"},)"
                            R"("object":{"id":"https://school.example/xapi/courses/cons-101/tasks/t1"}})" "\n";
  test::RealLrs lrs(dir_, "lrs", "lab", "s3cret pw");
  ASSERT_TRUE(lrs.up()) << lrs.log();
  // The LRS's own words, as it answered them (its "warnings").
  const std::string reason = "Problem in 'statements.0.actor.mbox'. Received '\"%s%n@example.org\"'";
  for (int round = 0; round < 2; ++round) {
    const auto r = dentsim("outbox send --config " + config_ + " --lrs " + lrs.url());
    EXPECT_EQ(r.exit_code, 1) << r.output;  // asked to send, and one could not be
    if (round == 0) {
      EXPECT_NE(r.output.find("learning records: 1 sent to " + lrs.url()), std::string::npos) << r.output;
    }
    EXPECT_NE(r.output.find("HTTP 400 (" + reason + "); 1 statement(s) stay pending"), std::string::npos) << r.output;
  }
  const auto status = dentsim("outbox status --config " + config_);
  EXPECT_EQ(status.exit_code, 0) << status.output;
  EXPECT_NE(status.output.find("2 statement(s), 1 pending"), std::string::npos) << status.output;
  EXPECT_NE(status.output.find(bad_id + " refused by the LRS (HTTP 400): " + reason), std::string::npos) << status.output;
  // Kept as data: a JSON line, the reason a string value; the second refusal, in the same words, not again.
  const std::vector<nlohmann::json> refusals = readJsonLines(outbox_ + ".refused");
  ASSERT_EQ(refusals.size(), 1u);
  EXPECT_EQ(refusals[0]["id"], bad_id);
  EXPECT_EQ(refusals[0]["http_status"], 400);
  EXPECT_EQ(refusals[0]["reason"], reason);
  EXPECT_EQ(readJsonLines(outbox_).size(), 2u);  // nothing left the outbox
  std::string read_error;
  const std::vector<nlohmann::json> stored = lrs.statements(&read_error);
  ASSERT_EQ(stored.size(), 1u) << read_error;
  EXPECT_EQ(stored[0]["id"], "6f1c1a0e-0000-5000-8000-000000000001");
}

// The credentials: the config file's username and password, or DENTSIM_LRS_USERNAME/PASSWORD over
// them. The real LRS refuses a request without the credentials it knows (401), and stamps the
// account of those it took on each statement as its authority: a stored statement whose authority
// names the config's user proves the config's credentials reached it, not merely that it was up.
TEST_F(LearningCli, TheConfigsCredentialsReachTheRealLrs) {
  if (const std::string why = test::RealLrs::missing(); !why.empty()) GTEST_SKIP() << why;
  std::ofstream(outbox_) << validStatement(1) << "\n" << validStatement(2) << "\n";
  const std::string with_credentials = dir_.file("credentials.json");
  std::ofstream(with_credentials) << R"({"course": "cons-101", "outbox": "outbox.jsonl", "username": "teacher-7", "password": "pw of %s"})";
  test::RealLrs lrs(dir_, "lrs", "teacher-7", "pw of %s");
  ASSERT_TRUE(lrs.up()) << lrs.log();
  // The environment's credentials (the fixture's "lab") win over the config's, and this LRS does not know them.
  const auto refused = dentsim("outbox send --config " + with_credentials + " --lrs " + lrs.url());
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("HTTP 401 (Unauthorised); 2 statement(s) stay pending"), std::string::npos) << refused.output;
  EXPECT_EQ(lrs.requests("POST", "/xAPI/statements", 401), 2);
  // Without them, the config's: taken.
  const auto taken = runCommand("DENTSIM_LRS_USERNAME= DENTSIM_LRS_PASSWORD= DENTSIM_CONFIG= XDG_CONFIG_HOME=" + dir_.file("xdg-config") +
                                " " + std::string(DENTSIM_BINARY) + " outbox send --config " + with_credentials + " --lrs " + lrs.url());
  EXPECT_EQ(taken.exit_code, 0) << taken.output;
  EXPECT_NE(taken.output.find("learning records: 2 sent to " + lrs.url()), std::string::npos) << taken.output;
  for (const auto& run : {refused, taken}) EXPECT_EQ(run.output.find("pw of"), std::string::npos) << run.output;
  std::string read_error;
  const std::vector<nlohmann::json> stored = lrs.statements(&read_error);
  ASSERT_EQ(stored.size(), 2u) << read_error;
  for (const auto& back : stored)
    EXPECT_EQ(back["authority"], nlohmann::json::parse(R"({"objectType":"Agent","account":{"homePage":"https://lrs.test.invalid","name":"teacher-7"}})"));
}

// One demo's attempt scored again by another student, with everything against it: a damaged line in
// the outbox, an LRS that answers once and then takes a minute per statement, and a password and a
// token in the LRS's URL (the stand-in: the real LRS cannot be made slow). The attempt is recorded,
// the bad line set aside, the command returns with the rest pending (the sending limit made small
// for the test), and neither secret is printed.
TEST_F(LearningCli, ABadOutboxLineASlowLrsAndCredentialsInItsUrlNeitherStopNorLeak) {
  if (!havePython()) GTEST_SKIP() << "python3 is needed for the stand-in LRS";
  const test::NoLeakCheckForGpuChild no_leak_check;  // the Vulkan loader looks for a device before the CPU path
  const auto demo = dentsim("demo --headless --level 6 --mirror none --no-sound --attempt expert --params " + preset_ + " --out " +
                                demoDir(0) + " --student s1001 --config " + config_,
                            "VK_ICD_FILENAMES=/nonexistent.json ");
  ASSERT_EQ(demo.exit_code, 0) << demo.output;
  ASSERT_EQ(readJsonLines(outbox_).size(), 1u);
  // Line 2 damaged (a hand edit, a disk fault), then two more good statements waiting to be sent.
  std::ofstream(outbox_, std::ios::app) << "{\"id\": broken\n"
                                        << R"({"id":"6f1c1a0e-0000-5000-8000-000000000001","verb":{"id":"x"}})" "\n"
                                        << R"({"id":"6f1c1a0e-0000-5000-8000-000000000002","verb":{"id":"x"}})" "\n";
  Recorder slow(dir_, "slow", false, "--slow-after 1 --delay 120");
  ASSERT_TRUE(slow.up());
  const std::string password = "PW-q7x2", token = "TK-z9w4";
  const std::string url = slow.urlWithCredentials(password, token);
  const auto r = dentsim("score --task caries --initial " + demoDir(0) + "/initial.dvol --final " + demoDir(0) + "/final.dvol --session " +
                             session(0) + " -o " + dir_.file("s.json") + " --student s1002 --config " + config_ + " --lrs '" + url + "'",
                         "DENTSIM_LRS_SEND_LIMIT_MS=3000 ");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The bad line: one warning naming the file and line, moved to the side file, nothing else lost.
  EXPECT_NE(r.output.find("dentsim: warning: " + outbox_ + ":2: not valid JSON; moved to " + outbox_ + ".bad"), std::string::npos)
      << r.output;
  std::ifstream bad(outbox_ + ".bad");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(bad), {}), "{\"id\": broken\n");
  const std::vector<nlohmann::json> statements = readJsonLines(outbox_);
  ASSERT_EQ(statements.size(), 4u);  // the demo's, the two waiting, and this score's
  EXPECT_EQ(statements[3]["actor"]["account"]["name"], "s1002");
  EXPECT_EQ(test::readJson(dir_.file("s.json")).value("statement_id", ""), statements[3]["id"]);
  // The slow LRS: fewer than all sent, and the rest still pending for the next run.
  EXPECT_NE(r.output.find("stay pending"), std::string::npos) << r.output;
  std::set<std::string> sent;
  std::ifstream sent_log(outbox_ + ".sent");
  for (std::string id; std::getline(sent_log, id);) sent.insert(id);
  EXPECT_LT(sent.size(), 4u);
  const auto status = dentsim("outbox status --config " + config_);
  EXPECT_NE(status.output.find("4 statement(s), " + std::to_string(4 - sent.size()) + " pending"), std::string::npos) << status.output;
  // The URL is shown, without its secrets.
  EXPECT_NE(r.output.find("LRS http://***@127.0.0.1:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("?token=***"), std::string::npos) << r.output;
  for (const std::string& secret : {password, token}) EXPECT_EQ(r.output.find(secret), std::string::npos) << r.output;
}

// `outbox send` with credentials in the URL against an LRS that is down, one that refuses, one that
// takes them, and a URL with a wrong scheme: the secrets appear in none of their outputs. The
// stand-in, for its 503 and for its log of the request's path, where the URL's query must arrive.
TEST_F(LearningCli, AUrlsPasswordAppearsInNoOutputOfOutboxSend) {
  if (!havePython()) GTEST_SKIP() << "python3 is needed for the stand-in LRS";
  std::ofstream(outbox_) << R"({"id":"6f1c1a0e-0000-5000-8000-000000000001","verb":{"id":"x"}})" "\n";
  const std::string password = "PW-q7x2", token = "TK-z9w4";
  const std::string down = "http://bob:" + password + "@127.0.0.1:" + std::to_string(freePort()) + "/xapi?token=" + token;
  std::vector<test::CommandResult> runs;
  runs.push_back(dentsim("outbox send --config " + config_ + " --lrs '" + down + "'"));
  EXPECT_EQ(runs.back().exit_code, 1) << runs.back().output;
  runs.push_back(dentsim("outbox send --config " + config_ + " --lrs 'ftp://bob:" + password + "@h/x?token=" + token + "'"));
  EXPECT_EQ(runs.back().exit_code, 1) << runs.back().output;
  {
    Recorder refusing(dir_, "refusing", true);
    ASSERT_TRUE(refusing.up());
    runs.push_back(dentsim("outbox send --config " + config_ + " --lrs '" + refusing.urlWithCredentials(password, token) + "'"));
    EXPECT_EQ(runs.back().exit_code, 1) << runs.back().output;
    EXPECT_NE(runs.back().output.find("HTTP 503"), std::string::npos) << runs.back().output;
  }
  Recorder lrs(dir_, "lrs", false);
  ASSERT_TRUE(lrs.up());
  runs.push_back(dentsim("outbox send --config " + config_ + " --lrs '" + lrs.urlWithCredentials(password, token) + "'"));
  EXPECT_EQ(runs.back().exit_code, 0) << runs.back().output;
  EXPECT_NE(runs.back().output.find("1 sent to http://***@127.0.0.1:"), std::string::npos) << runs.back().output;
  // The query travels after the statements path, where the LRS reads it.
  ASSERT_EQ(lrs.requests().size(), 1u);
  EXPECT_EQ(lrs.requests()[0]["path"], "/xapi/statements?token=" + token);
  for (const auto& run : runs)
    for (const std::string& secret : {password, token}) EXPECT_EQ(run.output.find(secret), std::string::npos) << run.output;
}

// A student name with a bidi control, a control character or 1,000 bytes is refused in one line
// before any work, whether it comes from --student or from the config.
TEST_F(LearningCli, StudentNamesAreCheckedBeforeTheWork) {
  const auto demo = [&](const std::string& student_option, const std::string& config) {
    return dentsim("demo --headless --level 6 --mirror none --no-sound --attempt expert --params " + preset_ + " --out " +
                   demoDir(0) + student_option + " --config " + config);
  };
  test::expectCleanFailure(demo(" --student 's1\u202e'", config_), "--student: \"s1\\u202e\"", "bidirectional control character",
                           demoDir(0));
  test::expectCleanFailure(demo(" --student \"$(printf 's1\\033[2J')\"", config_), "--student:", "control character", demoDir(0));
  test::expectCleanFailure(demo(" --student " + std::string(1000, 's'), config_), "--student:", "longer than 64 bytes", demoDir(0));
  const std::string named = dir_.file("named.json");
  std::ofstream(named) << "{\"student\": \"s1\", \"student_name\": \"Ada \u202e\"}";
  test::expectCleanFailure(demo("", named), named + ": student_name:", "bidirectional control character", demoDir(0));
}

// `outbox send` killed with -9 while the LRS sits on its second statement: the first, already taken,
// is marked sent and the next send posts only the other two. The stand-in: the real LRS cannot be
// made to hold an answer back.
TEST_F(LearningCli, ASenderKilledMidSendPostsNothingTwice) {
  if (!havePython()) GTEST_SKIP() << "python3 is needed for the stand-in LRS";
  for (int i = 1; i <= 3; ++i)
    std::ofstream(outbox_, std::ios::app) << R"({"id":"6f1c1a0e-0000-5000-8000-00000000000)" << i << R"(","verb":{"id":"x"}})" "\n";
  {
    Recorder slow(dir_, "slow", false, "--slow-after 1 --delay 120");
    ASSERT_TRUE(slow.up());
    const auto started = runCommand("DENTSIM_LRS_USERNAME= DENTSIM_CONFIG= " + std::string(DENTSIM_BINARY) + " outbox send --config " +
                                    config_ + " --lrs " + slow.url() + " >/dev/null 2>&1 & echo $!");
    const int pid = std::atoi(started.output.c_str());
    ASSERT_GT(pid, 0);
    // The second statement has reached the LRS, so the first one's answer has been handled (up to 60 s on a loaded machine).
    for (int i = 0; i < 1200 && slow.requests().size() < 2; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_EQ(slow.requests().size(), 2u);
    ::kill(pid, SIGKILL);
  }
  std::ifstream sent_log(outbox_ + ".sent");
  std::string first;
  std::getline(sent_log, first);
  EXPECT_EQ(first, "6f1c1a0e-0000-5000-8000-000000000001");
  Recorder lrs(dir_, "lrs", false);
  ASSERT_TRUE(lrs.up());
  const auto r = dentsim("outbox send --config " + config_ + " --lrs " + lrs.url());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("learning records: 2 sent to"), std::string::npos) << r.output;
  EXPECT_EQ(lrs.requests().size(), 2u);  // the killed sender's first statement is not posted again
}

size_t countOf(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++n;
  return n;
}

// After the options are checked, nothing about the records fails a scored attempt: with the LRS down
// and with an outbox that cannot be written, `score` writes its report, says why in one warning
// line, and succeeds.
TEST_F(LearningCli, AnUnreachableLrsOrAnUnwritableOutboxNeverFailsTheScore) {
  const test::NoLeakCheckForGpuChild no_leak_check;  // the Vulkan loader looks for a device before the CPU path
  const auto demo = dentsim("demo --headless --level 6 --mirror none --no-sound --attempt expert --params " + preset_ + " --out " +
                                demoDir(0),
                            "VK_ICD_FILENAMES=/nonexistent.json ");
  ASSERT_EQ(demo.exit_code, 0) << demo.output;
  const std::string down = "http://127.0.0.1:" + std::to_string(freePort()) + "/xapi";
  const auto r = scoreAs("s1001", 0, down);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_.file("s.json")));
  EXPECT_EQ(countOf(r.output, "dentsim: warning:"), 1u) << r.output;
  EXPECT_NE(r.output.find("dentsim: warning: LRS " + down), std::string::npos) << r.output;
  EXPECT_EQ(readJsonLines(outbox_).size(), 1u);  // recorded, and pending

  // The outbox's folder is a file: nothing can be recorded there.
  const std::string blocker = dir_.file("blocker");
  std::ofstream(blocker) << "not a folder\n";
  fs::remove(dir_.file("s.json"));
  const auto unwritable = dentsim("score --task caries --initial " + demoDir(0) + "/initial.dvol --final " + demoDir(0) +
                                  "/final.dvol --session " + session(0) + " -o " + dir_.file("s.json") + " --student s1001 --config " +
                                  config_ + " --outbox " + blocker + "/outbox.jsonl");
  EXPECT_EQ(unwritable.exit_code, 0) << unwritable.output;
  EXPECT_TRUE(fs::exists(dir_.file("s.json")));
  EXPECT_EQ(countOf(unwritable.output, "dentsim: warning:"), 1u) << unwritable.output;
  EXPECT_NE(unwritable.output.find("dentsim: warning: the attempt was not recorded: "), std::string::npos) << unwritable.output;
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
