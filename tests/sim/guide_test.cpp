// Haptic guidance: the guide's spring toward the nearest point ahead on a professional's path, its header JSON, the yielding scripted hand, and a guided session that replays to the same forces.
#include "sim/guide_spring.h"

#include <gtest/gtest.h>

#include "io/pen_playback.h"
#include "sim/novice_paths.h"
#include "sim/pro_path.h"
#include "sim/scripted_paths.h"
#include "sim/session_run.h"
#include "sim/yielding_hand.h"
#include "sim_fixtures.h"
#include "test_support.h"
#include "volume/volume_hash.h"

namespace dentsim {
namespace {

// A straight path along +x: point i at (0.1 i, 0, 0) mm, 0.01 s apart, 100 points. The spring's end
// is 5 points (0.05 s) ahead of the nearest.
GuidePath straightGuide() {
  GuidePath g;
  g.settings.stiffness_n_per_mm = 1.0;
  g.settings.max_force_n = 2.0;
  g.settings.lookahead_s = 0.05;
  g.settings.search_s = 1.0;
  g.source = "pro.dses";
  g.source_hash = "0123456789abcdef";
  g.source_task = "class1_cavity";
  g.source_tooth_hash = "fedcba9876543210";
  for (int i = 0; i < 100; ++i) g.points.push_back({0.1 * i, 0.0, 0.0});
  return g;
}

TEST(GuideSpring, PullsTowardThePointAheadOfTheNearestAndNeverBack) {
  GuideSpring guide(straightGuide());
  // Nearest (2.0, 0, 0), index 20; the end 5 points on, (2.5, 0, 0): force (0.5, -0.5, 0) N at 1 N/mm.
  Vec3 f = guide.force({2.0, 0.5, 0.0});
  EXPECT_EQ(guide.cursor(), 20u);
  EXPECT_NEAR(f.x, 0.5, 1e-12);
  EXPECT_NEAR(f.y, -0.5, 1e-12);
  EXPECT_NEAR(f.z, 0.0, 1e-12);
  // Back near the start: the guide keeps its place (index 20) and pulls on toward (2.5, 0, 0),
  // 2.2 mm away, capped at 2 N.
  f = guide.force({0.3, 0.0, 0.0});
  EXPECT_EQ(guide.cursor(), 20u);
  EXPECT_NEAR(f.x, 2.0, 1e-12);
  EXPECT_NEAR(norm(f), 2.0, 1e-12);
  // Past the end: the last point is the spring's end.
  f = guide.force({12.0, 0.0, 0.0});
  EXPECT_EQ(guide.cursor(), 99u);
  EXPECT_NEAR(f.x, -2.0, 1e-12);  // 2.1 mm back to (9.9, 0, 0), capped
}

TEST(GuideSpring, SearchesOnlyItsWindowAhead) {
  GuidePath g = straightGuide();
  g.settings.search_s = 0.1;  // 11 points from the cursor
  GuideSpring guide(g);
  guide.force({5.0, 0.0, 0.0});  // index 50 is beyond the window: the nearest in it is index 10
  EXPECT_EQ(guide.cursor(), 10u);
  guide.force({5.0, 0.0, 0.0});  // and from there, index 20
  EXPECT_EQ(guide.cursor(), 20u);
}

// A scripted professional (no session) as a guide: its drill's grip every 10 ms, linear between the
// script's samples, the mirror's samples left out, and a hash that is the points' own.
TEST(GuideSpring, AScriptedProfessionalBecomesAGuideAHundredPointsASecond) {
  PenPath script;
  auto add = [&](double t, PenRole pen, Vec3 p) {
    PenSample s;
    s.t_s = t;
    s.pen = pen;
    s.pose.position = p;
    script.samples.push_back(s);
  };
  add(0.0, PenRole::Drill, {0, 0, 0});
  add(0.0, PenRole::Mirror, {50, 50, 50});
  add(0.1, PenRole::Drill, {1, 0, -2});
  add(0.1, PenRole::Mirror, {60, 50, 50});
  const GuidePath g = guidePathFromScript(script, GuideSettings{}, "the task's scripted professional", "class1_cavity", "abc");
  ASSERT_EQ(g.points.size(), 11u);
  for (size_t i = 0; i < g.points.size(); ++i) {
    EXPECT_NEAR(g.points[i].x, 0.1 * double(i), 1e-7) << i;
    EXPECT_NEAR(g.points[i].z, -0.2 * double(i), 1e-7) << i;
  }
  EXPECT_EQ(g.source_task, "class1_cavity");
  EXPECT_EQ(g.source_hash.size(), 16u);
  // Through the header's JSON and back: the same guide a replay rebuilds.
  auto back = parseGuideJson(guideJson(g), "test");
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->points.size(), g.points.size());
  script.samples[2].pose.position.x = 2;
  EXPECT_NE(guidePathFromScript(script, GuideSettings{}, "s", "t", "abc").source_hash, g.source_hash);
  script.samples.erase(script.samples.begin());
  script.samples.erase(script.samples.begin() + 1);
  for (PenSample& s : script.samples) s.pen = PenRole::Mirror;
  EXPECT_TRUE(guidePathFromScript(script, GuideSettings{}, "s", "t", "abc").points.empty());
}

TEST(GuideSpring, HeaderJsonReadsBackToTheSameGuide) {
  GuidePath g = straightGuide();
  g.start_index = 7;
  g.points[3] = {0.1 + 0.2, -1e-4, 12.3456};  // doubles without a short binary form
  const std::string text = guideJson(g);
  auto back = parseGuideJson(text, "s.dses");
  ASSERT_TRUE(back) << back.message();
  EXPECT_EQ(guideJson(*back), text);
  EXPECT_EQ(back->points, g.points);
  EXPECT_EQ(back->start_index, 7u);
  EXPECT_EQ(back->source_tooth_hash, g.source_tooth_hash);
  EXPECT_EQ(GuideSpring(*back).cursor(), 7u);
}

TEST(GuideSpring, HeaderJsonProblemsNameTheFieldInOneLine) {
  const std::string good = guideJson(straightGuide());
  struct Case {
    std::string from, to, field;
  };
  const Case cases[] = {{"\"stiffness_n_per_mm\":1.0", "\"stiffness_n_per_mm\":-1.0", "stiffness_n_per_mm"},
                        {"\"max_force_n\":2.0", "\"max_force_n\":\"2\"", "max_force_n"},
                        {"\"start_index\":0", "\"start_index\":100", "start_index"},
                        {"\"points\":[[0.0,0.0,0.0]", "\"points\":[[0.0,0.0]", "points[0]"},
                        {"\"source\":\"pro.dses\",", "", "source"},
                        {"\"search_s\":1.0", "\"search_s\":3000.0", "search_s"}};
  for (const Case& c : cases) {
    std::string text = good;
    const size_t at = text.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.from << " in " << text.substr(0, 300);
    text.replace(at, c.from.size(), c.to);
    auto parsed = parseGuideJson(text, "s.dses");
    ASSERT_FALSE(parsed) << c.field;
    EXPECT_NE(parsed.message().find("s.dses: guide"), std::string::npos) << parsed.message();
    EXPECT_NE(parsed.message().find(c.field), std::string::npos) << parsed.message();
    EXPECT_EQ(parsed.message().find('\n'), std::string::npos);
  }
  EXPECT_FALSE(parseGuideJson("[1, 2]", "s.dses"));
  // A path longer than an hour is refused before the step would have to search it.
  GuidePath huge = straightGuide();
  huge.points.assign(kMaxGuidePoints + 1, Vec3{});
  auto refused = parseGuideJson(guideJson(huge), "s.dses");
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.message().find("points: 360001 points"), std::string::npos) << refused.message();
}

// A pen that stays at the origin.
class StillPen final : public PenSource {
 public:
  bool read(double, PenReading* out) override {
    *out = PenReading{};
    return true;
  }
};

TEST(YieldingHand, GivesWayByForceOverStiffnessAfterItsLag) {
  StillPen pen;
  YieldingHand hand(pen, HandSettings{2.0, 0.03});
  PenReading r;
  ASSERT_TRUE(hand.read(0.0, &r));
  EXPECT_EQ(r.grip.position, (Vec3{0, 0, 0}));  // no force yet
  for (int k = 1; k <= 500; ++k) {
    hand.display(Wrench{{2.0, 0.0, -1.0}, {}}, 0.001 * k);
    ASSERT_TRUE(hand.read(0.001 * k, &r));
    if (k == 30) {
      EXPECT_LT(r.grip.position.x, 0.7);  // one lag in: not yet all the way (1 mm)
    }
  }
  // 2 N and -1 N over 2 N/mm: 1 mm and -0.5 mm, settled after 0.5 s (the lag left e^-16 of it).
  EXPECT_NEAR(r.grip.position.x, 1.0, 1e-6);
  EXPECT_NEAR(r.grip.position.z, -0.5, 1e-6);
  EXPECT_NEAR(r.velocity.x, 0.0, 1e-3);
}

// ---- a guided session --------------------------------------------------------------------------------

SessionInfo info() { return test::molarSessionInfo("2026-11-27T10:00:00Z", "class1_cavity"); }

TEST(GuidedSession, ReplaysToTheSameVoxelsAndForcesFromItsHeaderAlone) {
  test::TempDir scratch;
  const SimParams params = defaultSimParams();
  // The professional: the groove as scripted.
  ToothVolume pro_tooth = test::molar();
  ASSERT_TRUE(recordScriptedSession(pro_tooth, params, test::molarGroove(), scratch.file("pro.dses"), info(), {}));
  GuideSettings settings;
  settings.stiffness_n_per_mm = 2.0;
  auto guide = loadGuidePath(scratch.file("pro.dses"), settings);
  ASSERT_TRUE(guide) << guide.message();
  EXPECT_EQ(guide->source_tooth_hash, volumeHashHex(test::molar().voxels, test::molar().frame));

  // The student: the same groove by a wandering hand that yields, guided; then again unguided.
  ScriptedSessionOptions o;
  o.guide = *guide;
  o.hand = HandSettings{2.0, 0.03};
  ToothVolume guided_tooth = test::molar();
  auto guided = recordScriptedSession(guided_tooth, params, wanderingPath(test::molarGroove(), 0.8), scratch.file("g.dses"), info(), o);
  ASSERT_TRUE(guided) << guided.message();
  o.guide.reset();
  ToothVolume free_tooth = test::molar();
  auto free = recordScriptedSession(free_tooth, params, wanderingPath(test::molarGroove(), 0.8), scratch.file("f.dses"), info(), o);
  ASSERT_TRUE(free) << free.message();
  EXPECT_NE(guided->final_hash, free->final_hash);  // the guide moved the yielding hand, so the cut differs

  auto session = readSessionFile(scratch.file("g.dses"));
  ASSERT_TRUE(session) << session.message();
  ASSERT_FALSE(session->info.guide_json.empty());
  auto recorded_guide = parseGuideJson(session->info.guide_json, "g.dses");
  ASSERT_TRUE(recorded_guide) << recorded_guide.message();
  EXPECT_EQ(recorded_guide->points, guide->points);
  EXPECT_EQ(recorded_guide->settings.stiffness_n_per_mm, 2.0);
  // The header's guide alone makes the same forces and voxels again.
  ToothVolume tooth = test::molar();
  auto replayed = replaySession(*session, tooth, {});
  ASSERT_TRUE(replayed) << replayed.message();
  EXPECT_EQ(replayed->final_hash, guided->final_hash);
  EXPECT_TRUE(replayed->recorded_hash_matches);
  EXPECT_EQ(replayed->force_mismatches, 0u);
  // Without it the readings still cut the same voxels, but the forces are not the recorded ones:
  // the recorded forces held the guide's spring.
  session->info.guide_json.clear();
  tooth = test::molar();
  auto unguided = replaySession(*session, tooth, {});
  ASSERT_TRUE(unguided) << unguided.message();
  EXPECT_EQ(unguided->final_hash, guided->final_hash);
  EXPECT_GT(unguided->force_mismatches, session->steps.size() / 2);
}

}  // namespace
}  // namespace dentsim
