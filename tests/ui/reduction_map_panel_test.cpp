// The panel's side of a crown task's reduction map, driven headless: the View page's switch (crown tasks only), the picture window holding the map instead of the score's picture, and the page fitting an 800-pixel window.
#include <gtest/gtest.h>

#include <string>

#include <imgui.h>

#include "ui/panel_widgets.h"
#include "ui/param_panel.h"

namespace dentsim::ui {
namespace {

constexpr float kDisplayW = 1280.0f;  // [px]
constexpr float kDisplayH = 800.0f;   // the window the panel must fit (issue 24) [px]

class ReductionMapPanel : public ::testing::Test {
 protected:
  void SetUp() override {
    ctx_ = ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(kDisplayW, kDisplayH);
    io.DeltaTime = 1.0f / 60.0f;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
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
  ImVec2 centre(const std::string& key) {
    EXPECT_TRUE(rects_.count(key)) << "no widget '" << key << "' this frame";
    const WidgetRect r = rects_.count(key) ? rects_.at(key) : WidgetRect{};
    return ImVec2((r.min_x + r.max_x) * 0.5f, (r.min_y + r.max_y) * 0.5f);
  }
  PanelActions mouse(ImVec2 p, bool down) {
    ImGui::GetIO().MousePos = p;
    ImGui::GetIO().MouseDown[0] = down;
    return frame();
  }
  // Hover, press, release; the actions of all three frames or'ed for the flags tested here.
  PanelActions click(ImVec2 p) {
    PanelActions a = mouse(p, false);
    const PanelActions press = mouse(p, true), release = mouse(p, false);
    a.params_changed |= press.params_changed || release.params_changed;
    return a;
  }
  void showPage(const std::string& key) {
    click(centre(key));
    frame();
  }

  ImGuiContext* ctx_ = nullptr;
  UiState state_;
  WidgetRects rects_;
};

TEST_F(ReductionMapPanel, TheSwitchIsOnTheViewPageOfACrownTaskOnly) {
  frame();
  showPage("page.view");
  ASSERT_TRUE(rects_.count("level")) << "the View page is in front";
  EXPECT_FALSE(rects_.count("reduction_map")) << "no crown task: no switch";
  state_.reduction.available = true;
  frame();
  ASSERT_TRUE(rects_.count("reduction_map"));
  EXPECT_FALSE(state_.reduction.shown) << "off by default";
  const PanelActions a = click(centre("reduction_map"));
  EXPECT_TRUE(state_.reduction.shown);
  EXPECT_FALSE(a.params_changed) << "the map is no tactile or visual parameter";
  click(centre("reduction_map"));
  EXPECT_FALSE(state_.reduction.shown);
}

// The picture window takes the map's size (its aspect fitted into the 320 px box, as the score's
// picture) while the app says the map is on screen, with or without a score; otherwise the score's.
TEST_F(ReductionMapPanel, ThePictureWindowHoldsTheMapWhileItIsOnScreen) {
  state_.reduction = {true, true, true, "bands: occlusal 1.5-2.0 mm, axial 1.0-1.5 mm", "40% within", 200, 100};
  frame();
  PanelActions a = frame();
  EXPECT_EQ(a.score_image_rect.width, 320);
  EXPECT_EQ(a.score_image_rect.height, 160);
  panel::WindowLayout w;
  EXPECT_TRUE(panel::windowLayout("Reduction map", &w));

  state_.score.valid = true;
  state_.score.image_width = 100;
  state_.score.image_height = 100;
  a = frame();
  EXPECT_EQ(a.score_image_rect.height, 160) << "the map, not the score's square picture";
  state_.reduction.on_screen = false;
  frame();
  a = frame();
  EXPECT_EQ(a.score_image_rect.width, 320);
  EXPECT_EQ(a.score_image_rect.height, 320) << "the score's picture again";
  state_.score = ScoreSummary{};
  EXPECT_TRUE(frame().score_image_rect.empty());
}

// The frame the map first shows, the View page (its switch, colours and bands) comes forward, and
// with the ghost's section above it, the page still fits the 800-pixel window.
TEST_F(ReductionMapPanel, TheViewPageComesForwardWithTheMapAndFits) {
  state_.reduction = {true, true, false, "", "", 0, 0};
  frame();
  EXPECT_FALSE(rects_.count("reduction_map")) << "the Task page is in front";
  state_.reduction.on_screen = true;
  state_.reduction.image_width = 800;
  state_.reduction.image_height = 600;
  state_.reduction.legend = "bands: occlusal 1.5-2.0 mm, axial 1.0-1.5 mm";
  state_.reduction.status = "39% within, 24% under, 37% over (0.5 s to measure)";
  state_.ghost_available = true;
  state_.ghost_source = "ghost: the task's ideal, a path long enough to wrap in the panel";
  frame();
  frame();
  EXPECT_TRUE(rects_.count("reduction_map"));
  panel::WindowLayout panel;
  ASSERT_TRUE(panel::windowLayout("Parameters", &panel));
  EXPECT_EQ(panel.scroll_max_y, 0.0f) << "the View page scrolls: " << panel.content_height << " px";
  EXPECT_LE(rects_.at("reduction_map").max_y, panel.rect.max_y);
}

}  // namespace
}  // namespace dentsim::ui
