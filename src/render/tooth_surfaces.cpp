// ToothSurfaces: builds and updates the four tissue surfaces together and sums what they report.
#include "render/tooth_surfaces.h"

#include <string>

#include "gpu/vk_check.h"

namespace dentsim::render {

namespace {

// Adds one tissue's statistics into the running total; live counts and bytes add up across tissues.
void accumulate(gpu::SurfaceUpdateStats& total, const gpu::SurfaceUpdateStats& s) {
  total.dirty_bricks = s.dirty_bricks;
  total.blocks_meshed += s.blocks_meshed;
  total.blocks_live += s.blocks_live;
  total.triangles += s.triangles;
  total.vertices += s.vertices;
  total.pool_bytes += s.pool_bytes;
  total.slot_bytes += s.slot_bytes;
  total.used_bytes += s.used_bytes;
  total.pool_grew = total.pool_grew || s.pool_grew;
  total.upload_ms += s.upload_ms;
  total.count_ms += s.count_ms;
  total.emit_ms += s.emit_ms;
  total.total_ms += s.total_ms;
  total.timestamps = s.timestamps;
  total.count_kernel_ms += s.count_kernel_ms;
  total.emit_kernel_ms += s.emit_kernel_ms;
}

}  // namespace

Result<ToothSurfaces> ToothSurfaces::create(gpu::Context& ctx, NormalMode normals) {
  ToothSurfaces t;
  t.ctx_ = &ctx;
  t.normals_ = normals;
  if (auto s = t.recreate(); !s) return s.error();
  return t;
}

Status ToothSurfaces::recreate() {
  for (size_t i = 0; i < kDrawnTissues.size(); ++i) {
    gpu::GpuSurfaceOptions options;
    options.normal_neighbours = normalNeighbours(normals_);
    options.tissue = kDrawnTissues[i];
    auto s = gpu::GpuSurface::create(*ctx_, options);
    if (!s) return s.error();
    surfaces_[i] = std::make_unique<gpu::GpuSurface>(std::move(*s));
  }
  built_ = false;
  return Ok{};
}

Status ToothSurfaces::build(const BrickVolume& volume, gpu::SurfaceUpdateStats* stats) {
  if (mode_changed_) {
    DS_TRY_STATUS(recreate());
    mode_changed_ = false;
  }
  gpu::SurfaceUpdateStats total;
  for (auto& surface : surfaces_) {
    gpu::SurfaceUpdateStats one;
    DS_TRY_STATUS(surface->build(volume, &one));
    accumulate(total, one);
  }
  built_ = true;
  if (stats) *stats = total;
  return Ok{};
}

Status ToothSurfaces::update(const BrickVolume& volume, std::span<const BrickCoord> dirty,
                             gpu::SurfaceUpdateStats* stats) {
  if (!built_) return makeError("tooth surfaces", "update before the first build");
  if (mode_changed_) return build(volume, stats);
  gpu::SurfaceUpdateStats total;
  for (auto& surface : surfaces_) {
    gpu::SurfaceUpdateStats one;
    DS_TRY_STATUS(surface->update(volume, dirty, &one));
    accumulate(total, one);
  }
  if (stats) *stats = total;
  return Ok{};
}

void ToothSurfaces::setNormalMode(NormalMode normals) {
  if (normals != normals_) {
    normals_ = normals;
    mode_changed_ = true;
  }
}

}  // namespace dentsim::render
