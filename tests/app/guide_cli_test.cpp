// Haptic guidance end to end: a scripted student with a wandering, yielding hand scores closer to the ideal guided by the professional's session than unguided; the guided session replays exactly; the score report and the learning record say it was guided.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_json.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readJson;
using test::readJsonLines;
using test::runDentsim;
using test::TempDir;

const std::string kGuidedIri = "https://dentsim.invalid/xapi/extensions/guided";

// The class I cavity on the level-7 molar, about 6 s of loop time each. The professional is the
// careful scripted preparation; the student is the same path drawn by a hand that wanders up to
// 0.8 mm sideways and yields like a 2 N/mm grip. Guided, a 2 N/mm spring pulls that hand back
// toward the professional's path.
TEST(GuideCli, AGuidedStudentScoresCloserToTheIdealAndItsSessionReplaysExactly) {
  TempDir dir;
  const test::NoLeakCheckForGpuChild no_leak_check;
  const std::string common = "run --headless --level 7 --task cavity --demo-script --no-sound --mirror none ";
  const auto pro = runDentsim(common + "--attempt expert --out " + dir.file("pro"));
  ASSERT_EQ(pro.exit_code, 0) << pro.output;
  const std::string pro_session = dir.file("pro/session.dses");
  ASSERT_TRUE(std::filesystem::exists(pro_session)) << pro.output;

  // Learning records go to an outbox in the test's folder, with no LRS and no config from home.
  std::ofstream(dir.file("learning.json")) << R"({"course": "cons-101", "outbox": ")" << dir.file("outbox.jsonl") << R"("})";
  const std::string student = "--attempt expert --wander 0.8 --hand-stiffness 2 --score-at-end --student s1001 --config " +
                              dir.file("learning.json") + " ";
  const auto free_run = runDentsim(common + student + "--out " + dir.file("free"));
  ASSERT_EQ(free_run.exit_code, 0) << free_run.output;
  const auto guided_run =
      runDentsim(common + student + "--guide " + pro_session + " --guide-stiffness 2 --out " + dir.file("guided"));
  ASSERT_EQ(guided_run.exit_code, 0) << guided_run.output;
  EXPECT_NE(guided_run.output.find("guided by " + pro_session + " at 2.00 N/mm"), std::string::npos) << guided_run.output;
  EXPECT_EQ(free_run.output.find("guided by"), std::string::npos) << free_run.output;

  const nlohmann::json free_score = readJson(dir.file("free/score.json"));
  const nlohmann::json guided_score = readJson(dir.file("guided/score.json"));
  ASSERT_TRUE(free_score.is_object() && guided_score.is_object());
  // Closer to the ideal: less tissue cut beyond it and left standing in it together, and more points.
  auto missed = [](const nlohmann::json& s) {
    return s["volumes"]["all"]["overcut_mm3"].get<double>() + s["volumes"]["all"]["undercut_mm3"].get<double>();
  };
  EXPECT_LT(missed(guided_score), 0.9 * missed(free_score)) << free_score.dump() << "\n" << guided_score.dump();
  EXPECT_GT(guided_score["total"].get<double>(), free_score["total"].get<double>() + 2.0);
  // The report names the guide; an unguided one has no "guided" at all.
  ASSERT_TRUE(guided_score.contains("guided")) << guided_score.dump();
  EXPECT_EQ(guided_score["guided"]["source"], pro_session);
  EXPECT_EQ(guided_score["guided"]["stiffness_n_per_mm"], 2.0);
  EXPECT_FALSE(free_score.contains("guided"));

  // The guided session replays to the recorded voxels with every recorded force, from its file alone.
  const auto replay = runDentsim("replay --headless --json " + dir.file("guided/session.dses"));
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  const nlohmann::json r = test::printedJson(replay.output);
  ASSERT_TRUE(r.is_object()) << replay.output;
  EXPECT_TRUE(r["matches_recording"].get<bool>());
  EXPECT_EQ(r["force_mismatches"], 0);
  EXPECT_DOUBLE_EQ(r["total"].get<double>(), guided_score["total"].get<double>());

  // The learning records: the unguided attempt's statement says false, the guided one's true.
  const std::vector<nlohmann::json> statements = readJsonLines(dir.file("outbox.jsonl"));
  ASSERT_EQ(statements.size(), 2u);
  EXPECT_FALSE(statements[0]["result"]["extensions"][kGuidedIri].get<bool>()) << statements[0].dump();
  EXPECT_TRUE(statements[1]["result"]["extensions"][kGuidedIri].get<bool>()) << statements[1].dump();
}

TEST(GuideCli, AGuideThatDoesNotReadIsOneLineAndNoRun) {
  TempDir dir;
  std::ofstream(dir.file("not-a-session.dses")) << "hello";
  const auto r = runDentsim("run --headless --level 6 --demo-script --no-sound --guide " + dir.file("not-a-session.dses") +
                            " --out " + dir.file("out"));
  EXPECT_NE(r.exit_code, 0);
  test::expectCleanFailure(r, dir.file("not-a-session.dses"), "--guide");
  EXPECT_FALSE(std::filesystem::exists(dir.file("out/session.dses")));
}

}  // namespace
}  // namespace dentsim
