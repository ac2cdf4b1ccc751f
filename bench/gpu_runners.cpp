// gpuVoxelizer, layersVolumeMaker and gpuMeshRunner: gpu::voxelizeGpu and gpu::GpuSurface behind the bench interfaces.
#include "bench/gpu_runners.h"

#include <chrono>
#include <memory>
#include <thread>
#include <optional>
#include <span>
#include <utility>

#include "gpu/gpu_surface.h"
#include "gpu/gpu_voxelizer.h"

namespace dentsim::bench {

DentsimVoxelizer gpuVoxelizer(gpu::Context& context, const VoxelizeOptions& options) {
  return [&context, options](const std::vector<MeshLayer>& layers, const VolumeFrame& frame) -> Result<DentsimRun> {
    const auto start = std::chrono::steady_clock::now();
    auto setup = makeRaySetup(layers, frame, options);
    if (!setup) return setup.error();
    gpu::VoxelizeTiming timing;
    auto volume = gpu::voxelizeGpu(context, *setup, options, &timing);
    if (!volume) return volume.error();
    DentsimRun run;
    run.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    run.kernel_ms = timing.kernels_ms;
    run.hits = timing.hits;
    run.dense_bricks = volume->stats().dense_bricks;
    run.totals = volume->materialTotals();
    return run;
  };
}

VolumeMaker layersVolumeMaker(gpu::Context* context, const std::vector<MeshLayer>& layers, Bounds3 bounds) {
  if (context == nullptr) return cpuVolumeMaker(layers);
  return [context, &layers, bounds](int level) -> Result<ToothVolume> {
    auto frame = fitGridToLevel(bounds, level);
    if (!frame) return frame.error();
    VoxelizeOptions vo;
    auto setup = makeRaySetup(layers, *frame, vo);
    if (!setup) return setup.error();
    auto voxels = gpu::voxelizeGpu(*context, *setup, vo);
    if (!voxels) return voxels.error();
    voxels->compact();
    return ToothVolume{*frame, std::move(voxels).value()};
  };
}

// One GpuSurface for the mode being measured; a new one when the mode changes, so that three
// level-10 surfaces never sit in memory at once.
MeshRunner gpuMeshRunner(gpu::Context& context, gpu::MesherKind asked) {
  const gpu::MesherKind mesher = gpu::resolveMesher(asked, context.device().type);
  struct Held {
    std::optional<gpu::GpuSurface> surface;
    int normals = 0;
  };
  auto held = std::make_shared<Held>();
  const auto timing = [](double ms, const gpu::SurfaceUpdateStats& st) {
    return MeshTiming{ms, st.timestamps ? st.count_kernel_ms + st.emit_kernel_ms : 0.0, st.triangles,
                      st.blocks_meshed};
  };
  MeshRunner r;
  r.name = mesher == gpu::MesherKind::Cpu
               ? "CPU mesher (GpuSurface, BlockMesher on " + std::to_string(std::max(1u, std::thread::hardware_concurrency())) +
                     " threads into host-visible slots)"
               : "GPU mesher (GpuSurface, compute kernel)";
  r.mesher = gpu::mesherKindName(mesher);
  r.full = [&context, held, timing, mesher](const ToothVolume& tooth, int normals) -> Result<MeshTiming> {
    if (!held->surface || held->normals != normals) {
      held->surface.reset();
      auto s = gpu::GpuSurface::create(context, {.normal_neighbours = normals, .mesher = mesher});
      if (!s) return s.error();
      held->surface.emplace(std::move(s).value());
      held->normals = normals;
    }
    gpu::SurfaceUpdateStats st;
    const auto t0 = std::chrono::steady_clock::now();
    if (Status b = held->surface->build(tooth.voxels, &st); !b) return b.error();
    return timing(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(), st);
  };
  r.update = [held, timing](const ToothVolume& tooth, std::span<const BrickCoord> dirty,
                            int normals) -> Result<MeshTiming> {
    if (!held->surface || held->normals != normals) return makeError("bench mesh", "update before a full build");
    gpu::SurfaceUpdateStats st;
    const auto t0 = std::chrono::steady_clock::now();
    if (Status u = held->surface->update(tooth.voxels, dirty, &st); !u) return u.error();
    return timing(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(), st);
  };
  return r;
}

}  // namespace dentsim::bench
