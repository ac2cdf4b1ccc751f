// Tests of src/ui/imgui_layer.cpp on a Vulkan device: the panel rendered headless into an offscreen image, validation clean and reproducible.
#include "ui/imgui_layer.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <optional>
#include <vector>

#include <imgui.h>

#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "gpu/context.h"
#include "ui/param_panel.h"

namespace dentsim::ui {
namespace {

constexpr uint32_t kWidth = 640, kHeight = 480;  // [px]
constexpr VkFormat kFormat = VK_FORMAT_R8G8B8A8_UNORM;

// A validated graphics context, skipping only when no Vulkan device exists; any validation error or
// warning fails the test (tests/gpu/gpu_fixture.h does the same for compute).
class ImGuiLayerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    gpu::ContextOptions options;
    options.enable_validation = true;
    options.graphics = true;
    auto created = gpu::Context::create(options);
    if (!created) {
      if (gpu::isNoDeviceError(created.error())) GTEST_SKIP() << "no Vulkan device: " << created.message();
      FAIL() << "context creation failed: " << created.message();
    }
    ctx_.emplace(std::move(*created));
  }
  void TearDown() override {
    if (!ctx_) return;
    EXPECT_EQ(ctx_->validationErrorCount(), 0u) << "last validation message: " << ctx_->lastValidationMessage();
    EXPECT_EQ(ctx_->validationWarningCount(), 0u) << "last validation message: " << ctx_->lastValidationMessage();
  }

  std::optional<gpu::Context> ctx_;
};

// A colour image, its render pass (clear, then ready to copy out) and framebuffer; freed in order.
struct Target {
  VkDevice device = VK_NULL_HANDLE;
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkRenderPass pass = VK_NULL_HANDLE;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;

  ~Target() {
    if (!device) return;
    vkDestroyFramebuffer(device, framebuffer, nullptr);
    vkDestroyRenderPass(device, pass, nullptr);
    vkDestroyImageView(device, view, nullptr);
    vkDestroyImage(device, image, nullptr);
    vkFreeMemory(device, memory, nullptr);
  }
};

void makeTarget(gpu::Context& ctx, Target& t) {
  gpu::ContextCore& core = ctx.core();
  t.device = core.device;

  VkImageCreateInfo ii{};
  ii.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = kFormat;
  ii.extent = {kWidth, kHeight, 1};
  ii.mipLevels = 1;
  ii.arrayLayers = 1;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  ASSERT_EQ(vkCreateImage(core.device, &ii, nullptr, &t.image), VK_SUCCESS);
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(core.device, t.image, &req);
  const int type = core.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, 0);
  ASSERT_GE(type, 0);
  VkMemoryAllocateInfo ai{};
  ai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = uint32_t(type);
  ASSERT_EQ(vkAllocateMemory(core.device, &ai, nullptr, &t.memory), VK_SUCCESS);
  ASSERT_EQ(vkBindImageMemory(core.device, t.image, t.memory, 0), VK_SUCCESS);

  VkImageViewCreateInfo vi{};
  vi.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
  vi.image = t.image;
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = kFormat;
  vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  ASSERT_EQ(vkCreateImageView(core.device, &vi, nullptr, &t.view), VK_SUCCESS);

  VkAttachmentDescription colour{};
  colour.format = kFormat;
  colour.samples = VK_SAMPLE_COUNT_1_BIT;
  colour.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  colour.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  colour.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  colour.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  colour.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  colour.finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = 1;
  sub.pColorAttachments = &ref;
  // The copy after the pass reads what the subpass wrote.
  VkSubpassDependency dep{};
  dep.srcSubpass = 0;
  dep.dstSubpass = VK_SUBPASS_EXTERNAL;
  dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dep.dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  dep.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dep.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  VkRenderPassCreateInfo ri{};
  ri.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
  ri.attachmentCount = 1;
  ri.pAttachments = &colour;
  ri.subpassCount = 1;
  ri.pSubpasses = &sub;
  ri.dependencyCount = 1;
  ri.pDependencies = &dep;
  ASSERT_EQ(vkCreateRenderPass(core.device, &ri, nullptr, &t.pass), VK_SUCCESS);

  VkFramebufferCreateInfo fi{};
  fi.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
  fi.renderPass = t.pass;
  fi.attachmentCount = 1;
  fi.pAttachments = &t.view;
  fi.width = kWidth;
  fi.height = kHeight;
  fi.layers = 1;
  ASSERT_EQ(vkCreateFramebuffer(core.device, &fi, nullptr, &t.framebuffer), VK_SUCCESS);
}

// Renders one frame of the panel and the overlay for `state` and returns its RGBA pixels.
std::vector<std::byte> renderFrame(gpu::Context& ctx, ImGuiLayer& layer, const Target& t, UiState& state,
                                   gpu::Buffer& readback) {
  layer.newFrame(int(kWidth), int(kHeight), 1.0 / 60.0);
  drawParamPanel(state);
  drawOverlay(state);
  Status s = gpu::submitAndWait(ctx, "imgui test frame", [&](gpu::Commands& c) -> Status {
    VkClearValue clear{};
    clear.color = {{0.0f, 0.0f, 0.0f, 1.0f}};
    VkRenderPassBeginInfo bi{};
    bi.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
    bi.renderPass = t.pass;
    bi.framebuffer = t.framebuffer;
    bi.renderArea = {{0, 0}, {kWidth, kHeight}};
    bi.clearValueCount = 1;
    bi.pClearValues = &clear;
    vkCmdBeginRenderPass(c.cmd(), &bi, VK_SUBPASS_CONTENTS_INLINE);
    layer.render(c.cmd());
    vkCmdEndRenderPass(c.cmd());
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {kWidth, kHeight, 1};
    vkCmdCopyImageToBuffer(c.cmd(), t.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.handle(), 1, &region);
    c.use(readback);
    return Ok{};
  });
  EXPECT_TRUE(s.ok()) << s.message();
  std::vector<std::byte> pixels(size_t(kWidth) * kHeight * 4);
  Status d = readback.download(ctx, pixels);
  EXPECT_TRUE(d.ok()) << d.message();
  return pixels;
}

TEST_F(ImGuiLayerTest, RendersThePanelOffscreenCleanlyAndReproducibly) {
  Target target;
  ASSERT_NO_FATAL_FAILURE(makeTarget(*ctx_, target));
  auto readback = gpu::Buffer::create(*ctx_, uint64_t(kWidth) * kHeight * 4, gpu::MemoryKind::HostVisible,
                                      gpu::BufferUse::Transfer, "imgui readback");
  ASSERT_TRUE(readback.ok()) << readback.message();
  {
    auto layer = ImGuiLayer::create(*ctx_, target.pass, 0, 2, nullptr);
    ASSERT_TRUE(layer.ok()) << layer.message();
    EXPECT_FALSE(layer->wantsMouse());

    UiState state;
    state.stats = {16.7, 1000.0, 1.2, 4096};
    state.force = {2.0, 8.0, true};
    // Frame 1 measures the auto-sized overlay and hides it; frames 2 and 3 are the same frame.
    renderFrame(*ctx_, *layer, target, state, *readback);
    std::vector<std::byte> second = renderFrame(*ctx_, *layer, target, state, *readback);
    std::vector<std::byte> third = renderFrame(*ctx_, *layer, target, state, *readback);
    EXPECT_TRUE(second == third) << "the same inputs gave different pixels";

    // Something was drawn over the black clear: the panel covers a good part of the image.
    size_t lit = 0;
    for (size_t i = 0; i < second.size(); i += 4)
      if (second[i] != std::byte{0} || second[i + 1] != std::byte{0} || second[i + 2] != std::byte{0}) ++lit;
    EXPECT_GT(lit, size_t(kWidth) * kHeight / 10);

    // Without a frame open, the layer ends one cleanly when nothing is to be drawn.
    layer->newFrame(int(kWidth), int(kHeight), 0.0);
    layer->discardFrame();
  }
  ASSERT_TRUE(ctx_->waitIdle().ok());
}

}  // namespace
}  // namespace dentsim::ui
