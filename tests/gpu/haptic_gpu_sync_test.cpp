// After a drilling session on the haptic thread, the GPU's copy of the voxels equals the haptic thread's CPU copy, and the surface equals a fresh build.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "gpu/gpu_surface.h"
#include "gpu_fixture.h"
#include "io/pen_playback.h"
#include "sim/haptic_loop.h"
#include "sim/sim_fixtures.h"

namespace dentsim::gpu {
namespace {

using test::GpuTest;

TEST_F(GpuTest, AfterASessionTheGpuAndCpuVolumesAreIdentical) {
  dentsim::test::Block block = dentsim::test::flatBlock(Material::Caries);
  BrickVolume render_copy = block.volume;  // the render thread's own copy
  const double r = 0.4;
  const ToolModel bur = dentsim::test::sphereBur(r, 0.03, {0, 0, r});
  SimParams params = defaultSimParams();
  params.burs[bur.name].cutting_ability = 0.8;
  // Press 1.5 mm into the caries with the pedal down and sweep across for 0.3 s.
  PenPath path;
  for (double t : {0.0, 0.3}) {
    PenSample s;
    s.t_s = t;
    s.pose = Pose{{0.4 + 2.0 * t, 0.8, block.surface_mm + r - 1.5}, Quat{}};
    s.pedal = 1.0;
    path.samples.push_back(s);
  }
  ScriptedPen pen(path, PenRole::Drill);
  EditChannel channel(20);
  HapticLoop loop(block.volume, block.frame, params, bur, nullptr, &channel);
  loop.attach(PenRole::Drill, &pen);
  loop.placeTool(PenRole::Drill, Pose{{0.4, 0.8, block.surface_mm + r}, Quat{}});

  // The kernel's mesher, whose GPU mirror of the voxels this test reads back.
  auto surface = GpuSurface::create(ctx(), {.normal_neighbours = 64, .mesher = MesherKind::Gpu});
  ASSERT_TRUE(surface.ok()) << surface.message();
  ASSERT_TRUE(surface->build(render_copy).ok());

  // The render thread's part: each frame, replay the edits and re-mesh the bricks they touched.
  std::vector<uint64_t> edits;
  std::vector<BrickCoord> dirty;
  size_t frames = 0, edits_total = 0;
  auto frame = [&] {
    edits.clear();
    dirty.clear();
    channel.drain(&edits);
    edits_total += edits.size();
    applyVoxelEdits(render_copy, edits, &dirty);
    ASSERT_TRUE(surface->update(render_copy, dirty).ok());
    ++frames;
  };
  // Until the path is done and at least three frames ran beside the loop: on a loaded machine one
  // lavapipe frame may take longer than the whole path, so the frame count is not left to timing.
  ASSERT_TRUE(loop.start().ok());
  while (loop.latest().t_s < 0.35 || frames < 3) {
    frame();
    std::this_thread::sleep_for(std::chrono::milliseconds(16));
  }
  loop.stop();
  frame();  // the last edits

  EXPECT_GT(frames, 2u);
  EXPECT_GT(edits_total, 0u);
  EXPECT_GT(loop.latest().removed_mm3, 0.0);
  EXPECT_TRUE(render_copy == block.volume) << "the render copy missed an edit";
  auto on_gpu = surface->downloadVolume();
  ASSERT_TRUE(on_gpu.ok()) << on_gpu.message();
  EXPECT_TRUE(*on_gpu == block.volume) << "the GPU's voxels differ from the haptic thread's";
  // And the incremental surface is the one a fresh build gives.
  auto fresh = GpuSurface::create(ctx(), {.normal_neighbours = 64, .mesher = MesherKind::Gpu});
  ASSERT_TRUE(fresh.ok());
  SurfaceUpdateStats a, b;
  ASSERT_TRUE(fresh->build(block.volume, &a).ok());
  ASSERT_TRUE(surface->update(render_copy, {}, &b).ok());
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.blocks_live, b.blocks_live);
}

}  // namespace
}  // namespace dentsim::gpu
