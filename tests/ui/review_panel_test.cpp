// Tests of src/ui/review_panel.cpp, driven headless: the Score page's review buttons (disabled with a tooltip, or pressed), the comparison with the last attempts, and the first-run name prompt.
#include "ui/review_panel.h"

#include <gtest/gtest.h>

#include <string>

#include <imgui.h>

#include "ui/param_panel.h"

namespace dentsim::ui {
namespace {

AttemptPart component(const std::string& name, double points, double max) {
  AttemptPart p;
  p.name = name;
  p.points = points;
  p.max = max;
  return p;
}
AttemptPart deduction(const std::string& name, double points) {
  AttemptPart p;
  p.name = name;
  p.deduction = true;
  p.points = points;
  return p;
}
ClassAttempt attempt(double score, std::vector<AttemptPart> parts) {
  ClassAttempt a;
  a.score = score;
  a.parts = std::move(parts);
  return a;
}

TEST(CompareRows, TheTotalThenEachPartAsItCountedWithTheChangeFromTheLastAttempt) {
  // Two earlier attempts (50 then 60) and this one (72): undercut 30 -> 35 -> 40 of 50; the force
  // deduction 5 -> 2 -> 3 points off; "time" was scored only in the first.
  const ClassAttempt now = attempt(72, {component("undercut", 40, 50), deduction("force", 3)});
  const std::vector<ClassAttempt> before = {attempt(50, {component("undercut", 30, 50), deduction("force", 5), component("time", 8, 10)}),
                                            attempt(60, {component("undercut", 35, 50), deduction("force", 2)})};
  const std::vector<CompareRow> rows = compareRows(now, before);
  ASSERT_EQ(rows.size(), 4u);  // total, undercut, force, then time (only an earlier attempt had it)
  EXPECT_EQ(rows[0].label, "total");
  ASSERT_EQ(rows[0].before.size(), 2u);
  EXPECT_DOUBLE_EQ(*rows[0].before[0], 50.0);
  EXPECT_DOUBLE_EQ(*rows[0].before[1], 60.0);
  EXPECT_DOUBLE_EQ(*rows[0].now, 72.0);
  EXPECT_DOUBLE_EQ(*rows[0].change, 12.0);  // 72 - 60
  EXPECT_EQ(rows[1].label, "undercut");
  EXPECT_DOUBLE_EQ(*rows[1].change, 5.0);   // 40 - 35
  // A deduction counts negative: -3 now against -2 before is one point worse.
  EXPECT_EQ(rows[2].label, "force");
  EXPECT_DOUBLE_EQ(*rows[2].now, -3.0);
  EXPECT_DOUBLE_EQ(*rows[2].change, -1.0);
  EXPECT_EQ(rows[3].label, "time");
  EXPECT_DOUBLE_EQ(*rows[3].before[0], 8.0);
  EXPECT_FALSE(rows[3].before[1]);
  EXPECT_FALSE(rows[3].now);
  EXPECT_FALSE(rows[3].change);  // nothing to compare
}

TEST(CompareRows, AFirstAttemptHasOnlyItsOwnValues) {
  const std::vector<CompareRow> rows = compareRows(attempt(40, {component("undercut", 20, 50)}), {});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_TRUE(rows[0].before.empty());
  EXPECT_FALSE(rows[0].change);
}

// One ImGui context with the font atlas built, the panel drawn frame by frame (as param_panel_test).
class ReviewPanelTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ctx_ = ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(1280.0f, 2000.0f);
    io.DeltaTime = 1.0f / 60.0f;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    state_.score.valid = true;
    state_.score.total = 72;
    state_.score.rows = {{"undercut", "40 / 50"}};
    frame();
    frame();  // the Score page comes forward
  }
  void TearDown() override { ImGui::DestroyContext(ctx_); }

  PanelActions frame() {
    ImGui::NewFrame();
    rects_.clear();
    PanelActions a = drawParamPanel(state_, &rects_);
    ImGui::Render();
    EXPECT_EQ(panel::windowsLeftOpen(), 0);
    return a;
  }
  ImVec2 centre(const std::string& key) {
    auto it = rects_.find(key);
    if (it == rects_.end()) {
      ADD_FAILURE() << "no widget '" << key << "' this frame";
      return ImVec2(-1, -1);
    }
    return ImVec2((it->second.min_x + it->second.max_x) * 0.5f, (it->second.min_y + it->second.max_y) * 0.5f);
  }
  PanelActions mouse(ImVec2 p, bool down) {
    ImGui::GetIO().MousePos = p;
    ImGui::GetIO().MouseDown[0] = down;
    return frame();
  }
  // Hover, press, release: the actions of the three frames together.
  ReviewActions click(const std::string& key) {
    const ImVec2 p = centre(key);
    ReviewActions all;
    for (bool down : {false, true, false}) {
      const ReviewActions a = mouse(p, down).review;
      all.replay |= a.replay;
      all.replay_ghost |= a.replay_ghost;
      all.retry_guided |= a.retry_guided;
      if (!a.name_given.empty()) all.name_given = a.name_given;
    }
    return all;
  }
  // The tooltip over `key` after hovering it for a few frames (panel_widgets.h keeps the last shown).
  std::string hoverTooltip(const std::string& key) {
    const ImVec2 p = centre(key);
    for (int i = 0; i < 3; ++i) mouse(p, false);
    return panel::shownTooltip();
  }

  ImGuiContext* ctx_ = nullptr;
  UiState state_;
  WidgetRects rects_;
};

TEST_F(ReviewPanelTest, DisabledButtonsDoNothingAndSayWhyInATooltip) {
  state_.review.replay = {false, "no recorded session: the run was started without --out"};
  state_.review.ghost = {false, "no professional's session: the task has no recorded ideal and no --ghost was given"};
  state_.review.guided = {false, "no professional's path to follow"};
  frame();
  for (const char* key : {"review.replay", "review.ghost", "review.guided"}) {
    const ReviewActions a = click(key);
    EXPECT_FALSE(a.replay || a.replay_ghost || a.retry_guided) << key;
  }
  // Hovering a disabled button shows its reason.
  EXPECT_NE(hoverTooltip("review.replay").find("without --out"), std::string::npos);
  EXPECT_NE(hoverTooltip("review.ghost").find("no recorded ideal"), std::string::npos);
  EXPECT_NE(hoverTooltip("review.guided").find("no professional's path"), std::string::npos);
}

TEST_F(ReviewPanelTest, EachAvailableButtonRaisesItsOwnAction) {
  state_.review.replay = {true, ""};
  state_.review.ghost = {true, ""};
  state_.review.guided = {true, ""};
  frame();
  ReviewActions a = click("review.replay");
  EXPECT_TRUE(a.replay);
  EXPECT_FALSE(a.replay_ghost || a.retry_guided);
  a = click("review.ghost");
  EXPECT_TRUE(a.replay_ghost);
  EXPECT_FALSE(a.replay || a.retry_guided);
  a = click("review.guided");
  EXPECT_TRUE(a.retry_guided);
  EXPECT_FALSE(a.replay || a.replay_ghost);
}

TEST_F(ReviewPanelTest, TheComparisonShowsOnlyWithEarlierAttempts) {
  state_.review.now = attempt(72, {component("undercut", 40, 50)});
  frame();
  EXPECT_FALSE(rects_.count("review.table"));
  state_.review.before = {attempt(60, {component("undercut", 35, 50)})};
  frame();
  EXPECT_TRUE(rects_.count("review.table"));
}

TEST_F(ReviewPanelTest, TheFirstRunPromptTakesTheName) {
  frame();
  EXPECT_FALSE(rects_.count("student.name"));
  state_.student.ask = true;
  frame();
  frame();
  ASSERT_TRUE(rects_.count("student.name"));
  // It takes no keyboard until clicked (the keys still drill): click the field, type, then Keep.
  ImGui::GetIO().AddInputCharactersUTF8("x");
  frame();
  EXPECT_EQ(state_.student.typed, "");
  click("student.name");
  ImGui::GetIO().AddInputCharactersUTF8("s1001");
  frame();
  EXPECT_EQ(state_.student.typed, "s1001");
  EXPECT_EQ(click("student.ok").name_given, "s1001");
  // Refused by the app (ask stays on, typed cleared): the prompt comes back, and Start waits for a name.
  state_.student.typed.clear();
  state_.student.error = "the student's name \"\" is empty";
  frame();
  frame();
  ASSERT_TRUE(rects_.count("student.ok"));
  EXPECT_TRUE(click("student.ok").name_given.empty());
}

}  // namespace
}  // namespace dentsim::ui
