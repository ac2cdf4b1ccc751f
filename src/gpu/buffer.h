// Buffer: a named, move-only Vulkan buffer with its memory, host-visible or device-local with staging copies.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include <vulkan/vulkan.h>

#include "core/result.h"
#include "gpu/context.h"

namespace dentsim::gpu {

enum class MemoryKind {
  HostVisible,  // mapped, coherent: upload and readback with memcpy
  DeviceLocal,  // GPU memory: upload and download go through a staging buffer and a copy submission
};

// What the buffer is bound as. Storage buffers are refused above maxStorageBufferRange.
enum class BufferUse {
  Storage,   // shader storage buffer (also a copy source and target)
  Transfer,  // staging only
  Geometry,  // storage written by compute and read by draws: also vertex, index and indirect buffer
};

class Buffer {
 public:
  // A buffer of `size` bytes (> 0). Errors: a storage buffer over maxStorageBufferRange or
  // maxMemoryAllocationSize, no suitable memory type, allocation failure.
  static Result<Buffer> create(Context& ctx, uint64_t size, MemoryKind kind, BufferUse use, std::string name);

  // Writes `bytes` at `offset` [B]: a memcpy when host-visible, else a staging copy and a wait.
  Status upload(Context& ctx, std::span<const std::byte> bytes, uint64_t offset = 0);
  // Reads out.size() bytes from `offset` [B] into `out`, the same two ways.
  Status download(Context& ctx, std::span<std::byte> out, uint64_t offset = 0);
  // Sets every byte to zero (host-visible: memset; device-local: vkCmdFillBuffer).
  Status clear(Context& ctx);

  VkBuffer handle() const { return buffer_; }
  uint64_t size() const { return size_; }  // [B]
  MemoryKind kind() const { return kind_; }
  const std::string& name() const { return name_; }
  void* mapped() const { return mapped_; }  // null unless host-visible

  // Records that submission `serial` reads or writes this buffer, so deletion waits for it.
  void markUsed(uint64_t serial) { last_use_ = serial > last_use_ ? serial : last_use_; }
  uint64_t lastUse() const { return last_use_; }

  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer();  // hands the handles to the context's retire list

 private:
  Buffer() = default;
  void release();

  std::shared_ptr<ContextCore> core_;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  uint64_t size_ = 0;
  MemoryKind kind_ = MemoryKind::HostVisible;
  void* mapped_ = nullptr;
  std::string name_;
  uint64_t last_use_ = 0;  // serial of the last submission that used it
};

// A buffer that grows (never shrinks) to the largest size asked of it, keeping nothing across a
// regrowth: for scratch arrays whose size changes from call to call.
struct GrowingBuffer {
  std::optional<Buffer> buffer;
  MemoryKind kind = MemoryKind::DeviceLocal;
  std::string name;
  BufferUse use = BufferUse::Storage;

  // At least `bytes` (and 16) bytes; a new, empty buffer when the old one is too small.
  Status ensure(Context& ctx, uint64_t bytes);
};

// "128 MiB", "3.5 KiB", "17 B": sizes in error messages and reports.
std::string formatBytes(uint64_t bytes);

}  // namespace dentsim::gpu
