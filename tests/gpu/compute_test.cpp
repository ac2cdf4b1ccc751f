// Tests of src/gpu/compute.cpp: group counts from the local size, the push-constant check, limits, timeouts, timestamps.
#include <gtest/gtest.h>

#include <array>
#include <cstring>

#include "dentsim_compute_spirv_spirv.h"
#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "gpu/material_counts.h"
#include "gpu_fixture.h"
#include "volume/brick_layout.h"

namespace dentsim::gpu::test {
namespace {

PipelineDesc countsDesc() {
  return PipelineDesc{"material_counts test", {material_counts_comp_spv, material_counts_comp_spv_words}, 4, {}};
}

// Four small buffers, enough to bind the counts kernel.
struct CountBindings {
  std::vector<Buffer> buffers;
  std::array<Buffer*, 4> ptrs{};
};
CountBindings makeBindings(Context& ctx) {
  CountBindings b;
  for (int i = 0; i < 4; ++i) {
    auto buf = Buffer::create(ctx, 256, MemoryKind::HostVisible, BufferUse::Storage, "binding " + std::to_string(i));
    EXPECT_TRUE(buf) << buf.message();
    b.buffers.push_back(std::move(*buf));
    std::memset(b.buffers.back().mapped(), 0, 256);
  }
  for (size_t i = 0; i < 4; ++i) b.ptrs[i] = &b.buffers[i];
  return b;
}

}  // namespace

using ComputeTest = GpuTest;

TEST_F(ComputeTest, GroupCountsComeFromTheShadersLocalSize) {
  auto p = ComputePipeline::create(ctx(), countsDesc());
  ASSERT_TRUE(p) << p.message();
  EXPECT_EQ(p->localSize(), (std::array<uint32_t, 3>{DS_COUNT_GROUP_SIZE, 1, 1}));
  EXPECT_EQ(p->pushConstantSize(), sizeof(layout::MaterialCountParams));
  EXPECT_EQ(p->groupsFor(0), 0u);
  EXPECT_EQ(p->groupsFor(1), 1u);
  EXPECT_EQ(p->groupsFor(DS_COUNT_GROUP_SIZE), 1u);
  EXPECT_EQ(p->groupsFor(DS_COUNT_GROUP_SIZE + 1), 2u);

  // 1000 invocations in parts of at most 4 groups: 16 groups in 4 parts, each starting on a group.
  const auto parts = p->split(1000, 4);
  ASSERT_EQ(parts.size(), 4u);
  uint64_t covered = 0;
  for (const DispatchRange& r : parts) {
    EXPECT_EQ(r.first, covered);
    EXPECT_EQ(r.first % DS_COUNT_GROUP_SIZE, 0u);
    EXPECT_LE(r.groups, 4u);
    EXPECT_EQ(r.groups, p->groupsFor(r.count));
    covered += r.count;
  }
  EXPECT_EQ(covered, 1000u);
  // Without an explicit cap the device limit applies: one part for a small count.
  EXPECT_EQ(p->split(1000).size(), 1u);
}

TEST_F(ComputeTest, WrongSizePushConstantsAreRefusedAndNothingIsSubmitted) {
  auto p = ComputePipeline::create(ctx(), countsDesc());
  ASSERT_TRUE(p) << p.message();
  auto b = makeBindings(ctx());
  struct TooSmall {
    layout::GridInfo grid;
    uint32_t firstBrick, brickLimit, pad0;  // one word short of MaterialCountParams
  };
  struct TooBig {
    layout::MaterialCountParams params;
    uint32_t extra;
  };
  bool recorded_after_refusal = false;
  const Status small = submitAndWait(ctx(), "wrong push constants", [&](Commands& cmds) -> Status {
    auto s = p->dispatch(cmds, b.ptrs, TooSmall{}, 1);
    if (!s) return s;
    recorded_after_refusal = true;
    return Ok{};
  });
  ASSERT_FALSE(small);
  EXPECT_FALSE(recorded_after_refusal);
  EXPECT_NE(small.message().find("push constants are 28 B"), std::string::npos) << small.message();
  EXPECT_NE(small.message().find("32 B"), std::string::npos) << small.message();

  const Status big = submitAndWait(ctx(), "wrong push constants", [&](Commands& cmds) {
    return p->dispatch(cmds, b.ptrs, TooBig{}, 1);
  });
  ASSERT_FALSE(big);
  EXPECT_NE(big.message().find("36 B"), std::string::npos) << big.message();

  // The right struct goes through.
  layout::MaterialCountParams ok{};
  ok.grid = layout::GridInfo{3, 1, 1, 1};
  ok.brickLimit = 0;  // counts nothing, so the zeroed tables are never indexed
  EXPECT_TRUE(submitAndWait(ctx(), "right push constants", [&](Commands& cmds) { return p->dispatch(cmds, b.ptrs, ok, 1); }));
}

TEST_F(ComputeTest, WrongBindingsAndGroupCountsOverTheLimitAreRefused) {
  auto p = ComputePipeline::create(ctx(), countsDesc());
  ASSERT_TRUE(p) << p.message();
  auto b = makeBindings(ctx());
  layout::MaterialCountParams params{};
  const Status three = submitAndWait(ctx(), "three buffers", [&](Commands& cmds) {
    return p->dispatch(cmds, std::span<Buffer* const>(b.ptrs).first(3), params, 1);
  });
  ASSERT_FALSE(three);
  EXPECT_NE(three.message().find("3 buffers given"), std::string::npos) << three.message();

  const uint32_t limit = ctx().limits().max_group_count[0];
  ASSERT_LT(limit, UINT32_MAX);
  const Status over = submitAndWait(ctx(), "too many groups", [&](Commands& cmds) {
    return p->dispatch(cmds, b.ptrs, params, limit + 1);
  });
  ASSERT_FALSE(over);
  EXPECT_NE(over.message().find("maxComputeWorkGroupCount"), std::string::npos) << over.message();

  // A pipeline that binds fewer buffers than the shader uses is refused at creation; one that binds
  // more (a shader of a family using part of the shared list) is accepted.
  auto wrong = ComputePipeline::create(ctx(), PipelineDesc{"wrong", {material_counts_comp_spv, material_counts_comp_spv_words}, 2, {}});
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.message().find("storage binding 2"), std::string::npos) << wrong.message();
  auto wider = ComputePipeline::create(ctx(), PipelineDesc{"wider", {material_counts_comp_spv, material_counts_comp_spv_words}, 6, {}});
  EXPECT_TRUE(wider.ok()) << (wider ? "" : wider.message());
}

TEST_F(ComputeTest, ASubmissionThatNeverFinishesTimesOutAsAnError) {
  // The GPU waits on an event only the host sets, so the fence cannot signal before the timeout.
  ctx().core().options.submit_timeout_ns = 200'000'000;  // [ns]
  VkDevice device = ctx().core().device;
  VkEventCreateInfo eci{};
  eci.sType = VK_STRUCTURE_TYPE_EVENT_CREATE_INFO;
  VkEvent event = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateEvent(device, &eci, nullptr, &event), VK_SUCCESS);
  const Status s = submitAndWait(ctx(), "blocked submission", [&](Commands& cmds) -> Status {
    vkCmdWaitEvents(cmds.cmd(), 1, &event, VK_PIPELINE_STAGE_HOST_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, nullptr,
                    0, nullptr, 0, nullptr);
    return Ok{};
  });
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("did not finish within 200 ms"), std::string::npos) << s.message();
  // Its command buffer stays retired until the work is seen to finish.
  EXPECT_GT(ctx().collectRetired(), 0u);
  ASSERT_EQ(vkSetEvent(device, event), VK_SUCCESS);
  ASSERT_TRUE(ctx().waitIdle());
  EXPECT_EQ(ctx().collectRetired(), 0u);
  vkDestroyEvent(device, event, nullptr);
}

TEST_F(ComputeTest, TimestampsGiveAPositiveKernelTime) {
  std::string why;
  if (!TimestampPool::supported(ctx(), &why)) {
    auto pool = TimestampPool::create(ctx(), 1, "unsupported");
    ASSERT_FALSE(pool);
    EXPECT_NE(pool.message().find("unsupported"), std::string::npos);
    GTEST_SKIP() << "timestamps unsupported on " << ctx().device().name << ": " << why;
  }
  BrickVolume v(6);
  for (uint32_t z = 0; z < v.dim(); z += 3)
    for (uint32_t y = 0; y < v.dim(); y += 2)
      for (uint32_t x = 0; x < v.dim(); ++x) v.setVoxel(x, y, z, makeVoxel(Material::Dentin, 1 + (x % 31)));
  TimingOut timing;
  auto totals = countMaterialsGpu(ctx(), v, &timing);
  ASSERT_TRUE(totals) << totals.message();
  EXPECT_TRUE(timing.timestamps) << timing.timestamp_note;
  EXPECT_GT(timing.kernel_ns, 0.0);
  EXPECT_LT(timing.kernel_ns, 60e9);
  EXPECT_EQ(timing.dispatches, 1u);
  EXPECT_EQ(timing.workgroups, 512u / DS_COUNT_GROUP_SIZE);
}

}  // namespace dentsim::gpu::test
