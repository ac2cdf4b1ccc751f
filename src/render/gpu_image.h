// GpuImage: a named, move-only 2-D Vulkan image with its memory and view, retired through the context like buffers.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <vulkan/vulkan.h>

#include "core/result.h"
#include "gpu/context.h"

namespace dentsim::render {

class GpuImage {
 public:
  // A device-local width x height image of `format` for `usage`, with one view of `aspect`.
  // Errors: no memory type fits, a Vulkan failure.
  static Result<GpuImage> create(gpu::Context& ctx, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                                 VkImageAspectFlags aspect, std::string name);

  VkImage image() const { return image_; }
  VkImageView view() const { return view_; }
  VkFormat format() const { return format_; }
  VkExtent2D extent() const { return extent_; }

  // Records that submission `serial` uses the image, so its deletion waits for that submission.
  void markUsed(uint64_t serial) { last_use_ = serial > last_use_ ? serial : last_use_; }

  GpuImage(GpuImage&& other) noexcept;
  GpuImage& operator=(GpuImage&& other) noexcept;
  GpuImage(const GpuImage&) = delete;
  GpuImage& operator=(const GpuImage&) = delete;
  ~GpuImage();  // hands the handles to the context's retire list

 private:
  GpuImage() = default;
  void release();

  std::shared_ptr<gpu::ContextCore> core_;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{0, 0};
  uint64_t last_use_ = 0;
};

}  // namespace dentsim::render
