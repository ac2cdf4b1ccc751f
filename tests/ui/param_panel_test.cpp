// Tests of src/ui/param_panel.cpp and the student's help it draws (controls_help.cpp), driven headless: a bare ImGui context, simulated mouse and keys, no backends and no GPU.
#include "ui/param_panel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <string>
#include <vector>

#include <imgui.h>
#include "ui/controls_help.h"
#include "ui/panel_widgets.h"

#include "test_support.h"
#include "ui/preset.h"

namespace dentsim::ui {
namespace {

constexpr float kDisplayW = 1280.0f;  // [px]
// Tall enough that any page, every section open, fits without scrolling.
constexpr float kDisplayH = 2000.0f;  // [px]
// The window height the panel must fit in (issue 24): 1280 x 800.
constexpr float kSmallDisplayH = 800.0f;  // [px]

// The panel's pages and the widgets each lays out.
const std::vector<std::pair<std::string, std::vector<std::string>>> kPages = {
    {"page.task", {"tooth", "tooth_path", "open_tooth", "task", "teacher"}},
    {"page.tissues",
     {"tab.enamel", "tab.dentin", "tab.pulp", "tab.caries", "tissues.enamel.stiffness_n_per_mm3",
      "tissues.enamel.damping_s_per_mm", "tissues.enamel.friction", "tissues.enamel.hardness", "looks.enamel.diffuse",
      "looks.enamel.alpha", "looks.enamel.ambient", "looks.enamel.specular", "looks.enamel.shininess"}},
    {"page.tools", {"bur", "bur.cutting_ability", "turbine.speed", "turbine.max_rpm", "sound.volume", "sound.mute"}},
    {"page.view", {"view.normal_neighbours.8", "view.normal_neighbours.64", "view.normal_neighbours.216", "level"}},
    {"page.presets", {"preset", "load", "save_name", "save", "section.advanced"}},
};

// One ImGui context per test, with the font atlas built (as a renderer backend would) and the
// mouse moved frame by frame.
class PanelTest : public ::testing::Test {
 protected:
  virtual float displayHeight() const { return kDisplayH; }
  void SetUp() override {
    ctx_ = ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(kDisplayW, displayHeight());
    io.DeltaTime = 1.0f / 60.0f;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    frame();  // the first frame places the windows; input works from the second
  }
  void TearDown() override { ImGui::DestroyContext(ctx_); }

  // One whole frame: the panel and the overlay, with the window stack checked balanced.
  PanelActions frame() {
    ImGui::NewFrame();
    rects_.clear();
    PanelActions a = drawParamPanel(state_, &rects_);
    drawOverlay(state_);
    ImGui::Render();
    EXPECT_EQ(panel::windowsLeftOpen(), 0);
    EXPECT_NE(ImGui::GetDrawData(), nullptr);
    return a;
  }

  ImVec2 centre(const std::string& key) const {
    const WidgetRect& r = rect(key);
    return ImVec2((r.min_x + r.max_x) * 0.5f, (r.min_y + r.max_y) * 0.5f);
  }
  const WidgetRect& rect(const std::string& key) const {
    auto it = rects_.find(key);
    if (it == rects_.end()) ADD_FAILURE() << "no widget '" << key << "' this frame";
    static const WidgetRect none;
    return it == rects_.end() ? none : it->second;
  }

  // A frame with the mouse at p and the left button as given.
  PanelActions mouse(ImVec2 p, bool down) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = p;
    io.MouseDown[0] = down;
    return frame();
  }
  // Hover, press, release over one point; the actions of the press and of the release frames.
  struct Click {
    PanelActions press, release;
  };
  Click click(ImVec2 p) {
    mouse(p, false);
    Click c;
    c.press = mouse(p, true);
    c.release = mouse(p, false);
    return c;
  }
  // Brings a page forward ("page.tissues") and lays it out.
  void showPage(const std::string& key) {
    click(centre(key));
    frame();
  }
  // Press at `from`, drag through `to`, release there.
  PanelActions drag(ImVec2 from, ImVec2 to) {
    mouse(from, false);
    PanelActions any = mouse(from, true);
    PanelActions moved = mouse(ImVec2((from.x + to.x) * 0.5f, (from.y + to.y) * 0.5f), true);
    PanelActions last = mouse(to, true);
    mouse(to, false);
    any.params_changed |= moved.params_changed | last.params_changed;
    return any;
  }

  ImGuiContext* ctx_ = nullptr;
  UiState state_;
  WidgetRects rects_;
};

// Only the named flag (or none) is set.
void expectOnly(const PanelActions& a, const std::vector<std::string>& set) {
  auto has = [&](const char* n) { return std::find(set.begin(), set.end(), n) != set.end(); };
  EXPECT_EQ(a.params_changed, has("params")) << "params_changed";
  EXPECT_EQ(a.bur_changed, has("bur")) << "bur_changed";
  EXPECT_EQ(a.speed_changed, has("speed")) << "speed_changed";
  EXPECT_EQ(a.level_changed, has("level")) << "level_changed";
  EXPECT_EQ(a.normal_mode_changed, has("normals")) << "normal_mode_changed";
  EXPECT_EQ(a.task_changed, has("task")) << "task_changed";
  EXPECT_EQ(a.tooth_changed, has("tooth")) << "tooth_changed";
  EXPECT_EQ(a.record_ideal, has("record_ideal")) << "record_ideal";
  EXPECT_EQ(a.sound_changed, has("sound")) << "sound_changed";
  EXPECT_EQ(a.start, has("start")) << "start";
  EXPECT_EQ(a.stop, has("stop")) << "stop";
  EXPECT_EQ(a.reset, has("reset")) << "reset";
  EXPECT_EQ(a.score, has("score")) << "score";
  EXPECT_TRUE(a.load_preset.empty());
  EXPECT_TRUE(a.save_preset.empty());
}

TEST_F(PanelTest, EveryWidgetIsLaidOutAndIdleFramesAskNothing) {
  PanelActions a = frame();
  expectOnly(a, {});
  EXPECT_TRUE(a.score_image_rect.empty());
  // The task page comes first; every page has the run's buttons above it.
  EXPECT_TRUE(rects_.count("tooth"));
  for (const auto& [page, keys] : kPages) {
    showPage(page);
    expectOnly(frame(), {});
    for (const std::string& key : keys) {
      ASSERT_TRUE(rects_.count(key)) << page << ": " << key;
      const WidgetRect& r = rects_.at(key);
      EXPECT_LT(r.min_x, r.max_x) << key;
      EXPECT_LT(r.min_y, r.max_y) << key;
      EXPECT_LE(r.max_y, kDisplayH) << key << " is off screen";
    }
    for (const char* key : {"start", "stop", "reset", "score"}) EXPECT_TRUE(rects_.count(key)) << page << ": " << key;
  }
  // The other tissues' tabs are closed, and the advanced section is folded.
  showPage("page.tissues");
  EXPECT_FALSE(rects_.count("tissues.dentin.hardness"));
  showPage("page.presets");
  EXPECT_FALSE(rects_.count("device.max_force_n"));
  EXPECT_TRUE(state_.params == defaultSimParams());
}

TEST_F(PanelTest, ClickingTheHardnessSliderSetsExactlyEnamelHardness) {
  frame();
  showPage("page.tissues");
  SimParams expected = state_.params;
  // The slider's usable track is symmetric inside its frame (grab padding and half a grab at each
  // end), so its centre is t = 0.5 of [0, 1].
  Click c = click(centre("tissues.enamel.hardness"));
  expected.tissue(Material::Enamel).hardness = 0.5;
  EXPECT_EQ(state_.params.tissue(Material::Enamel).hardness, 0.5);
  EXPECT_TRUE(state_.params == expected);
  expectOnly(c.press, {"params"});
  expectOnly(c.release, {});
}

TEST_F(PanelTest, DraggingPastTheEndsClampsToTheRange) {
  frame();
  showPage("page.tissues");
  const WidgetRect r = rect("tissues.enamel.hardness");
  const float y = (r.min_y + r.max_y) * 0.5f;
  PanelActions a = drag(centre("tissues.enamel.hardness"), ImVec2(r.max_x + 600.0f, y));
  EXPECT_TRUE(a.params_changed);
  EXPECT_EQ(state_.params.tissue(Material::Enamel).hardness, 1.0);
  drag(centre("tissues.enamel.hardness"), ImVec2(r.min_x - 600.0f, y));
  EXPECT_EQ(state_.params.tissue(Material::Enamel).hardness, 0.0);
}

TEST_F(PanelTest, AlphaSliderChangesOnlyEnamelAlpha) {
  frame();
  showPage("page.tissues");
  const SimParams touch = state_.params;
  LookParams expected = state_.looks;
  const WidgetRect r = rect("looks.enamel.alpha");
  // The last pixel column of the frame lies beyond the track's end: t clamps to 1.
  Click c = click(ImVec2(r.max_x - 1.0f, (r.min_y + r.max_y) * 0.5f));
  expected.look(Material::Enamel).alpha = 1.0;
  EXPECT_TRUE(state_.looks == expected);
  EXPECT_TRUE(state_.params == touch);
  expectOnly(c.press, {"params"});
}

TEST_F(PanelTest, ColourDragWritesBackOnlyTheDraggedComponent) {
  frame();
  showPage("page.tissues");
  const SimParams touch = state_.params;
  const LookParams before = state_.looks;
  const WidgetRect r = rect("looks.enamel.diffuse");
  // The red field is the first of the three inline fields, at least 30 px wide here.
  const ImVec2 from(r.min_x + 10.0f, (r.min_y + r.max_y) * 0.5f);
  PanelActions a = drag(from, ImVec2(from.x - 60.0f, from.y));
  EXPECT_TRUE(a.params_changed);
  const TissueLook& now = state_.looks.look(Material::Enamel);
  const TissueLook& was = before.look(Material::Enamel);
  EXPECT_LT(now.diffuse_r, was.diffuse_r);
  // Untouched components keep their exact doubles, not a float round trip of them.
  EXPECT_EQ(now.diffuse_g, was.diffuse_g);
  EXPECT_EQ(now.diffuse_b, was.diffuse_b);
  LookParams expected = before;
  expected.look(Material::Enamel).diffuse_r = now.diffuse_r;
  EXPECT_TRUE(state_.looks == expected);
  EXPECT_TRUE(state_.params == touch);
}

TEST_F(PanelTest, TabsSwitchTheEditedTissue) {
  frame();
  showPage("page.tissues");
  click(centre("tab.dentin"));
  frame();
  ASSERT_TRUE(rects_.count("tissues.dentin.hardness"));
  EXPECT_FALSE(rects_.count("tissues.enamel.hardness"));
  SimParams expected = state_.params;
  click(centre("tissues.dentin.friction"));
  // Friction's slider is [0, 2]: the centre is 1.
  expected.tissue(Material::Dentin).friction = 1.0;
  EXPECT_TRUE(state_.params == expected);
}

TEST_F(PanelTest, StartStopResetScoreFollowTheRunState) {
  frame();
  Click c = click(centre("start"));
  expectOnly(c.press, {});  // a button fires on release
  expectOnly(c.release, {"start"});

  // Running: Start, Reset and Score are disabled, Stop works.
  state_.run_state = RunState::Running;
  frame();
  expectOnly(click(centre("start")).release, {});
  expectOnly(click(centre("reset")).release, {});
  expectOnly(click(centre("score")).release, {});
  expectOnly(click(centre("stop")).release, {"stop"});

  state_.run_state = RunState::Stopped;
  frame();
  expectOnly(click(centre("score")).release, {"score"});
  expectOnly(click(centre("reset")).release, {"reset"});
  expectOnly(click(centre("stop")).release, {});
}

TEST_F(PanelTest, NormalsAndLevelRaiseTheirFlags) {
  frame();
  showPage("page.view");
  Click c = click(centre("view.normal_neighbours.64"));
  EXPECT_EQ(state_.looks.view.normals, NormalMode::Box64);
  expectOnly(c.press, {});
  expectOnly(c.release, {"params", "normals"});
  // Clicking the mode already chosen changes nothing.
  expectOnly(click(centre("view.normal_neighbours.64")).release, {});

  const WidgetRect r = rect("level");
  c = click(ImVec2(r.max_x - 1.0f, (r.min_y + r.max_y) * 0.5f));
  EXPECT_EQ(state_.level, kMaxLevel);
  expectOnly(c.press, {"level"});
  // A running task keeps its level.
  state_.run_state = RunState::Running;
  frame();
  click(ImVec2(r.min_x + 1.0f, (r.min_y + r.max_y) * 0.5f));
  EXPECT_EQ(state_.level, kMaxLevel);
}

TEST_F(PanelTest, TurbineSpeedFromSliderWheelAndKeysWithoutAPedal) {
  frame();
  showPage("page.tools");
  const ImVec2 p = centre("turbine.speed");
  Click c = click(p);
  EXPECT_EQ(state_.turbine_speed, 0.5);
  expectOnly(c.press, {"speed"});

  ImGuiIO& io = ImGui::GetIO();
  io.MouseWheel = 2.0f;  // two notches up, 0.05 each
  PanelActions a = mouse(p, false);
  io.MouseWheel = 0.0f;
  EXPECT_DOUBLE_EQ(state_.turbine_speed, 0.6);
  EXPECT_TRUE(a.speed_changed);

  // PageDown as the GLFW backend would map it: one press, one step of 0.1.
  io.KeyMap[ImGuiKey_PageDown] = 300;
  io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
  io.KeysDown[300] = true;
  a = frame();
  EXPECT_TRUE(a.speed_changed);
  EXPECT_DOUBLE_EQ(state_.turbine_speed, 0.5);
  a = frame();  // held, before the repeat delay: no second step
  EXPECT_FALSE(a.speed_changed);
  io.KeysDown[300] = false;
  frame();

  // With a pedal the speed is the pedal's: the bar takes no input.
  state_.pedal_present = true;
  frame();
  c = click(centre("turbine.speed"));
  EXPECT_DOUBLE_EQ(state_.turbine_speed, 0.5);
  EXPECT_FALSE(c.press.speed_changed);
}

TEST_F(PanelTest, VolumeSliderAndMuteBoxSetTheSoundAndNothingElse) {
  frame();
  showPage("page.tools");
  const SimParams before = state_.params;
  const LookParams looks_before = state_.looks;
  // The slider's centre is half volume; past its right end, full.
  Click c = click(centre("sound.volume"));
  EXPECT_EQ(state_.sound.volume, 0.5);
  expectOnly(c.press, {"sound"});
  const WidgetRect r = rect("sound.volume");
  drag(centre("sound.volume"), ImVec2(r.max_x + 400.0f, (r.min_y + r.max_y) * 0.5f));
  EXPECT_EQ(state_.sound.volume, 1.0);
  EXPECT_FALSE(state_.sound.mute);
  Click m = click(centre("sound.mute"));
  EXPECT_TRUE(state_.sound.mute);
  EXPECT_TRUE(m.press.sound_changed || m.release.sound_changed);
  click(centre("sound.mute"));
  EXPECT_FALSE(state_.sound.mute);
  EXPECT_TRUE(state_.params == before) << "sound is not a tactile or visual parameter";
  EXPECT_TRUE(state_.looks == looks_before) << "sound is not a tactile or visual parameter";
}

TEST_F(PanelTest, LoadAndSaveButtonsNameThePreset) {
  state_.presets = {"default", "soft"};
  state_.selected_preset = "soft";
  frame();
  showPage("page.presets");
  Click c = click(centre("load"));
  EXPECT_EQ(c.release.load_preset, "soft");
  // Save is disabled while the name field is empty.
  EXPECT_TRUE(click(centre("save")).release.save_preset.empty());
  state_.save_name = "hard";
  frame();
  EXPECT_EQ(click(centre("save")).release.save_preset, "hard");
}

TEST_F(PanelTest, ScorePictureRectangleIsLaidOutFromTheImageAspect) {
  state_.score.valid = true;
  state_.score.total = 87.5;
  state_.score.rows = {{"over-cut", "0.12 mm^3"}, {"under-cut", "0.30 mm^3"}};
  state_.score.image_width = 200;
  state_.score.image_height = 100;
  frame();
  PanelActions a = frame();
  // 200 x 100 fitted into the 320 px box: scale 1.6, so 320 x 160. With no tooth to keep clear, the
  // window (336 px wide: 8 px padding each side) stands at the right of what the panel leaves free
  // (the panel at x 890, 10 px margins), 180 px down; the picture starts one window padding (8, 8)
  // in, below the 19 px title bar (13 px font plus twice the 3 px frame padding): (552, 207).
  EXPECT_EQ(a.score_image_rect.x, 880 - 336 + 8);
  EXPECT_EQ(a.score_image_rect.y, 207);
  EXPECT_EQ(a.score_image_rect.width, 320);
  EXPECT_EQ(a.score_image_rect.height, 160);
  // The score page came forward with the score.
  EXPECT_TRUE(rects_.count("page.score"));
  EXPECT_FALSE(rects_.count("tooth"));

  state_.score = ScoreSummary{};
  EXPECT_TRUE(frame().score_image_rect.empty());
}

// Every slider of every section, dragged far past both ends, leaves a set that saves: the panel's
// ranges lie inside parsePreset's.
TEST_F(PanelTest, NoSliderCanProduceASetThatWouldNotSave) {
  frame();
  showPage("page.presets");
  click(centre("section.advanced"));  // unfold it
  frame();
  ASSERT_TRUE(rects_.count("device.max_force_n"));

  // The sliders of the tools and presets pages, then each tissue's.
  auto slidersShown = [&] {
    std::vector<std::string> sliders;
    for (const auto& [key, r] : rects_) {
      const bool colour = key.ends_with(".diffuse") || key.ends_with(".ambient") || key.ends_with(".specular");
      const bool slider = key.starts_with("tissues.") || key.starts_with("looks.") || key.starts_with("cutting.") ||
                          key.starts_with("coupling.") || key.starts_with("device.") ||
                          key.starts_with("point_shell.") || key == "bur.cutting_ability" || key == "turbine.max_rpm";
      if (slider && !colour && !key.starts_with("value.")) sliders.push_back(key);
    }
    return sliders;
  };
  int dragged = 0;
  auto dragAll = [&](const std::vector<std::string>& sliders) {
    for (const std::string& key : sliders) {
      for (float dx : {2000.0f, -2000.0f}) {
        const WidgetRect r = rect(key);
        const ImVec2 c = centre(key);
        drag(c, ImVec2(dx > 0 ? r.max_x + dx : r.min_x + dx, c.y));
        Result<Preset> back = parsePreset(presetJson({state_.params, state_.looks}), "panel");
        ASSERT_TRUE(back.ok()) << key << ": " << back.message();
        ++dragged;
      }
    }
  };
  dragAll(slidersShown());  // 15: 2 cutting, 6 coupling, 4 device, 3 shells
  showPage("page.tools");
  dragAll(slidersShown());  // 2: ability, max rpm
  showPage("page.tissues");
  for (const char* tab : {"tab.enamel", "tab.dentin", "tab.pulp", "tab.caries"}) {
    click(centre(tab));
    frame();
    dragAll(slidersShown());  // the tissue's 6: spring, damper, friction, hardness, alpha, shininess
  }
  EXPECT_EQ(dragged, (15 + 2 + 4 * 6) * 2);
}

TEST_F(PanelTest, OverlayAndScoreDrawWithExtremeValues) {
  state_.stats = {16.7, 998.0, 2.5, 123456};
  state_.force = {12.0, 8.0, true};  // beyond full scale: the bar stays full
  state_.turbine_speed = 1.0;
  state_.score.valid = true;
  state_.score.rows = {{"time", "3 min"}};
  state_.status = "preset 'soft' saved";
  for (int i = 0; i < 3; ++i) expectOnly(frame(), {});
  state_.force = {0.0, 0.0, false};  // no scale yet
  expectOnly(frame(), {});
}

// Picking a tooth from the list, or opening one by path, raises tooth_changed with the choice in
// the state; a task file that does not load shows its error and starts nothing.
TEST_F(PanelTest, ThePickersRaiseTheirChoicesAndABrokenTaskShowsItsError) {
  state_.course.teeth = {{"built-in molar, level 7", "", 7}, {"built-in molar, level 9", "", 9}, {"t.dvol", "/c/t.dvol", 0}};
  state_.course.tasks = {{"caries", "caries (built in)", "Remove the caries", "", true, ""},
                         {"/c/good.json", "good.json", "A good task", "Do it well.", false, ""},
                         {"/c/bad.json", "bad.json", "", "", false, "/c/bad.json: version: expected 1 or 2"}};
  state_.level = 9;
  frame();
  // The tooth list: the third entry, a file.
  click(centre("tooth"));
  frame();
  Click c = click(centre("tooth.item.2"));
  EXPECT_TRUE(c.press.tooth_changed || c.release.tooth_changed);
  EXPECT_EQ(state_.tooth, "/c/t.dvol");
  frame();
  // The built-in molar at level 7.
  click(centre("tooth"));
  frame();
  c = click(centre("tooth.item.0"));
  EXPECT_TRUE(c.press.tooth_changed || c.release.tooth_changed);
  EXPECT_EQ(state_.tooth, "");
  EXPECT_EQ(state_.level, 7);
  frame();
  // Any .dvol by its path: Open is disabled until a path is typed.
  expectOnly(click(centre("open_tooth")).release, {});
  state_.tooth_path = "/elsewhere/x.dvol";
  frame();
  expectOnly(click(centre("open_tooth")).release, {"tooth"});
  EXPECT_EQ(state_.tooth, "/elsewhere/x.dvol");

  // The broken task: listed, its error shown, nothing started.
  click(centre("task"));
  frame();
  c = click(centre("task.item.2"));
  EXPECT_FALSE(c.press.task_changed || c.release.task_changed);
  EXPECT_EQ(state_.task, "caries");
  EXPECT_EQ(state_.task_error, "/c/bad.json: version: expected 1 or 2");
  frame();
  // The good one starts.
  click(centre("task"));
  frame();
  c = click(centre("task.item.1"));
  EXPECT_TRUE(c.press.task_changed || c.release.task_changed);
  EXPECT_EQ(state_.task, "/c/good.json");
}

// Record as ideal is offered in teacher mode only, and works only for a task file whose segment is
// being recorded.
TEST_F(PanelTest, RecordAsIdealNeedsTeacherModeATaskFileAndARecordedSegment) {
  frame();
  EXPECT_FALSE(rects_.count("record_ideal"));
  click(centre("teacher"));
  frame();
  EXPECT_TRUE(state_.teacher);
  ASSERT_TRUE(rects_.count("record_ideal"));
  state_.task_is_file = false;
  state_.segment_recorded = true;
  frame();
  expectOnly(click(centre("record_ideal")).release, {});
  state_.task_is_file = true;
  state_.segment_recorded = false;
  frame();
  expectOnly(click(centre("record_ideal")).release, {});
  state_.segment_recorded = true;
  frame();
  expectOnly(click(centre("record_ideal")).release, {"record_ideal"});
}

// The score picture stands beside the tooth's rectangle, never over it: right of it when there is
// room before the panel, else left of it, else shrunk on the roomier side.
TEST_F(PanelTest, TheScorePictureStaysOffTheTooth) {
  state_.score.valid = true;
  state_.score.image_width = 200;
  state_.score.image_height = 100;
  auto overlaps = [](const PixelRect& a, const PixelRect& b) {
    return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
  };
  for (const PixelRect tooth : {PixelRect{150, 300, 300, 400}, PixelRect{500, 200, 300, 400}, PixelRect{200, 200, 450, 500}}) {
    // The window follows the tooth from frame to frame.
    state_.keep_clear = tooth;
    frame();
    const PanelActions a = frame();
    ASSERT_FALSE(a.score_image_rect.empty());
    EXPECT_FALSE(overlaps(a.score_image_rect, tooth)) << "tooth at x " << tooth.x << ": picture at " << a.score_image_rect.x
                                                      << ", " << a.score_image_rect.y << " size " << a.score_image_rect.width;
    EXPECT_LE(a.score_image_rect.x + a.score_image_rect.width, a.panel_rect.x) << "the picture stays off the panel";
    EXPECT_GE(a.score_image_rect.x, 0);
  }
}

// In a 1280 x 800 window every page of the panel fits without scrolling, with every section open
// and a score shown, and each slider's value stands beside its track, inside the window.
// The ghost's box and follow choice (View page): disabled while the app has no ghost to show; then
// the box shows it and the radio buttons pick how it moves, and none of it is a tactile or visual
// parameter.
TEST_F(PanelTest, GhostBoxAndFollowChoiceNeedAGhostToShow) {
  frame();
  showPage("page.view");
  click(centre("ghost"));
  EXPECT_FALSE(state_.ghost_shown) << "the box is disabled without a ghost";
  state_.ghost_available = true;
  frame();
  Click c = click(centre("ghost"));
  EXPECT_TRUE(state_.ghost_shown);
  EXPECT_FALSE(c.press.params_changed || c.release.params_changed);
  click(centre("ghost.follow.nearest"));
  EXPECT_TRUE(state_.ghost_nearest);
  click(centre("ghost.follow.time"));
  EXPECT_FALSE(state_.ghost_nearest);
  click(centre("ghost"));
  EXPECT_FALSE(state_.ghost_shown);
}

class SmallPanelTest : public PanelTest {
 protected:
  float displayHeight() const override { return kSmallDisplayH; }
};

TEST_F(SmallPanelTest, EveryPageFitsIn800PixelsAndNoValueIsUnderItsSlider) {
  state_.score.valid = true;
  state_.score.total = 71.5;
  for (int i = 0; i < 12; ++i) state_.score.rows.push_back({"part " + std::to_string(i), "1.0 mm^3"});
  state_.teacher = true;
  state_.task_title = "Prepare an occlusal class I cavity by indirect vision, in the mirror";
  state_.task_instructions = std::string(400, 'x');
  state_.tooth_error = "t.dvol: not a dentsim volume file";
  state_.ideal_status = "ideal recorded: t.ideal.dses and t.ideal.dvol beside t.json";
  state_.status = "a status line long enough to wrap once in the panel's width, as notices often do";
  frame();
  panel::WindowLayout panel;
  ASSERT_TRUE(panel::windowLayout("Parameters", &panel));
  EXPECT_LE(panel.rect.max_y, kSmallDisplayH) << "the panel itself fits the window";
  int values = 0;
  for (const char* page : {"page.task", "page.tissues", "page.tools", "page.view", "page.presets", "page.score"}) {
    showPage(page);
    if (std::string(page) == "page.presets") {
      click(centre("section.advanced"));
      frame();
      ASSERT_TRUE(rects_.count("device.max_force_n"));
    }
    frame();
    ASSERT_TRUE(panel::windowLayout("Parameters", &panel));
    EXPECT_EQ(panel.scroll_max_y, 0.0f) << page << " scrolls: its content is " << panel.content_height << " px high";
    for (const auto& [key, r] : rects_) {
      EXPECT_LE(r.max_y, panel.rect.max_y) << page << ": " << key << " is below the panel";
      if (!key.starts_with("value.")) continue;
      const std::string slider = key.substr(6);
      ASSERT_TRUE(rects_.count(slider)) << key;
      EXPECT_GE(r.min_x, rects_.at(slider).max_x) << key << " overlaps its track";
      EXPECT_LE(r.max_x, panel.rect.max_x) << key << " runs off the panel";
      ++values;
    }
  }
  EXPECT_GT(values, 20);
}

TEST(PresetActions, LoadAndSaveUpdateStateAndStatus) {
  test::TempDir dir;
  PresetStore store(dir.path().string());
  UiState state;
  state.params.tissue(Material::Pulp).hardness = 0.25;
  state.looks.view.normals = NormalMode::Box8;

  PanelActions save;
  save.save_preset = "pulp";
  applyPresetActions(save, store, state);
  EXPECT_EQ(state.status, "preset 'pulp' saved");
  EXPECT_EQ(state.presets, (std::vector<std::string>{"default", "pulp"}));
  EXPECT_EQ(state.selected_preset, "pulp");
  EXPECT_FALSE(save.params_changed);

  PanelActions load;
  load.load_preset = "default";
  applyPresetActions(load, store, state);
  EXPECT_TRUE(state.params == defaultSimParams());
  EXPECT_TRUE(state.looks == defaultLookParams());
  EXPECT_TRUE(load.params_changed);
  EXPECT_TRUE(load.normal_mode_changed);  // 8 -> 216
  EXPECT_EQ(state.status, "preset 'default' loaded");

  PanelActions bad;
  bad.save_preset = "default";
  applyPresetActions(bad, store, state);
  EXPECT_EQ(state.status, "preset 'default' is built in and read-only: save under another name");

  PanelActions missing;
  missing.load_preset = "nope";
  applyPresetActions(missing, store, state);
  EXPECT_FALSE(missing.params_changed);
  EXPECT_NE(state.status.find("nope.json"), std::string::npos) << state.status;
  EXPECT_TRUE(state.params == defaultSimParams());
}

// ---- the student's help: the controls overlay, the disabled buttons' reasons, guidance ----------------

// At the window size a student has (1280 x 800), with a task shown.
class HelpTest : public PanelTest {
 protected:
  float displayHeight() const override { return kSmallDisplayH; }
  void SetUp() override {
    state_.task_title = "Class I cavity";
    state_.task_instructions = "Prepare the occlusal fissures of the lower first molar.";
    PanelTest::SetUp();
  }
  // A click on a widget by its key: the actions of its press and its release frames together.
  PanelActions press(const std::string& key) {
    const Click c = click(centre(key));
    PanelActions a = c.press;
    a.score |= c.release.score;
    a.help_closed |= c.release.help_closed;
    a.bring_to_tooth |= c.release.bring_to_tooth;
    a.guidance_changed |= c.release.guidance_changed;
    return a;
  }
  // The tooltip over `key` after hovering it for a few frames.
  std::string hoverTooltip(const std::string& key) {
    const ImVec2 p = centre(key);
    for (int i = 0; i < 3; ++i) mouse(p, false);
    return panel::shownTooltip();
  }
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
  EXPECT_TRUE(press("help.bring").bring_to_tooth);
  EXPECT_TRUE(state_.help.shown);
  const PanelActions closed = press("help.close");
  EXPECT_TRUE(closed.help_closed);
  EXPECT_FALSE(state_.help.shown);
  frame();
  EXPECT_FALSE(rects_.count("help.table"));
  // The Help button brings it back.
  press("help");
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
  EXPECT_FALSE(press("help.bring").bring_to_tooth);
  EXPECT_NE(hoverTooltip("help.bring").find("no professional's path"), std::string::npos);
}

TEST_F(HelpTest, EveryDisabledRunButtonSaysWhy) {
  state_.run_state = RunState::Running;
  frame();
  EXPECT_NE(hoverTooltip("score").find("Press Stop first"), std::string::npos);
  EXPECT_NE(hoverTooltip("start").find("Already running"), std::string::npos);
  EXPECT_NE(hoverTooltip("reset").find("Stop first"), std::string::npos);
  EXPECT_FALSE(press("score").score);
  state_.run_state = RunState::Idle;
  frame();
  EXPECT_NE(hoverTooltip("score").find("Nothing to score yet"), std::string::npos);
  EXPECT_NE(hoverTooltip("stop").find("Nothing is running"), std::string::npos);
  state_.run_state = RunState::Stopped;
  frame();
  EXPECT_TRUE(press("score").score);
}

TEST_F(HelpTest, TheGuidanceSwitchAndSliderApplyFromTheNextSegmentAndSayWhyWhenThereIsNoPath) {
  frame();
  press("page.tools");
  frame();
  // No path: the switch is disabled and says why.
  EXPECT_FALSE(press("guidance").guidance_changed);
  EXPECT_FALSE(state_.guidance.on);
  EXPECT_NE(hoverTooltip("guidance").find("No professional's path"), std::string::npos);
  state_.guidance.available = true;
  state_.guidance.source = "the task's scripted professional";
  frame();
  EXPECT_TRUE(press("guidance").guidance_changed);
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
