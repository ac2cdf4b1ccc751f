// Tests of src/ui/imgui_layer.cpp on a Vulkan device: the panel rendered headless into an offscreen image, validation clean and reproducible.
#include "ui/imgui_layer.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <imgui.h>

#include "gpu/compute.h"
#include "gpu/gpu_fixture.h"
#include "render/offscreen.h"
#include "render/scene_renderer.h"
#include "render/tooth_surfaces.h"
#include "ui/param_panel.h"

namespace dentsim::ui {
namespace {

constexpr uint32_t kWidth = 640, kHeight = 480;  // [px]

// A validated graphics context (gpu/gpu_fixture.h), skipping only when no Vulkan device exists.
using ImGuiLayerTest = gpu::test::GraphicsGpuTest;

// What the panel is drawn with: the app's scene render pass (ending ready to copy out), an offscreen
// image of its colour format, and an empty tooth, so that a frame shows only the clear and ImGui.
struct Scene {
  render::SceneRenderer renderer;
  render::OffscreenTarget target;
  render::ToothSurfaces tooth;
  render::FrameState frame;
};

std::optional<Scene> makeScene(gpu::Context& ctx) {
  auto renderer = render::SceneRenderer::create(ctx, render::kDefaultColourFormat, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  EXPECT_TRUE(renderer.ok()) << (renderer.ok() ? "" : renderer.message());
  auto target = render::OffscreenTarget::create(ctx, kWidth, kHeight, render::kDefaultColourFormat);
  EXPECT_TRUE(target.ok()) << (target.ok() ? "" : target.message());
  auto tooth = render::ToothSurfaces::create(ctx);
  EXPECT_TRUE(tooth.ok()) << (tooth.ok() ? "" : tooth.message());
  if (!renderer || !target || !tooth) return std::nullopt;
  render::FrameState frame;
  frame.tooth_shown = false;
  frame.drill_shown = false;
  frame.mirror_shown = false;
  frame.background = {0.0f, 0.0f, 0.0f};  // black, so that anything ImGui draws shows
  return Scene{std::move(*renderer), std::move(*target), std::move(*tooth), frame};
}

// Renders one frame of the panel and the overlay for `state` through the scene pass and returns its RGB pixels.
std::vector<uint8_t> renderFrame(gpu::Context& ctx, ImGuiLayer& layer, Scene& scene, UiState& state) {
  layer.newFrame(int(kWidth), int(kHeight), 1.0 / 60.0);
  drawParamPanel(state);
  drawOverlay(state);
  Status s = gpu::submitAndWait(ctx, "imgui test frame", [&](gpu::Commands& c) -> Status {
    scene.renderer.markSubmitted(c.serial());
    return scene.renderer.recordFrame(c.cmd(), scene.target.image(), scene.tooth, scene.frame,
                                      [&](VkCommandBuffer cmd) { layer.render(cmd); });
  });
  EXPECT_TRUE(s.ok()) << s.message();
  auto pixels = scene.target.readback(ctx);
  EXPECT_TRUE(pixels.ok()) << (pixels.ok() ? "" : pixels.message());
  return pixels.ok() ? std::move(pixels->rgb) : std::vector<uint8_t>{};
}

TEST_F(ImGuiLayerTest, RendersThePanelOffscreenCleanlyAndReproducibly) {
  std::optional<Scene> scene = makeScene(*ctx_);
  ASSERT_TRUE(scene.has_value());
  {
    auto layer = ImGuiLayer::create(*ctx_, scene->renderer.renderPass(), 0, 2, nullptr);
    ASSERT_TRUE(layer.ok()) << layer.message();
    EXPECT_FALSE(layer->wantsMouse());

    UiState state;
    state.stats = {16.7, 1000.0, 1.2, 4096};
    state.force = {2.0, 8.0, true};
    // Frame 1 measures the auto-sized overlay and hides it; frames 2 and 3 are the same frame.
    renderFrame(*ctx_, *layer, *scene, state);
    std::vector<uint8_t> second = renderFrame(*ctx_, *layer, *scene, state);
    std::vector<uint8_t> third = renderFrame(*ctx_, *layer, *scene, state);
    ASSERT_EQ(second.size(), size_t(kWidth) * kHeight * 3);
    EXPECT_TRUE(second == third) << "the same inputs gave different pixels";

    // Something was drawn over the black clear: the panel covers a good part of the image.
    size_t lit = 0;
    for (size_t i = 0; i < second.size(); i += 3)
      if (second[i] != 0 || second[i + 1] != 0 || second[i + 2] != 0) ++lit;
    EXPECT_GT(lit, size_t(kWidth) * kHeight / 10);

    // Without a frame open, the layer ends one cleanly when nothing is to be drawn.
    layer->newFrame(int(kWidth), int(kHeight), 0.0);
    layer->discardFrame();
  }
  ASSERT_TRUE(ctx_->waitIdle().ok());
  // The target's view dies before the renderer; it forgets its framebuffer for it first.
  scene->renderer.forgetTarget(scene->target.image().view);
}

}  // namespace
}  // namespace dentsim::ui
