// Compute pipelines from embedded SPIR-V, one-shot command submission with a timeout, and timestamp queries.
//
// Contents
//   1. submitAndWait and Commands: record, submit, wait on a fence (a timeout is an Error)
//   2. ComputePipeline: checks the push-constant contract at every dispatch, groups from local size
//   3. TimestampPool: elapsed GPU time around a dispatch [ns]
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/result.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/spirv_reflect.h"

namespace dentsim::gpu {

class Commands;

// ---- 1. submission ----------------------------------------------------------------------------------

// Records one command buffer with `record`, submits it to the compute queue and waits for its fence
// at most the context's submit timeout. An error from `record` ends the recording unsubmitted; a
// timeout returns an Error (the handles stay retired until the work is seen to finish).
Status submitAndWait(Context& ctx, std::string_view what, const std::function<Status(Commands&)>& record);

// The command buffer being recorded by submitAndWait, with what this submission needs.
class Commands {
 public:
  VkCommandBuffer cmd() const { return cmd_; }
  uint64_t serial() const { return serial_; }  // this submission's number
  Context& context() const { return *ctx_; }

  // Marks `b` as used by this submission: its deletion waits for the fence.
  void use(Buffer& b) { b.markUsed(serial_); }
  // Makes shader and transfer writes so far visible to later shader, transfer and host reads.
  void barrier();
  // A descriptor set for `layout` with `storage_buffers` storage-buffer descriptors, freed with the submission.
  Result<VkDescriptorSet> allocateSet(VkDescriptorSetLayout layout, uint32_t storage_buffers, std::string_view name);

  Commands(const Commands&) = delete;
  Commands& operator=(const Commands&) = delete;
  ~Commands();

 private:
  friend Status submitAndWait(Context&, std::string_view, const std::function<Status(Commands&)>&);
  Commands(Context& ctx, VkCommandBuffer cmd, uint64_t serial) : ctx_(&ctx), cmd_(cmd), serial_(serial) {}

  Context* ctx_;
  VkCommandBuffer cmd_;
  uint64_t serial_;
  std::vector<VkDescriptorPool> pools_;
  uint32_t sets_left_ = 0;         // in pools_.back()
  uint32_t descriptors_left_ = 0;  // in pools_.back()
};

// ---- 2. pipelines ------------------------------------------------------------------------------------

struct PipelineDesc {
  std::string name;                          // debug name of the pipeline and its layout
  std::span<const uint32_t> spirv;           // the module (entry point "main")
  uint32_t storage_buffers = 0;              // set 0, bindings 0 .. storage_buffers-1
  std::vector<SpecValue> spec_constants;    // shader variants (constant_id, 32-bit value)
};

// One contiguous part of a 1-D dispatch: invocations [first, first + count), as `groups` groups.
struct DispatchRange {
  uint64_t first = 0;   // first invocation, a multiple of the local size
  uint64_t count = 0;   // invocations in this part
  uint32_t groups = 0;  // workgroups to dispatch
};

class ComputePipeline {
 public:
  // Reflects the module, checks it against the device limits (local size, push-constant size) and
  // against `desc` (binding count), then creates the pipeline.
  static Result<ComputePipeline> create(Context& ctx, const PipelineDesc& desc);

  const ShaderReflection& reflection() const { return reflection_; }
  std::array<uint32_t, 3> localSize() const { return local_size_; }  // after specialization [invocations]
  uint32_t pushConstantSize() const { return reflection_.push_constant_size; }  // [B]
  const std::string& name() const { return name_; }

  // Workgroups that cover `invocations` along x with this shader's local size.
  uint64_t groupsFor(uint64_t invocations) const;
  // Splits `invocations` into dispatches of at most `max_groups` groups each (0: the device's
  // maxComputeWorkGroupCount[0]); each part starts at a multiple of the local size.
  std::vector<DispatchRange> split(uint64_t invocations, uint32_t max_groups = 0) const;

  // Binds `buffers` to bindings 0..n-1, pushes `params`, dispatches `groups` x 1 x 1 and adds a
  // barrier. Refused with an Error when sizeof(Params) differs from the shader's push-constant
  // block, when the buffer count differs, or when `groups` exceeds the device limit.
  template <class Params>
  Status dispatch(Commands& cmds, std::span<Buffer* const> buffers, const Params& params, uint32_t groups) {
    static_assert(std::is_trivially_copyable_v<Params>, "push constants are copied bytewise");
    return dispatchRaw(cmds, buffers, &params, sizeof(Params), groups);
  }
  Status dispatchRaw(Commands& cmds, std::span<Buffer* const> buffers, const void* params, size_t params_size,
                     uint32_t groups);

  ComputePipeline(ComputePipeline&& other) noexcept;
  ComputePipeline& operator=(ComputePipeline&& other) noexcept;
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;
  ~ComputePipeline();

 private:
  ComputePipeline() = default;
  void release();

  std::shared_ptr<ContextCore> core_;
  std::string name_;
  ShaderReflection reflection_;
  std::array<uint32_t, 3> local_size_{1, 1, 1};
  uint32_t storage_buffers_ = 0;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  uint64_t last_use_ = 0;
};

// ---- 3. timestamps -------------------------------------------------------------------------------

class TimestampPool {
 public:
  // True when the compute queue writes timestamps (timestampValidBits > 0); else `why` says so.
  static bool supported(const Context& ctx, std::string* why = nullptr);
  // A pool of `pairs` begin/end pairs. Error "timestamps unsupported: ..." when !supported().
  static Result<TimestampPool> create(Context& ctx, uint32_t pairs, std::string name);

  // Records the begin (before the following commands) and end (after them) of pair `pair`.
  void begin(Commands& cmds, uint32_t pair);
  void end(Commands& cmds, uint32_t pair);
  // Time between begin and end of `pair` after its submission finished [ns]; an Error if the
  // queries were never written.
  Result<double> elapsedNs(uint32_t pair) const;

  TimestampPool(TimestampPool&& other) noexcept;
  TimestampPool& operator=(TimestampPool&& other) noexcept;
  TimestampPool(const TimestampPool&) = delete;
  TimestampPool& operator=(const TimestampPool&) = delete;
  ~TimestampPool();

 private:
  TimestampPool() = default;
  void release();

  std::shared_ptr<ContextCore> core_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t pairs_ = 0;
  uint64_t last_use_ = 0;
};

}  // namespace dentsim::gpu
