// GpuImage: creation with device-local memory, and retirement of the image, view and memory together.
#include "render/gpu_image.h"

#include <utility>

#include "gpu/vk_check.h"

namespace dentsim::render {

Result<GpuImage> GpuImage::create(gpu::Context& ctx, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                                  VkImageAspectFlags aspect, std::string name) {
  gpu::ContextCore& core = ctx.core();
  GpuImage img;
  img.core_ = ctx.sharedCore();
  img.format_ = format;
  img.extent_ = extent;

  VkImageCreateInfo ici{};
  ici.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
  ici.imageType = VK_IMAGE_TYPE_2D;
  ici.format = format;
  ici.extent = {extent.width, extent.height, 1};
  ici.mipLevels = 1;
  ici.arrayLayers = 1;
  ici.samples = VK_SAMPLE_COUNT_1_BIT;
  ici.tiling = VK_IMAGE_TILING_OPTIMAL;
  ici.usage = usage;
  ici.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  DS_VK_TRY(vkCreateImage(core.device, &ici, nullptr, &img.image_), "vkCreateImage for " + name);

  VkMemoryRequirements req{};
  vkGetImageMemoryRequirements(core.device, img.image_, &req);
  int type = core.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, 0);
  if (type < 0) type = core.findMemoryType(req.memoryTypeBits, 0, 0, 0);
  if (type < 0) return makeError("render", "no memory type fits the image " + name);
  VkMemoryAllocateInfo mai{};
  mai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = uint32_t(type);
  DS_VK_TRY(vkAllocateMemory(core.device, &mai, nullptr, &img.memory_), "vkAllocateMemory for " + name);
  DS_VK_TRY(vkBindImageMemory(core.device, img.image_, img.memory_, 0), "vkBindImageMemory for " + name);

  VkImageViewCreateInfo vci{};
  vci.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
  vci.image = img.image_;
  vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vci.format = format;
  vci.subresourceRange = {aspect, 0, 1, 0, 1};
  DS_VK_TRY(vkCreateImageView(core.device, &vci, nullptr, &img.view_), "vkCreateImageView for " + name);

  core.name(VK_OBJECT_TYPE_IMAGE, img.image_, name);
  core.name(VK_OBJECT_TYPE_IMAGE_VIEW, img.view_, name + " view");
  core.name(VK_OBJECT_TYPE_DEVICE_MEMORY, img.memory_, name + " memory");
  return img;
}

GpuImage::GpuImage(GpuImage&& other) noexcept { *this = std::move(other); }

GpuImage& GpuImage::operator=(GpuImage&& other) noexcept {
  if (this != &other) {
    release();
    core_ = std::move(other.core_);
    image_ = std::exchange(other.image_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    view_ = std::exchange(other.view_, VK_NULL_HANDLE);
    format_ = other.format_;
    extent_ = other.extent_;
    last_use_ = std::exchange(other.last_use_, 0);
  }
  return *this;
}

GpuImage::~GpuImage() { release(); }

void GpuImage::release() {
  if (!core_) return;
  if (image_ || memory_ || view_) {
    VkDevice device = core_->device;
    VkImage image = image_;
    VkDeviceMemory memory = memory_;
    VkImageView view = view_;
    core_->retired.retire(last_use_, [device, image, memory, view] {
      if (view) vkDestroyImageView(device, view, nullptr);
      if (image) vkDestroyImage(device, image, nullptr);
      if (memory) vkFreeMemory(device, memory, nullptr);
    });
    core_->collect();
  }
  image_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  view_ = VK_NULL_HANDLE;
  core_.reset();
}

}  // namespace dentsim::render
