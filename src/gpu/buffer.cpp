// Buffer creation, host copies, staging copies for device-local memory, and retirement to the context.
#include "gpu/buffer.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "gpu/compute.h"
#include "gpu/vk_check.h"

namespace dentsim::gpu {

std::string formatBytes(uint64_t bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1024.0 && u < 4) {
    v /= 1024.0;
    ++u;
  }
  char text[32];
  if (u == 0 || v == static_cast<double>(static_cast<uint64_t>(v)))
    std::snprintf(text, sizeof text, "%llu %s", static_cast<unsigned long long>(v), units[u]);
  else
    std::snprintf(text, sizeof text, "%.1f %s", v, units[u]);
  return text;
}

Result<Buffer> Buffer::create(Context& ctx, uint64_t size, MemoryKind kind, BufferUse use, std::string name) {
  ContextCore& core = ctx.core();
  const std::string where = "gpu: buffer '" + name + "'";
  if (size == 0) return makeError(where, "size 0 (Vulkan buffers hold at least one byte)");
  const DeviceLimits& lim = core.limits;
  if ((use == BufferUse::Storage || use == BufferUse::Geometry) && size > lim.max_storage_buffer_range)
    return makeError(where, formatBytes(size) + " is over this device's maxStorageBufferRange of " +
                                formatBytes(lim.max_storage_buffer_range) + " for one storage binding");
  if (lim.max_memory_allocation_size && size > lim.max_memory_allocation_size)
    return makeError(where, formatBytes(size) + " is over this device's maxMemoryAllocationSize of " +
                                formatBytes(lim.max_memory_allocation_size));

  Buffer b;
  b.core_ = ctx.sharedCore();
  b.size_ = size;
  b.kind_ = kind;
  b.name_ = std::move(name);

  VkBufferCreateInfo bci{};
  bci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  bci.size = size;
  bci.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  if (use == BufferUse::Storage) bci.usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  if (use == BufferUse::Geometry)
    bci.usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT |
                 VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  DS_VK_TRY(vkCreateBuffer(core.device, &bci, nullptr, &b.buffer_), "vkCreateBuffer for " + b.name_);

  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(core.device, b.buffer_, &req);
  int type = -1;
  if (kind == MemoryKind::HostVisible) {
    // Cached memory makes readback fast; coherent spares explicit flushes.
    type = core.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                               VK_MEMORY_PROPERTY_HOST_CACHED_BIT, 0);
  } else {
    // Prefer memory the host cannot see: on a discrete GPU that is the fast VRAM heap.
    type = core.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    if (type < 0) type = core.findMemoryType(req.memoryTypeBits, 0, 0, 0);
  }
  if (type < 0) return makeError(where, "no memory type fits (host-visible coherent memory is required for staging)");

  VkMemoryAllocateInfo mai{};
  mai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = static_cast<uint32_t>(type);
  DS_VK_TRY(vkAllocateMemory(core.device, &mai, nullptr, &b.memory_),
            "vkAllocateMemory of " + formatBytes(req.size) + " for " + b.name_);
  DS_VK_TRY(vkBindBufferMemory(core.device, b.buffer_, b.memory_, 0), "vkBindBufferMemory for " + b.name_);
  if (kind == MemoryKind::HostVisible)
    DS_VK_TRY(vkMapMemory(core.device, b.memory_, 0, VK_WHOLE_SIZE, 0, &b.mapped_), "vkMapMemory for " + b.name_);

  core.name(VK_OBJECT_TYPE_BUFFER, b.buffer_, b.name_);
  core.name(VK_OBJECT_TYPE_DEVICE_MEMORY, b.memory_, b.name_ + " memory");
  return b;
}

Status Buffer::upload(Context& ctx, std::span<const std::byte> bytes, uint64_t offset) {
  if (offset > size_ || bytes.size() > size_ - offset)
    return makeError("gpu: buffer '" + name_ + "'", "upload of " + formatBytes(bytes.size()) + " at offset " +
                                                        std::to_string(offset) + " overruns its " + formatBytes(size_));
  if (bytes.empty()) return Ok{};
  if (mapped_) {
    std::memcpy(static_cast<std::byte*>(mapped_) + offset, bytes.data(), bytes.size());
    return Ok{};
  }
  auto staging = Buffer::create(ctx, bytes.size(), MemoryKind::HostVisible, BufferUse::Transfer, name_ + " upload staging");
  if (!staging) return staging.error();
  std::memcpy(staging->mapped(), bytes.data(), bytes.size());
  return submitAndWait(ctx, "upload to " + name_, [&](Commands& cmds) -> Status {
    VkBufferCopy region{0, offset, bytes.size()};
    vkCmdCopyBuffer(cmds.cmd(), staging->handle(), buffer_, 1, &region);
    cmds.use(*staging);
    cmds.use(*this);
    cmds.barrier();
    return Ok{};
  });
}

Status Buffer::download(Context& ctx, std::span<std::byte> out, uint64_t offset) {
  if (offset > size_ || out.size() > size_ - offset)
    return makeError("gpu: buffer '" + name_ + "'", "download of " + formatBytes(out.size()) + " at offset " +
                                                        std::to_string(offset) + " overruns its " + formatBytes(size_));
  if (out.empty()) return Ok{};
  if (mapped_) {
    std::memcpy(out.data(), static_cast<const std::byte*>(mapped_) + offset, out.size());
    return Ok{};
  }
  auto staging = Buffer::create(ctx, out.size(), MemoryKind::HostVisible, BufferUse::Transfer, name_ + " download staging");
  if (!staging) return staging.error();
  DS_TRY_STATUS(submitAndWait(ctx, "download from " + name_, [&](Commands& cmds) -> Status {
    VkBufferCopy region{offset, 0, out.size()};
    vkCmdCopyBuffer(cmds.cmd(), buffer_, staging->handle(), 1, &region);
    cmds.use(*staging);
    cmds.use(*this);
    cmds.barrier();
    return Ok{};
  }));
  std::memcpy(out.data(), staging->mapped(), out.size());
  return Ok{};
}

Status Buffer::clear(Context& ctx) {
  if (mapped_) {
    std::memset(mapped_, 0, size_);
    return Ok{};
  }
  return submitAndWait(ctx, "clear " + name_, [&](Commands& cmds) -> Status {
    vkCmdFillBuffer(cmds.cmd(), buffer_, 0, VK_WHOLE_SIZE, 0);
    cmds.use(*this);
    cmds.barrier();
    return Ok{};
  });
}

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    core_ = std::move(other.core_);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    kind_ = other.kind_;
    mapped_ = std::exchange(other.mapped_, nullptr);
    name_ = std::move(other.name_);
    last_use_ = std::exchange(other.last_use_, 0);
  }
  return *this;
}

Buffer::~Buffer() { release(); }

void Buffer::release() {
  if (!core_) return;
  if (buffer_ || memory_) {
    // The handles may still be read by a submission in flight; the retire list frees them after
    // that submission's fence.
    VkDevice device = core_->device;
    VkBuffer buffer = buffer_;
    VkDeviceMemory memory = memory_;
    core_->retired.retire(last_use_, [device, buffer, memory] {
      if (buffer) vkDestroyBuffer(device, buffer, nullptr);
      if (memory) vkFreeMemory(device, memory, nullptr);  // unmaps too
    });
    core_->collect();
  }
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  core_.reset();
}

Status GrowingBuffer::ensure(Context& ctx, uint64_t bytes) {
  bytes = std::max<uint64_t>(bytes, 16);
  if (buffer && buffer->size() >= bytes) return Ok{};
  buffer.reset();
  auto b = Buffer::create(ctx, bytes, kind, use, name);
  if (!b) return b.error();
  buffer.emplace(std::move(b).value());
  return Ok{};
}

}  // namespace dentsim::gpu
