// Offscreen frames: a colour image to render into without a window, read-back of any colour image to RGB, and a one-call headless render.
#pragma once

#include <cstdint>
#include <optional>

#include <vulkan/vulkan.h>

#include "core/result.h"
#include "gpu/context.h"
#include "io/png_file.h"
#include "render/gpu_image.h"
#include "render/scene_renderer.h"
#include "render/tooth_surfaces.h"

namespace dentsim::render {

// The usual swapchain format, so that headless frames equal windowed ones byte for byte.
inline constexpr VkFormat kDefaultColourFormat = VK_FORMAT_B8G8R8A8_UNORM;

class OffscreenTarget {
 public:
  // A width x height colour image (COLOR_ATTACHMENT and TRANSFER_SRC). Errors: a zero size, a Vulkan failure.
  static Result<OffscreenTarget> create(gpu::Context& ctx, uint32_t width, uint32_t height,
                                        VkFormat format = kDefaultColourFormat);

  RenderImage image() const;
  // The pixels after a frame of a renderer whose final layout is TRANSFER_SRC_OPTIMAL.
  Result<RgbImage> readback(gpu::Context& ctx);

 private:
  OffscreenTarget() = default;
  std::optional<GpuImage> colour_;
};

// Copies `image` (8-bit RGBA or BGRA, UNORM or SRGB, with TRANSFER_SRC usage), now in `layout`
// (TRANSFER_SRC_OPTIMAL, PRESENT_SRC_KHR or SHADER_READ_ONLY_OPTIMAL, and left so), to RGB with row 0
// at the top; alpha is dropped. Submits and waits. Errors: another format, a Vulkan failure.
Result<RgbImage> readImage(gpu::Context& ctx, const RenderImage& image, VkImageLayout layout);

// Records one frame of `renderer` (final layout TRANSFER_SRC_OPTIMAL) into a fresh width x height
// image of its colour format, submits, waits and reads it back.
Result<RgbImage> renderOffscreen(gpu::Context& ctx, SceneRenderer& renderer, const ToothSurfaces& tooth,
                                 const FrameState& frame, uint32_t width, uint32_t height);

}  // namespace dentsim::render
