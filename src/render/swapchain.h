// Swapchain: the window's presentable images, acquired and presented in step with dentsim's synchronous submissions.
//
// dentsim submits each frame with gpu::submitAndWait, so by the time it presents, the frame's work
// has finished on the host's watch. Acquisition therefore waits on a fence rather than a semaphore,
// and presentation waits on nothing; one frame is in flight, which keeps the mesher's slot pool
// (rewritten between frames) safe without further barriers.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/result.h"
#include "gpu/context.h"

namespace dentsim::render {

struct SwapchainOptions {
  bool vsync = true;  // FIFO; else MAILBOX or IMMEDIATE when offered (frame-rate measurements)
};

class Swapchain {
 public:
  // Takes ownership of `surface` (destroyed with the swapchain, or on error). Errors: the context's
  // queue cannot present to the surface, no usable format, a Vulkan failure.
  static Result<std::unique_ptr<Swapchain>> create(gpu::Context& ctx, VkSurfaceKHR surface, VkExtent2D wanted,
                                                   const SwapchainOptions& options);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  VkFormat format() const { return format_; }
  VkExtent2D extent() const { return extent_; }
  uint32_t imageCount() const { return uint32_t(images_.size()); }
  VkImage image(uint32_t i) const { return images_[i]; }
  VkImageView view(uint32_t i) const { return views_[i]; }
  VkPresentModeKHR presentMode() const { return present_mode_; }

  // The next image's index, ready to be drawn (waited for on the host); false when the swapchain
  // no longer matches the window and must be recreated.
  Result<bool> acquire(uint32_t* index);
  // Presents an image whose frame has finished; false when the swapchain must be recreated.
  Result<bool> present(uint32_t index);
  // A new swapchain for the window's current size (the device must be idle of its images).
  Status recreate(VkExtent2D wanted);

 private:
  Swapchain(gpu::Context& ctx, VkSurfaceKHR surface, const SwapchainOptions& options);
  Status build(VkExtent2D wanted);
  void releaseImages();

  std::shared_ptr<gpu::ContextCore> core_;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  SwapchainOptions options_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFence acquired_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{0, 0};
  VkPresentModeKHR present_mode_ = VK_PRESENT_MODE_FIFO_KHR;
  std::vector<VkImage> images_;
  std::vector<VkImageView> views_;
};

}  // namespace dentsim::render
