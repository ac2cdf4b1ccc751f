// The professional's ghost on lavapipe: showing it changes only the pixels its tools project to, blends them over the scene at its opacity, and never covers the student's nearer tool.
#include "render/scene_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>

#include "gpu/gpu_fixture.h"
#include "model/builtin_assets.h"
#include "render/camera.h"
#include "render/offscreen.h"
#include "render/tooth_surfaces.h"

namespace dentsim::render::test {
namespace {

constexpr uint32_t kW = 240, kH = 180;

class GhostRender : public gpu::test::GraphicsGpuTest {
 protected:
  void SetUp() override {
    GraphicsGpuTest::SetUp();
    if (!ctx_) return;
    auto r = SceneRenderer::create(*ctx_, kDefaultColourFormat, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    ASSERT_TRUE(r.ok()) << r.message();
    renderer_.emplace(std::move(*r));
    auto t = ToothSurfaces::create(*ctx_);
    ASSERT_TRUE(t.ok()) << t.message();
    tooth_.emplace(std::move(*t));  // never built: tools only
  }
  void TearDown() override {
    if (ctx_) {
      renderer_.reset();
      tooth_.reset();
      EXPECT_TRUE(ctx_->waitIdle().ok());
    }
    GraphicsGpuTest::TearDown();
  }

  RgbImage render(const FrameState& frame) {
    auto img = renderOffscreen(*ctx_, *renderer_, *tooth_, frame, kW, kH);
    EXPECT_TRUE(img.ok()) << (img.ok() ? "" : img.message());
    if (!img.ok()) return RgbImage{};
    // With DENTSIM_TEST_IMAGES=DIR set, every frame is also written there, to look at.
    if (const char* dir = std::getenv("DENTSIM_TEST_IMAGES"); dir && *dir) {
      const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
      EXPECT_TRUE(writePng(std::string(dir) + "/" + info->name() + "_" + std::to_string(frames_++) + ".png", *img).ok());
    }
    return std::move(*img);
  }
  int frames_ = 0;

  std::optional<SceneRenderer> renderer_;
  std::optional<ToothSurfaces> tooth_;
};

// A side view of two drills: the student's at the front, the professional's ghost 15 mm behind it
// and 1.5 mm to the side, so that the student's handpiece covers part of the ghost.
FrameState twoDrills() {
  FrameState f;
  f.eye = {0.0f, -80.0f, 12.0f};
  f.view = glm::lookAt(f.eye, glm::vec3(0.0f, 0.0f, 12.0f), glm::vec3(0.0f, 0.0f, 1.0f));
  f.projection = glm::perspectiveRH_ZO(glm::radians(32.0f), float(kW) / float(kH), 1.0f, 300.0f);
  f.projection[1][1] = -f.projection[1][1];  // Vulkan's y down
  f.light_dir = glm::normalize(glm::vec3(0.3f, -1.0f, 0.6f));
  f.tooth_shown = false;
  f.drill_shown = true;
  f.drill = {{-1.0, 0.0, 0.0}, Quat{}};
  f.bur = "round_bur_010";
  f.ghost_drill = {{0.5, 15.0, 1.0}, Quat::fromAxisAngle({0.0, 1.0, 0.0}, 0.15)};
  f.ghost_bur = "fissure_bur_010";  // the professional's own bur, not the student's
  f.ghost_opacity = 0.4f;
  return f;
}

// Where `mesh` posed by `pose` lands on screen: the bounding box of its projected vertices [px].
struct Box {
  float x0 = 1e9f, y0 = 1e9f, x1 = -1e9f, y1 = -1e9f;
  bool contains(int x, int y, float margin) const {
    return float(x) + 0.5f >= x0 - margin && float(x) + 0.5f <= x1 + margin && float(y) + 0.5f >= y0 - margin &&
           float(y) + 0.5f <= y1 + margin;
  }
};
void addProjection(Box& box, const FrameState& f, std::string_view tool, const Pose& pose) {
  auto mesh = loadBuiltinTool(tool);
  ASSERT_TRUE(mesh.ok()) << mesh.message();
  const glm::mat4 m = f.projection * f.view * toGlm(pose);
  for (const Vec3f& p : mesh->positions) {
    const glm::vec4 c = m * glm::vec4(p[0], p[1], p[2], 1.0f);
    const float x = (c.x / c.w * 0.5f + 0.5f) * float(kW), y = (c.y / c.w * 0.5f + 0.5f) * float(kH);
    box.x0 = std::min(box.x0, x);
    box.x1 = std::max(box.x1, x);
    box.y0 = std::min(box.y0, y);
    box.y1 = std::max(box.y1, y);
  }
}

bool samePixel(const RgbImage& a, const RgbImage& b, int x, int y) { return a.pixel(x, y) == b.pixel(x, y); }

TEST_F(GhostRender, GhostChangesOnlyItsFootprintAsABlendBehindTheStudentsTool) {
  const FrameState hidden_state = twoDrills();
  FrameState shown_state = hidden_state;
  shown_state.ghost_drill_shown = true;
  FrameState full_state = shown_state;  // the same ghost fully opaque: the colour it blends
  full_state.ghost_opacity = 1.0f;
  FrameState bare_state = hidden_state;  // the student's drill gone: the background alone
  bare_state.drill_shown = false;
  const RgbImage hidden = render(hidden_state), shown = render(shown_state), full = render(full_state),
                 bare = render(bare_state);
  ASSERT_EQ(hidden.width, int(kW));
  ASSERT_EQ(shown.width, int(kW));

  Box ghost;
  addProjection(ghost, hidden_state, "fissure_bur_010", hidden_state.ghost_drill);
  addProjection(ghost, hidden_state, "turbine_handpiece", hidden_state.ghost_drill);
  const std::array<uint8_t, 3> bg = bare.pixel(0, 0);

  int changed = 0, outside = 0, blended = 0, off_blend = 0, blue = 0, covered = 0, covered_changed = 0;
  for (int y = 0; y < int(kH); ++y)
    for (int x = 0; x < int(kW); ++x) {
      const bool student = !samePixel(hidden, bare, x, y);
      const bool ghost_there = !samePixel(full, hidden, x, y);
      if (!samePixel(shown, hidden, x, y)) {
        ++changed;
        if (!ghost.contains(x, y, 1.0f)) ++outside;
      }
      if (student) {
        // Where the student's tool stands in front, the ghost behind it shows nowhere.
        if (ghost.contains(x, y, 0.0f)) ++covered;
        if (!samePixel(shown, hidden, x, y)) ++covered_changed;
        continue;
      }
      if (!ghost_there) continue;
      // Over the background: shown = 0.4 ghost + 0.6 background, neither of the two.
      const auto s = shown.pixel(x, y), g = full.pixel(x, y);
      ++blended;
      bool ok = s != bg && s != g;
      for (int c = 0; c < 3; ++c)
        ok = ok && std::abs(float(s[c]) - (0.4f * float(g[c]) + 0.6f * float(bg[c]))) <= 1.5f;
      if (!ok) ++off_blend;
      if (s[2] > s[0] + 8) ++blue;
    }
  EXPECT_GT(changed, 300) << "the ghost barely shows";
  EXPECT_EQ(outside, 0) << "pixels changed outside the ghost's projected box (" << ghost.x0 << ", " << ghost.y0
                        << ") - (" << ghost.x1 << ", " << ghost.y1 << ")";
  EXPECT_GT(blended, 300);
  EXPECT_LE(off_blend, blended / 100) << "pixels over the background that are not 40% of the ghost's colour";
  EXPECT_GT(blue, blended * 9 / 10) << "the ghost's tint is pale blue";
  EXPECT_GT(covered, 50) << "the scene should put the student's tool in front of part of the ghost";
  EXPECT_EQ(covered_changed, 0) << "the ghost showed through the student's nearer tool";
}

// The student's own drill at the ghost's place, opaque steel, is not what the ghost looks like:
// the ghost is never drawn as a second real tool.
TEST_F(GhostRender, GhostIsNotTheOpaqueToolColour) {
  FrameState ghost_only = twoDrills();
  ghost_only.drill_shown = false;
  ghost_only.ghost_drill_shown = true;
  FrameState steel = ghost_only;
  steel.ghost_drill_shown = false;
  steel.drill_shown = true;
  steel.drill = ghost_only.ghost_drill;
  steel.bur = ghost_only.ghost_bur;
  const RgbImage a = render(ghost_only), b = render(steel);
  const std::array<uint8_t, 3> bg = a.pixel(0, 0);
  int both = 0, same = 0;
  for (int y = 0; y < int(kH); ++y)
    for (int x = 0; x < int(kW); ++x) {
      if (a.pixel(x, y) == bg || b.pixel(x, y) == bg) continue;
      ++both;
      if (a.pixel(x, y) == b.pixel(x, y)) ++same;
    }
  EXPECT_GT(both, 300);
  EXPECT_EQ(same, 0);
}

// A ghost exactly where the student's tool is (a student on the professional's path) leaves the
// student's tool as it was: the ghost yields at equal depth.
TEST_F(GhostRender, AGhostOnTheStudentsToolLeavesItUntinted) {
  FrameState hidden = twoDrills();
  hidden.ghost_drill = hidden.drill;
  hidden.ghost_bur = hidden.bur;
  FrameState shown = hidden;
  shown.ghost_drill_shown = true;
  const RgbImage a = render(hidden), b = render(shown);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  int changed = 0;
  for (int y = 0; y < int(kH); ++y)
    for (int x = 0; x < int(kW); ++x) changed += !samePixel(a, b, x, y);
  EXPECT_EQ(changed, 0);
}

// The mirror pass draws the ghost too: a mirror facing the eye beside the ghost shows it.
TEST_F(GhostRender, TheMirrorReflectsTheGhost) {
  FrameState f = twoDrills();
  f.drill_shown = false;
  f.mirror_shown = true;
  // The mirror's face stands left of the ghost, turned so that the eye sees the ghost in it.
  const Vec3 at{-16.0, 4.0, 10.0}, eye{f.eye.x, f.eye.y, f.eye.z};
  const auto unit = [](const Vec3& v) { return v * (1.0 / norm(v)); };
  const Vec3 n = unit(unit(f.ghost_drill.apply({0.0, 0.0, 8.0}) - at) - unit(at - eye));
  const Vec3 side = unit(cross(Vec3{0.0, 0.0, 1.0}, n));
  f.mirror = {at, Quat::fromAxes(side, cross(n, side), n)};
  FrameState g = f;
  g.ghost_drill_shown = true;
  const RgbImage without = render(f), with = render(g);
  ASSERT_TRUE(renderer_->mirrorDrawn());
  Box ghost;
  addProjection(ghost, f, "fissure_bur_010", f.ghost_drill);
  addProjection(ghost, f, "turbine_handpiece", f.ghost_drill);
  int reflected = 0;
  for (int y = 0; y < int(kH); ++y)
    for (int x = 0; x < int(kW); ++x)
      if (!ghost.contains(x, y, 2.0f) && !samePixel(with, without, x, y)) ++reflected;
  EXPECT_GT(reflected, 20) << "no ghost pixels in the mirror";
}

}  // namespace
}  // namespace dentsim::render::test
