// One-shot submission with a fenced timeout, compute pipelines with per-dispatch contract checks, timestamps.
//
// Contents
//   1. submitAndWait, Commands
//   2. ComputePipeline
//   3. TimestampPool
#include "gpu/compute.h"

#include <algorithm>

#include "gpu/vk_check.h"

namespace dentsim::gpu {

// ---- 1. submission -------------------------------------------------------------------------------

Status submitAndWait(Context& ctx, std::string_view what, const std::function<Status(Commands&)>& record) {
  ContextCore& core = ctx.core();
  const std::string label(what);
  core.collect();

  VkCommandBufferAllocateInfo cai{};
  cai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  cai.commandPool = core.command_pool;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  DS_VK_TRY(vkAllocateCommandBuffers(core.device, &cai, &cmd), "vkAllocateCommandBuffers for " + label);
  core.name(VK_OBJECT_TYPE_COMMAND_BUFFER, cmd, label);

  const uint64_t serial = ++core.issued_serial;
  core.pending.insert(serial);
  VkDevice device = core.device;
  VkCommandPool pool = core.command_pool;
  // From here on the command buffer and whatever Commands allocated are retired at `serial`, which
  // frees them as soon as that submission is known finished (or was never made).
  auto retire_cmd = [&] { core.retired.retire(serial, [device, pool, cmd] { vkFreeCommandBuffers(device, pool, 1, &cmd); }); };
  auto abandon = [&](Error e) -> Status {
    retire_cmd();
    core.pending.erase(serial);
    core.collect();
    return e;
  };

  {
    Commands cmds(ctx, cmd, serial);
    VkCommandBufferBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if (const VkResult r = vkBeginCommandBuffer(cmd, &begin); r != VK_SUCCESS)
      return abandon(detail::vkError("vkBeginCommandBuffer for " + label, r));
    Status recorded = record(cmds);
    const VkResult ended = vkEndCommandBuffer(cmd);
    if (!recorded) return abandon(recorded.error());
    if (ended != VK_SUCCESS) return abandon(detail::vkError("vkEndCommandBuffer for " + label, ended));
  }  // ~Commands retires its descriptor pools at `serial`

  VkFenceCreateInfo fci{};
  fci.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  VkFence fence = VK_NULL_HANDLE;
  if (const VkResult r = vkCreateFence(device, &fci, nullptr, &fence); r != VK_SUCCESS)
    return abandon(detail::vkError("vkCreateFence for " + label, r));
  core.name(VK_OBJECT_TYPE_FENCE, fence, label + " fence");

  VkSubmitInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  if (const VkResult r = vkQueueSubmit(core.queue, 1, &si, fence); r != VK_SUCCESS) {
    vkDestroyFence(device, fence, nullptr);
    return abandon(detail::vkError("vkQueueSubmit for " + label, r));
  }

  const VkResult waited = vkWaitForFences(device, 1, &fence, VK_TRUE, core.options.submit_timeout_ns);
  retire_cmd();
  if (waited == VK_TIMEOUT) {
    // The work may still finish; collect() polls this fence and frees what it used then.
    core.timed_out.push_back({serial, fence});
    return makeError("gpu", label + " did not finish within " +
                                std::to_string(core.options.submit_timeout_ns / 1'000'000) + " ms (GPU hang or too much work)");
  }
  if (waited != VK_SUCCESS) {
    core.timed_out.push_back({serial, fence});
    return detail::vkError("vkWaitForFences for " + label, waited);
  }
  vkDestroyFence(device, fence, nullptr);
  core.pending.erase(serial);
  core.collect();
  return Ok{};
}

void Commands::barrier() {
  VkMemoryBarrier mb{};
  mb.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                     VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                       0, 1, &mb, 0, nullptr, 0, nullptr);
}

Result<VkDescriptorSet> Commands::allocateSet(VkDescriptorSetLayout layout, uint32_t storage_buffers, std::string_view name) {
  ContextCore& core = ctx_->core();
  const uint32_t needed = std::max(storage_buffers, 1u);
  if (pools_.empty() || sets_left_ == 0 || descriptors_left_ < needed) {
    // Pools are per submission: enough for a run of split dispatches, replaced when full.
    constexpr uint32_t kSets = 32;
    const uint32_t descriptors = std::max(kSets * 8u, needed * 4u);
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, descriptors};
    VkDescriptorPoolCreateInfo dpci{};
    dpci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    dpci.maxSets = kSets;
    dpci.poolSizeCount = 1;
    dpci.pPoolSizes = &size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    DS_VK_TRY(vkCreateDescriptorPool(core.device, &dpci, nullptr, &pool), "vkCreateDescriptorPool");
    core.name(VK_OBJECT_TYPE_DESCRIPTOR_POOL, pool, "descriptor pool of submission " + std::to_string(serial_));
    pools_.push_back(pool);
    sets_left_ = kSets;
    descriptors_left_ = descriptors;
  }
  VkDescriptorSetAllocateInfo dsai{};
  dsai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  dsai.descriptorPool = pools_.back();
  dsai.descriptorSetCount = 1;
  dsai.pSetLayouts = &layout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  DS_VK_TRY(vkAllocateDescriptorSets(core.device, &dsai, &set), "vkAllocateDescriptorSets");
  core.name(VK_OBJECT_TYPE_DESCRIPTOR_SET, set, name);
  --sets_left_;
  descriptors_left_ -= needed;
  return set;
}

Commands::~Commands() {
  ContextCore& core = ctx_->core();
  VkDevice device = core.device;
  for (VkDescriptorPool pool : pools_)
    core.retired.retire(serial_, [device, pool] { vkDestroyDescriptorPool(device, pool, nullptr); });
}

// ---- 2. ComputePipeline -----------------------------------------------------------------------------

Result<ComputePipeline> ComputePipeline::create(Context& ctx, const PipelineDesc& desc) {
  ContextCore& core = ctx.core();
  const std::string where = "gpu: pipeline '" + desc.name + "'";
  auto reflected = reflectSpirv(desc.spirv);
  if (!reflected) return makeError(where, reflected.message());

  ComputePipeline p;
  p.core_ = ctx.sharedCore();
  p.name_ = desc.name;
  p.reflection_ = std::move(*reflected);
  p.storage_buffers_ = desc.storage_buffers;
  p.local_size_ = specializedLocalSize(p.reflection_, desc.spec_constants);

  // The shader's contract against the device and the caller, before any Vulkan object exists.
  const DeviceLimits& lim = core.limits;
  uint64_t invocations = 1;
  for (size_t i = 0; i < 3; ++i) {
    if (p.local_size_[i] == 0 || p.local_size_[i] > lim.max_group_size[i])
      return makeError(where, "local size " + std::to_string(p.local_size_[i]) + " on axis " + std::to_string(i) +
                                  " is outside this device's maxComputeWorkGroupSize of " + std::to_string(lim.max_group_size[i]));
    invocations *= p.local_size_[i];
  }
  if (invocations > lim.max_group_invocations)
    return makeError(where, std::to_string(invocations) + " invocations per group exceed maxComputeWorkGroupInvocations " +
                                std::to_string(lim.max_group_invocations));
  if (p.reflection_.push_constant_size > lim.max_push_constants_size)
    return makeError(where, "push constants of " + std::to_string(p.reflection_.push_constant_size) +
                                " B exceed maxPushConstantsSize " + std::to_string(lim.max_push_constants_size));
  // Kernels of one family share a binding list and each uses part of it (the optimizer drops the
  // rest), so a shader may use any subset of bindings 0..n-1 but nothing outside it.
  for (uint32_t b : p.reflection_.storage_bindings)
    if (b >= desc.storage_buffers)
      return makeError(where, "shader uses storage binding " + std::to_string(b) +
                                  " in set 0 but the pipeline binds only 0.." + std::to_string(desc.storage_buffers) +
                                  "-1");

  VkShaderModuleCreateInfo smci{};
  smci.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  smci.codeSize = desc.spirv.size_bytes();
  smci.pCode = desc.spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  DS_VK_TRY(vkCreateShaderModule(core.device, &smci, nullptr, &module), "vkCreateShaderModule for " + desc.name);
  core.name(VK_OBJECT_TYPE_SHADER_MODULE, module, desc.name + " module");
  // The module is only needed while the pipeline is built.
  struct ModuleGuard {
    VkDevice d;
    VkShaderModule m;
    ~ModuleGuard() { vkDestroyShaderModule(d, m, nullptr); }
  } guard{core.device, module};

  std::vector<VkDescriptorSetLayoutBinding> bindings(desc.storage_buffers);
  for (uint32_t i = 0; i < desc.storage_buffers; ++i) {
    bindings[i].binding = i;
    bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[i].descriptorCount = 1;
    bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo dslci{};
  dslci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  dslci.bindingCount = desc.storage_buffers;
  dslci.pBindings = bindings.data();
  DS_VK_TRY(vkCreateDescriptorSetLayout(core.device, &dslci, nullptr, &p.set_layout_), "vkCreateDescriptorSetLayout");
  core.name(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, p.set_layout_, desc.name + " set layout");

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, p.reflection_.push_constant_size};
  VkPipelineLayoutCreateInfo plci{};
  plci.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &p.set_layout_;
  plci.pushConstantRangeCount = p.reflection_.push_constant_size ? 1u : 0u;
  plci.pPushConstantRanges = &range;
  DS_VK_TRY(vkCreatePipelineLayout(core.device, &plci, nullptr, &p.layout_), "vkCreatePipelineLayout");
  core.name(VK_OBJECT_TYPE_PIPELINE_LAYOUT, p.layout_, desc.name + " layout");

  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> values;
  for (const SpecValue& s : desc.spec_constants) {
    entries.push_back({s.id, static_cast<uint32_t>(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
    values.push_back(s.value);
  }
  VkSpecializationInfo spec{};
  spec.mapEntryCount = static_cast<uint32_t>(entries.size());
  spec.pMapEntries = entries.data();
  spec.dataSize = values.size() * sizeof(uint32_t);
  spec.pData = values.data();

  VkComputePipelineCreateInfo cpci{};
  cpci.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cpci.stage.module = module;
  cpci.stage.pName = "main";
  cpci.stage.pSpecializationInfo = entries.empty() ? nullptr : &spec;
  cpci.layout = p.layout_;
  DS_VK_TRY(vkCreateComputePipelines(core.device, VK_NULL_HANDLE, 1, &cpci, nullptr, &p.pipeline_),
            "vkCreateComputePipelines for " + desc.name);
  core.name(VK_OBJECT_TYPE_PIPELINE, p.pipeline_, desc.name);
  return p;
}

uint64_t ComputePipeline::groupsFor(uint64_t invocations) const {
  const uint64_t x = local_size_[0];
  return (invocations + x - 1) / x;
}

std::vector<DispatchRange> ComputePipeline::split(uint64_t invocations, uint32_t max_groups) const {
  const uint32_t limit = core_->limits.max_group_count[0];
  const uint64_t per = max_groups == 0 ? limit : std::min(max_groups, limit);
  std::vector<DispatchRange> out;
  const uint64_t total_groups = groupsFor(invocations);
  for (uint64_t g = 0; g < total_groups; g += per) {
    DispatchRange r;
    r.groups = static_cast<uint32_t>(std::min(per, total_groups - g));
    r.first = g * local_size_[0];
    r.count = std::min<uint64_t>(uint64_t(r.groups) * local_size_[0], invocations - r.first);
    out.push_back(r);
  }
  return out;
}

Status ComputePipeline::dispatchRaw(Commands& cmds, std::span<Buffer* const> buffers, const void* params,
                                    size_t params_size, uint32_t groups) {
  const std::string where = "gpu: dispatch of '" + name_ + "'";
  // The C++/shader contract, checked every time: a struct edited on one side only is caught here.
  if (params_size != reflection_.push_constant_size)
    return makeError(where, "push constants are " + std::to_string(params_size) + " B in C++ but the shader's block is " +
                                std::to_string(reflection_.push_constant_size) + " B");
  if (buffers.size() != storage_buffers_)
    return makeError(where, std::to_string(buffers.size()) + " buffers given, the shader binds " + std::to_string(storage_buffers_));
  if (groups == 0) return makeError(where, "zero workgroups");
  if (groups > core_->limits.max_group_count[0])
    return makeError(where, std::to_string(groups) + " groups exceed maxComputeWorkGroupCount[0] " +
                                std::to_string(core_->limits.max_group_count[0]) + " (split the dispatch)");

  auto set = cmds.allocateSet(set_layout_, storage_buffers_, name_ + " set");
  if (!set) return set.error();
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (size_t i = 0; i < buffers.size(); ++i) {
    if (!buffers[i] || !buffers[i]->handle()) return makeError(where, "binding " + std::to_string(i) + " has no buffer");
    infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = *set;
    writes[i].dstBinding = static_cast<uint32_t>(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
    cmds.use(*buffers[i]);
  }
  vkUpdateDescriptorSets(core_->device, static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);

  VkCommandBuffer cmd = cmds.cmd();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &*set, 0, nullptr);
  if (params_size) vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, static_cast<uint32_t>(params_size), params);
  vkCmdDispatch(cmd, groups, 1, 1);
  cmds.barrier();
  last_use_ = std::max(last_use_, cmds.serial());
  return Ok{};
}

ComputePipeline::ComputePipeline(ComputePipeline&& other) noexcept { *this = std::move(other); }

ComputePipeline& ComputePipeline::operator=(ComputePipeline&& other) noexcept {
  if (this != &other) {
    release();
    core_ = std::move(other.core_);
    name_ = std::move(other.name_);
    reflection_ = std::move(other.reflection_);
    local_size_ = other.local_size_;
    storage_buffers_ = other.storage_buffers_;
    set_layout_ = std::exchange(other.set_layout_, VK_NULL_HANDLE);
    layout_ = std::exchange(other.layout_, VK_NULL_HANDLE);
    pipeline_ = std::exchange(other.pipeline_, VK_NULL_HANDLE);
    last_use_ = std::exchange(other.last_use_, 0);
  }
  return *this;
}

ComputePipeline::~ComputePipeline() { release(); }

void ComputePipeline::release() {
  if (!core_) return;
  VkDevice device = core_->device;
  VkDescriptorSetLayout set_layout = set_layout_;
  VkPipelineLayout layout = layout_;
  VkPipeline pipeline = pipeline_;
  core_->retired.retire(last_use_, [device, set_layout, layout, pipeline] {
    if (pipeline) vkDestroyPipeline(device, pipeline, nullptr);
    if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
    if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
  });
  core_->collect();
  set_layout_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  pipeline_ = VK_NULL_HANDLE;
  core_.reset();
}

// ---- 3. TimestampPool ----------------------------------------------------------------------------

bool TimestampPool::supported(const Context& ctx, std::string* why) {
  if (ctx.limits().timestamp_valid_bits == 0) {
    if (why) *why = "timestamps unsupported: the compute queue family has timestampValidBits == 0";
    return false;
  }
  if (ctx.limits().timestamp_period <= 0.0f) {
    if (why) *why = "timestamps unsupported: timestampPeriod is 0";
    return false;
  }
  return true;
}

Result<TimestampPool> TimestampPool::create(Context& ctx, uint32_t pairs, std::string name) {
  std::string why;
  if (!supported(ctx, &why)) return makeError("gpu", why);
  if (pairs == 0) return makeError("gpu", "timestamp pool '" + name + "' with no pairs");
  ContextCore& core = ctx.core();
  TimestampPool t;
  t.core_ = ctx.sharedCore();
  t.pairs_ = pairs;
  VkQueryPoolCreateInfo qpci{};
  qpci.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
  qpci.queryType = VK_QUERY_TYPE_TIMESTAMP;
  qpci.queryCount = 2 * pairs;
  DS_VK_TRY(vkCreateQueryPool(core.device, &qpci, nullptr, &t.pool_), "vkCreateQueryPool for " + name);
  core.name(VK_OBJECT_TYPE_QUERY_POOL, t.pool_, name);
  // Queries start unavailable only after a reset.
  if (core.features.host_query_reset) vkResetQueryPool(core.device, t.pool_, 0, 2 * pairs);
  return t;
}

void TimestampPool::begin(Commands& cmds, uint32_t pair) {
  if (pair >= pairs_) return;
  // Without host reset the queries are reset in the command buffer, before their first write.
  if (core_->features.host_query_reset)
    vkResetQueryPool(core_->device, pool_, 2 * pair, 2);
  else
    vkCmdResetQueryPool(cmds.cmd(), pool_, 2 * pair, 2);
  vkCmdWriteTimestamp(cmds.cmd(), VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool_, 2 * pair);
  last_use_ = std::max(last_use_, cmds.serial());
}

void TimestampPool::end(Commands& cmds, uint32_t pair) {
  if (pair >= pairs_) return;
  vkCmdWriteTimestamp(cmds.cmd(), VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, 2 * pair + 1);
  last_use_ = std::max(last_use_, cmds.serial());
}

Result<double> TimestampPool::elapsedNs(uint32_t pair) const {
  if (pair >= pairs_) return makeError("gpu", "timestamp pair " + std::to_string(pair) + " out of range");
  // Two values, each followed by its availability word.
  uint64_t data[4] = {};
  const VkResult r = vkGetQueryPoolResults(core_->device, pool_, 2 * pair, 2, sizeof data, data, 2 * sizeof(uint64_t),
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
  if (r != VK_SUCCESS && r != VK_NOT_READY) return detail::vkError("vkGetQueryPoolResults", r);
  if (data[1] == 0 || data[3] == 0) return makeError("gpu", "timestamps of pair " + std::to_string(pair) + " were not written");
  const uint32_t bits = core_->limits.timestamp_valid_bits;
  const uint64_t mask = bits >= 64 ? ~uint64_t(0) : ((uint64_t(1) << bits) - 1);
  const uint64_t ticks = ((data[2] & mask) - (data[0] & mask)) & mask;  // wraps correctly within valid bits
  return static_cast<double>(ticks) * static_cast<double>(core_->limits.timestamp_period);
}

TimestampPool::TimestampPool(TimestampPool&& other) noexcept { *this = std::move(other); }

TimestampPool& TimestampPool::operator=(TimestampPool&& other) noexcept {
  if (this != &other) {
    release();
    core_ = std::move(other.core_);
    pool_ = std::exchange(other.pool_, VK_NULL_HANDLE);
    pairs_ = std::exchange(other.pairs_, 0);
    last_use_ = std::exchange(other.last_use_, 0);
  }
  return *this;
}

TimestampPool::~TimestampPool() { release(); }

void TimestampPool::release() {
  if (!core_) return;
  if (pool_) {
    VkDevice device = core_->device;
    VkQueryPool pool = pool_;
    core_->retired.retire(last_use_, [device, pool] { vkDestroyQueryPool(device, pool, nullptr); });
    core_->collect();
  }
  pool_ = VK_NULL_HANDLE;
  core_.reset();
}

}  // namespace dentsim::gpu
