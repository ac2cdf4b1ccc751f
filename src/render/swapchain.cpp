// Swapchain creation (format, present mode, image count), fence-based acquisition, presentation, recreation.
#include "render/swapchain.h"

#include <algorithm>
#include <string>

namespace dentsim::render {
namespace {

Error vkFail(const char* call, VkResult r) { return makeError("swapchain", std::string(call) + " failed (VkResult " + std::to_string(int(r)) + ")"); }

// B8G8R8A8_UNORM first: the offscreen target's format, so that headless and windowed frames hold the
// same bytes; then its RGBA twin; then whatever the surface offers first.
VkSurfaceFormatKHR chooseFormat(const std::vector<VkSurfaceFormatKHR>& formats) {
  for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM})
    for (const VkSurfaceFormatKHR& f : formats)
      if (f.format == wanted && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
  return formats.front();
}

}  // namespace

Swapchain::Swapchain(gpu::Context& ctx, VkSurfaceKHR surface, const SwapchainOptions& options)
    : core_(ctx.sharedCore()), surface_(surface), options_(options) {}

Result<std::unique_ptr<Swapchain>> Swapchain::create(gpu::Context& ctx, VkSurfaceKHR surface, VkExtent2D wanted,
                                                     const SwapchainOptions& options) {
  std::unique_ptr<Swapchain> sc(new Swapchain(ctx, surface, options));
  const gpu::ContextCore& core = *sc->core_;
  VkBool32 can_present = VK_FALSE;
  if (VkResult r = vkGetPhysicalDeviceSurfaceSupportKHR(core.physical, core.queue_family, surface, &can_present); r != VK_SUCCESS)
    return vkFail("vkGetPhysicalDeviceSurfaceSupportKHR", r);
  if (!can_present)
    return makeError("swapchain", core.info.name + " cannot present to this window from its graphics queue");
  VkFenceCreateInfo fci{};
  fci.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  if (VkResult r = vkCreateFence(core.device, &fci, nullptr, &sc->acquired_); r != VK_SUCCESS) return vkFail("vkCreateFence", r);
  if (Status st = sc->build(wanted); !st) return st.error();
  return sc;
}

Status Swapchain::build(VkExtent2D wanted) {
  const gpu::ContextCore& core = *core_;
  VkSurfaceCapabilitiesKHR caps{};
  if (VkResult r = vkGetPhysicalDeviceSurfaceCapabilitiesKHR(core.physical, surface_, &caps); r != VK_SUCCESS)
    return vkFail("vkGetPhysicalDeviceSurfaceCapabilitiesKHR", r);
  uint32_t n = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(core.physical, surface_, &n, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(n);
  vkGetPhysicalDeviceSurfaceFormatsKHR(core.physical, surface_, &n, formats.data());
  if (formats.empty()) return makeError("swapchain", "the window's surface offers no image format");
  const VkSurfaceFormatKHR format = chooseFormat(formats);

  vkGetPhysicalDeviceSurfacePresentModesKHR(core.physical, surface_, &n, nullptr);
  std::vector<VkPresentModeKHR> modes(n);
  vkGetPhysicalDeviceSurfacePresentModesKHR(core.physical, surface_, &n, modes.data());
  present_mode_ = VK_PRESENT_MODE_FIFO_KHR;  // always offered
  if (!options_.vsync) {
    for (VkPresentModeKHR m : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
      if (std::find(modes.begin(), modes.end(), m) != modes.end()) {
        present_mode_ = m;
        break;
      }
  }

  VkExtent2D extent = caps.currentExtent;
  if (extent.width == UINT32_MAX) {  // the surface takes the swapchain's size
    extent.width = std::clamp(wanted.width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height = std::clamp(wanted.height, caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  if (extent.width == 0 || extent.height == 0) return makeError("swapchain", "the window has no area (minimised)");
  uint32_t images = std::max(caps.minImageCount + 1, 2u);
  if (caps.maxImageCount > 0) images = std::min(images, caps.maxImageCount);
  // Screenshots copy the presented image back, so it must be a transfer source.
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT))
    return makeError("swapchain", "the window's images cannot be read back (no TRANSFER_SRC usage)");

  VkSwapchainCreateInfoKHR sci{};
  sci.sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR;
  sci.surface = surface_;
  sci.minImageCount = images;
  sci.imageFormat = format.format;
  sci.imageColorSpace = format.colorSpace;
  sci.imageExtent = extent;
  sci.imageArrayLayers = 1;
  sci.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  sci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  sci.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR) ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                                                                                         : caps.currentTransform;
  sci.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                           ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                           : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
  sci.presentMode = present_mode_;
  sci.clipped = VK_TRUE;
  sci.oldSwapchain = swapchain_;
  VkSwapchainKHR created = VK_NULL_HANDLE;
  if (VkResult r = vkCreateSwapchainKHR(core.device, &sci, nullptr, &created); r != VK_SUCCESS) return vkFail("vkCreateSwapchainKHR", r);
  releaseImages();
  swapchain_ = created;
  format_ = format.format;
  extent_ = extent;

  vkGetSwapchainImagesKHR(core.device, swapchain_, &n, nullptr);
  images_.resize(n);
  vkGetSwapchainImagesKHR(core.device, swapchain_, &n, images_.data());
  for (uint32_t i = 0; i < n; ++i) {
    VkImageViewCreateInfo vci{};
    vci.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
    vci.image = images_[i];
    vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vci.format = format_;
    vci.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView view = VK_NULL_HANDLE;
    if (VkResult r = vkCreateImageView(core.device, &vci, nullptr, &view); r != VK_SUCCESS) return vkFail("vkCreateImageView", r);
    views_.push_back(view);
    core.name(VK_OBJECT_TYPE_IMAGE_VIEW, view, "swapchain image view " + std::to_string(i));
  }
  return Ok{};
}

void Swapchain::releaseImages() {
  for (VkImageView v : views_) vkDestroyImageView(core_->device, v, nullptr);
  views_.clear();
  images_.clear();
  if (swapchain_) vkDestroySwapchainKHR(core_->device, swapchain_, nullptr);
  swapchain_ = VK_NULL_HANDLE;
}

Swapchain::~Swapchain() {
  if (!core_) return;
  vkDeviceWaitIdle(core_->device);
  releaseImages();
  if (acquired_) vkDestroyFence(core_->device, acquired_, nullptr);
  if (surface_) vkDestroySurfaceKHR(core_->instance, surface_, nullptr);
}

Result<bool> Swapchain::acquire(uint32_t* index) {
  const VkDevice device = core_->device;
  const uint64_t timeout = core_->options.submit_timeout_ns;
  const VkResult r = vkAcquireNextImageKHR(device, swapchain_, timeout, VK_NULL_HANDLE, acquired_, index);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) return false;
  if (r != VK_SUCCESS && r != VK_SUBOPTIMAL_KHR) return vkFail("vkAcquireNextImageKHR", r);
  const VkResult w = vkWaitForFences(device, 1, &acquired_, VK_TRUE, timeout);
  vkResetFences(device, 1, &acquired_);
  if (w != VK_SUCCESS) return vkFail("vkWaitForFences (image acquisition)", w);
  return true;
}

Result<bool> Swapchain::present(uint32_t index) {
  VkPresentInfoKHR pi{};
  pi.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR;
  pi.swapchainCount = 1;
  pi.pSwapchains = &swapchain_;
  pi.pImageIndices = &index;
  const VkResult r = vkQueuePresentKHR(core_->queue, &pi);
  if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) return false;
  if (r != VK_SUCCESS) return vkFail("vkQueuePresentKHR", r);
  return true;
}

Status Swapchain::recreate(VkExtent2D wanted) {
  vkDeviceWaitIdle(core_->device);
  return build(wanted);
}

}  // namespace dentsim::render
