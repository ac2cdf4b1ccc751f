// The student's help on the panel, driven headless: the controls overlay (its contents for each pen, Got it, Bring), the disabled buttons' tooltips saying why, and the guidance switch and slider.
#include "ui/controls_help.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <imgui.h>

#include "ui/panel_widgets.h"
#include "ui/param_panel.h"

namespace dentsim::ui {
namespace {

class HelpTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ctx_ = ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(1280.0f, 800.0f);
    io.DeltaTime = 1.0f / 60.0f;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    state_.task_title = "Class I cavity";
    state_.task_instructions = "Prepare the occlusal fissures of the lower first molar.";
    frame();
  }
  void TearDown() override { ImGui::DestroyContext(ctx_); }
  PanelActions frame() {
    ImGui::NewFrame();
    rects_.clear();
    PanelActions a = drawParamPanel(state_, &rects_);
    drawOverlay(state_);
    ImGui::Render();
    EXPECT_EQ(panel::windowsLeftOpen(), 0);
    return a;
  }
  ImVec2 centre(const std::string& key) const {
    auto it = rects_.find(key);
    if (it == rects_.end()) {
      ADD_FAILURE() << "no widget '" << key << "'";
      return ImVec2(-1, -1);
    }
    return ImVec2((it->second.min_x + it->second.max_x) * 0.5f, (it->second.min_y + it->second.max_y) * 0.5f);
  }
  PanelActions mouse(ImVec2 p, bool down) {
    ImGui::GetIO().MousePos = p;
    ImGui::GetIO().MouseDown[0] = down;
    return frame();
  }
  PanelActions click(const std::string& key) {
    const ImVec2 p = centre(key);
    mouse(p, false);
    PanelActions a = mouse(p, true);
    PanelActions b = mouse(p, false);
    a.score |= b.score;
    a.help_closed |= b.help_closed;
    a.bring_to_tooth |= b.bring_to_tooth;
    a.guidance_changed |= b.guidance_changed;
    return a;
  }
  // The tooltip over `key` after hovering it for a few frames.
  std::string hoverTooltip(const std::string& key) {
    const ImVec2 p = centre(key);
    for (int i = 0; i < 3; ++i) mouse(p, false);
    return panel::shownTooltip();
  }
  ImGuiContext* ctx_ = nullptr;
  UiState state_;
  WidgetRects rects_;
};

TEST(ControlLines, TheMouseIsToldEveryControlItNeedsAndAHapticPenItsStylusAndPedal) {
  auto has = [](const std::vector<ControlLine>& lines, const std::string& control) {
    return std::any_of(lines.begin(), lines.end(), [&](const ControlLine& l) { return l.control == control; });
  };
  const auto mouse = controlLines(DrillInput::Mouse, false);
  // Move, lift and lower, tilt, the turbine, the mirror hand, bring to tooth, help: each named.
  for (const char* c : {"left drag", "W / S", "wheel", "arrow keys", "turbine", "Shift + any", "B", "F1", "1 to 5"})
    EXPECT_TRUE(has(mouse, c)) << c;
  const auto pen = controlLines(DrillInput::HapticPen, true);
  EXPECT_TRUE(has(pen, "the stylus"));
  EXPECT_TRUE(has(pen, "stylus buttons"));
  EXPECT_FALSE(has(pen, "W / S"));  // a haptic pen is not moved by keys
  const auto it = std::find_if(pen.begin(), pen.end(), [](const ControlLine& l) { return l.control == "turbine"; });
  ASSERT_NE(it, pen.end());
  EXPECT_NE(it->action.find("foot pedal"), std::string::npos);
  EXPECT_FALSE(has(controlLines(DrillInput::Script, false), "B"));
}

TEST_F(HelpTest, TheOverlayShowsTheTaskAndControlsAndGotItClosesItForGood) {
  state_.help.shown = true;
  state_.help.bur = "round_bur_010 (round bur, head 1.0 mm)";
  state_.help.bring_available = true;
  frame();  // a new window's table settles its columns in its first frame (the app lays a frame out unseen)
  PanelActions a = frame();
  for (const char* key : {"help.task", "help.instructions", "help.table", "help.bring", "help.close"})
    EXPECT_TRUE(rects_.count(key)) << key;
  EXPECT_GT(a.help_rect.width, 200);
  // Beside the panel, not over it.
  EXPECT_LE(a.help_rect.x + a.help_rect.width, a.panel_rect.x);
  EXPECT_TRUE(click("help.bring").bring_to_tooth);
  EXPECT_TRUE(state_.help.shown);
  const PanelActions closed = click("help.close");
  EXPECT_TRUE(closed.help_closed);
  EXPECT_FALSE(state_.help.shown);
  frame();
  EXPECT_FALSE(rects_.count("help.table"));
  // The Help button brings it back.
  click("help");
  frame();
  frame();
  EXPECT_TRUE(state_.help.shown);
  EXPECT_TRUE(rects_.count("help.table"));
}

TEST_F(HelpTest, BringIsDisabledWithItsReasonWhenTheTaskHasNoPath) {
  state_.help.shown = true;
  state_.help.bring_available = false;
  frame();
  frame();
  EXPECT_FALSE(click("help.bring").bring_to_tooth);
  EXPECT_NE(hoverTooltip("help.bring").find("no professional's path"), std::string::npos);
}

TEST_F(HelpTest, EveryDisabledRunButtonSaysWhy) {
  state_.run_state = RunState::Running;
  frame();
  EXPECT_NE(hoverTooltip("score").find("Press Stop first"), std::string::npos);
  EXPECT_NE(hoverTooltip("start").find("Already running"), std::string::npos);
  EXPECT_NE(hoverTooltip("reset").find("Stop first"), std::string::npos);
  EXPECT_FALSE(click("score").score);
  state_.run_state = RunState::Idle;
  frame();
  EXPECT_NE(hoverTooltip("score").find("Nothing to score yet"), std::string::npos);
  EXPECT_NE(hoverTooltip("stop").find("Nothing is running"), std::string::npos);
  state_.run_state = RunState::Stopped;
  frame();
  EXPECT_TRUE(click("score").score);
}

TEST_F(HelpTest, TheGuidanceSwitchAndSliderApplyFromTheNextSegmentAndSayWhyWhenThereIsNoPath) {
  frame();
  click("page.tools");
  frame();
  // No path: the switch is disabled and says why.
  EXPECT_FALSE(click("guidance").guidance_changed);
  EXPECT_FALSE(state_.guidance.on);
  EXPECT_NE(hoverTooltip("guidance").find("No professional's path"), std::string::npos);
  state_.guidance.available = true;
  state_.guidance.source = "the task's scripted professional";
  frame();
  EXPECT_TRUE(click("guidance").guidance_changed);
  EXPECT_TRUE(state_.guidance.on);
  // The slider: a click at its left end sets its least stiffness.
  const auto r = rects_.at("guidance.stiffness");
  const ImVec2 left(r.min_x + 1.0f, 0.5f * (r.min_y + r.max_y));
  mouse(left, false);
  PanelActions a = mouse(left, true);
  mouse(left, false);
  EXPECT_TRUE(a.guidance_changed);
  EXPECT_NEAR(state_.guidance.stiffness_n_per_mm, 0.1, 0.05);
}

}  // namespace
}  // namespace dentsim::ui
