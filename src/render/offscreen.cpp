// Offscreen targets, image read-back through a staging buffer, and the headless one-frame render.
#include "render/offscreen.h"

#include <cstring>
#include <string>

#include "gpu/buffer.h"
#include "gpu/compute.h"

namespace dentsim::render {

Result<OffscreenTarget> OffscreenTarget::create(gpu::Context& ctx, uint32_t width, uint32_t height, VkFormat format) {
  if (width == 0 || height == 0) return makeError("render", "offscreen target of zero size");
  auto img = GpuImage::create(ctx, {width, height}, format,
                              VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              VK_IMAGE_ASPECT_COLOR_BIT, "offscreen colour");
  if (!img) return img.error();
  OffscreenTarget t;
  t.colour_.emplace(std::move(*img));
  return t;
}

RenderImage OffscreenTarget::image() const { return {colour_->image(), colour_->view(), colour_->format(), colour_->extent()}; }

Result<RgbImage> OffscreenTarget::readback(gpu::Context& ctx) {
  return readImage(ctx, image(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

Result<RgbImage> readImage(gpu::Context& ctx, const RenderImage& image, VkImageLayout layout) {
  bool bgra = false;
  switch (image.format) {
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_SRGB: bgra = true; break;
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB: break;
    default: return makeError("render", "read-back of colour format " + std::to_string(int(image.format)) + " is not supported");
  }
  const uint32_t w = image.extent.width, h = image.extent.height;
  auto staging = gpu::Buffer::create(ctx, uint64_t(w) * h * 4, gpu::MemoryKind::HostVisible, gpu::BufferUse::Transfer,
                                     "image read-back");
  if (!staging) return staging.error();
  const Status done = gpu::submitAndWait(ctx, "image read-back", [&](gpu::Commands& cmds) -> Status {
    VkImageMemoryBarrier b{};
    b.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image.image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    const bool transition = layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    // Whatever wrote the image last (a render pass) finishes before the copy reads it.
    b.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    b.oldLayout = layout;
    b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    vkCmdPipelineBarrier(cmds.cmd(), VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                         nullptr, 0, nullptr, transition ? 1u : 0u, &b);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {w, h, 1};
    vkCmdCopyImageToBuffer(cmds.cmd(), image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging->handle(), 1, &region);
    if (transition) {
      b.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
      b.dstAccessMask = 0;
      b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
      b.newLayout = layout;
      vkCmdPipelineBarrier(cmds.cmd(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, nullptr,
                           0, nullptr, 1, &b);
    }
    VkMemoryBarrier host{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(cmds.cmd(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &host, 0, nullptr,
                         0, nullptr);
    cmds.use(*staging);
    return Ok{};
  });
  if (!done) return done.error();

  RgbImage out;
  out.width = int(w);
  out.height = int(h);
  out.rgb.resize(size_t(w) * h * 3);
  const auto* src = static_cast<const uint8_t*>(staging->mapped());
  for (size_t p = 0; p < size_t(w) * h; ++p) {
    out.rgb[3 * p + 0] = src[4 * p + (bgra ? 2 : 0)];
    out.rgb[3 * p + 1] = src[4 * p + 1];
    out.rgb[3 * p + 2] = src[4 * p + (bgra ? 0 : 2)];
  }
  return out;
}

Result<RgbImage> renderOffscreen(gpu::Context& ctx, SceneRenderer& renderer, const ToothSurfaces& tooth,
                                 const FrameState& frame, uint32_t width, uint32_t height) {
  if (renderer.finalLayout() != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
    return makeError("render", "renderOffscreen needs a renderer whose final layout is TRANSFER_SRC_OPTIMAL");
  auto target = OffscreenTarget::create(ctx, width, height, renderer.colourFormat());
  if (!target) return target.error();
  const RenderImage image = target->image();
  Status drawn = gpu::submitAndWait(ctx, "offscreen frame", [&](gpu::Commands& cmds) -> Status {
    renderer.markSubmitted(cmds.serial());
    return renderer.recordFrame(cmds.cmd(), image, tooth, frame);
  });
  Result<RgbImage> pixels = drawn ? target->readback(ctx) : Result<RgbImage>(drawn.error());
  // The target's view dies with it; a later image may reuse the handle.
  renderer.forgetTarget(image.view);
  return pixels;
}

}  // namespace dentsim::render
