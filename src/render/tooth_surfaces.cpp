// ToothSurfaces: builds and updates the tissue surfaces of every copy together, in one go or region by region, and sums what they report.
#include "render/tooth_surfaces.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <tuple>

#include "gpu/vk_check.h"
#include "volume/brick_pyramid.h"

namespace dentsim::render {

namespace {

using Clock = std::chrono::steady_clock;

// The coarsest copy is kept at 32^3 voxels or more: below that it holds no shape worth drawing.
constexpr int kCoarsestLevel = 5;

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

uint32_t regionOfBlock(uint32_t b, uint32_t region_dim) { return std::min(b / kLodRegionBricks, region_dim - 1); }

}  // namespace

NormalMode coarseNormalMode(NormalMode full, uint32_t k) {
  const double want = double(normalBoxSide(full)) / double(1u << k);
  NormalMode best = NormalMode::Box8;
  double best_gap = INFINITY;
  for (NormalMode m : kNormalModes) {  // widest last, so a tie goes to it
    const double gap = std::fabs(double(normalBoxSide(m)) - want);
    if (gap <= best_gap) {
      best_gap = gap;
      best = m;
    }
  }
  return best;
}

Result<ToothSurfaces> ToothSurfaces::create(gpu::Context& ctx, NormalMode normals, uint32_t coarse_copies,
                                            gpu::MesherKind mesher) {
  ToothSurfaces t;
  t.ctx_ = &ctx;
  t.normals_ = normals;
  t.coarse_wanted_ = coarse_copies;
  t.mesher_ = gpu::resolveMesher(mesher, ctx.device().type);
  if (t.mesher_ == gpu::MesherKind::Cpu) t.workers_ = std::make_shared<WorkerPool>();
  if (auto s = t.recreate(); !s) return s.error();
  return t;
}

Result<std::unique_ptr<gpu::GpuSurface>> ToothSurfaces::makeSurface(Material tissue, NormalMode normals) {
  gpu::GpuSurfaceOptions options;
  options.normal_neighbours = normalNeighbours(normals);
  options.tissue = tissue;
  options.mesher = mesher_;
  options.workers = workers_;
  auto s = gpu::GpuSurface::create(*ctx_, options);
  if (!s) return s.error();
  return std::make_unique<gpu::GpuSurface>(std::move(*s));
}

// Surfaces for the full copy; coarse copies get theirs at the first build of a level that has room.
Status ToothSurfaces::recreate() {
  copies_.clear();
  copies_.emplace_back();
  for (size_t i = 0; i < kDrawnTissues.size(); ++i) {
    auto s = makeSurface(kDrawnTissues[i], normals_);
    if (!s) return s.error();
    copies_[0].surfaces[i] = std::move(*s);
  }
  built_ = false;
  return Ok{};
}

Status ToothSurfaces::build(const BrickVolume& volume, gpu::SurfaceUpdateStats* stats) {
  DS_TRY_STATUS(buildCoarse(volume, 1));
  gpu::SurfaceUpdateStats total;
  for (auto& surface : copies_[0].surfaces) {
    gpu::SurfaceUpdateStats one;
    DS_TRY_STATUS(surface->build(volume, &one));
    accumulate(total, one);
  }
  if (stats) *stats = total;
  return Ok{};
}

Status ToothSurfaces::buildCoarse(const BrickVolume& volume, uint32_t from) {
  if (mode_changed_ || copies_.empty()) {
    DS_TRY_STATUS(recreate());
    mode_changed_ = false;
  }
  const uint32_t coarse = uint32_t(std::clamp(volume.level() - kCoarsestLevel, 0, int(coarse_wanted_)));
  copies_.resize(1 + coarse);
  region_dim_ = lodRegionDim(volume.brickDim());
  error_.assign(copies_.size(), {});
  for (uint32_t k = 1; k <= coarse; ++k) {
    Copy& c = copies_[k];
    if (!c.surfaces[0]) {
      for (size_t i = 0; i < kDrawnTissues.size(); ++i) {
        auto s = makeSurface(kDrawnTissues[i], coarseNormalMode(normals_, k));
        if (!s) return s.error();
        c.surfaces[i] = std::move(*s);
      }
    }
    c.volume = downsampleVolume(volume, k);
    c.pending.clear();
    if (k < from) continue;
    for (auto& surface : c.surfaces) DS_TRY_STATUS(surface->build(c.volume));
    measureCopyError(volume, c.volume, k, kLodRegionBricks, {}, error_[k]);
  }
  lagging_.assign(copies_.size(), std::vector<uint8_t>(size_t(region_dim_) * region_dim_ * region_dim_, 0));
  lagging_[0].clear();  // the full copy never lags
  pending_.clear();
  waiting_.clear();
  ready_.clear();
  blocks_total_ = blocks_done_ = 0;
  built_ = true;
  return Ok{};
}

Status ToothSurfaces::beginBuild(const BrickVolume& volume, const VolumeFrame& frame) {
  if (volume.level() - kCoarsestLevel < 1 || coarse_wanted_ == 0) return build(volume);
  const uint32_t coarsest = uint32_t(std::min(volume.level() - kCoarsestLevel, int(coarse_wanted_)));
  DS_TRY_STATUS(buildCoarse(volume, coarsest));
  frame_ = frame;
  const uint32_t rd = region_dim_;
  const size_t regions = size_t(rd) * rd * rd;
  ready_.assign(copies_.size(), std::vector<uint8_t>(regions, 1));
  waiting_.assign(copies_.size(), std::vector<uint8_t>(regions, 0));
  // The finer copies: nothing meshed yet, their candidate blocks bucketed by region.
  for (uint32_t k = 0; k < coarsest; ++k) {
    const BrickVolume& v = k == 0 ? volume : copies_[k].volume;
    for (auto& surface : copies_[k].surfaces) DS_TRY_STATUS(surface->clear(v));
    std::vector<uint32_t> packed;
    for (Material tissue : kDrawnTissues)
      for (const MeshBlock& b : activeMeshBlocks(v, tissue)) packed.push_back(b.packed());
    std::sort(packed.begin(), packed.end());
    packed.erase(std::unique(packed.begin(), packed.end()), packed.end());
    std::vector<std::vector<MeshBlock>> by_region(regions);
    // Copy k's block b lies mostly in the region of full block b * 2^k.
    for (uint32_t p : packed) {
      const MeshBlock b = MeshBlock::unpack(p);
      by_region[(size_t(regionOfBlock(b.z << k, rd)) * rd + regionOfBlock(b.y << k, rd)) * rd +
                regionOfBlock(b.x << k, rd)]
          .push_back(b);
    }
    blocks_total_ += packed.size();
    for (size_t r = 0; r < regions; ++r) {
      if (by_region[r].empty()) continue;
      pending_.push_back({k, uint32_t(r), std::move(by_region[r])});
      waiting_[k][r] = 1;
    }
    markReady(k);
  }
  if (pending_.empty()) ready_.clear();
  return Ok{};
}

// A region of copy k is ready when neither it nor a neighbour waits: its blocks reach one region out.
void ToothSurfaces::markReady(uint32_t k) {
  const int64_t rd = region_dim_;
  const std::vector<uint8_t>& waiting = waiting_[k];
  for (size_t r = 0; r < ready_[k].size(); ++r) {
    const int64_t x = int64_t(r) % rd, y = int64_t(r) / rd % rd, z = int64_t(r) / rd / rd;
    bool all = true;
    for (int64_t dz = -1; dz <= 1 && all; ++dz)
      for (int64_t dy = -1; dy <= 1 && all; ++dy)
        for (int64_t dx = -1; dx <= 1 && all; ++dx) {
          const int64_t nx = x + dx, ny = y + dy, nz = z + dz;
          if (nx < 0 || ny < 0 || nz < 0 || nx >= rd || ny >= rd || nz >= rd) continue;
          all = !waiting[size_t((nz * rd + ny) * rd + nx)];
        }
    ready_[k][r] = all ? 1 : 0;
  }
}

Status ToothSurfaces::continueBuild(const BrickVolume& volume, const glm::vec3& focus_mm, double budget_ms) {
  if (pending_.empty()) return Ok{};
  const auto t0 = Clock::now();
  // The next coarser copy first, then nearest the focus; sorted again each call, because the focus
  // moves with the camera.
  const uint32_t rd = region_dim_;
  const double side = double(kLodRegionBricks * DS_BRICK_DIM) * frame_.voxel_mm;
  const auto distance = [&](const PendingRegion& p) {
    const uint32_t at[3] = {p.region % rd, p.region / rd % rd, p.region / rd / rd};
    glm::vec3 c;
    for (int a = 0; a < 3; ++a) c[a] = float(frame_.origin_mm[size_t(a)] + (double(at[a]) + 0.5) * side);
    return glm::length(c - focus_mm);
  };
  std::vector<std::pair<std::pair<int64_t, float>, size_t>> order(pending_.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = {{-int64_t(pending_[i].copy), distance(pending_[i])}, i};
  std::sort(order.begin(), order.end());
  // Regions go to the mesher in batches of a few hundred blocks, one copy at a time: a submission
  // per region and tissue would cost more than its meshing.
  constexpr size_t kBatchBlocks = 512;
  std::vector<uint8_t> finished(pending_.size(), 0);
  std::vector<uint8_t> touched(copies_.size(), 0);
  size_t next = 0;
  while (next < order.size()) {
    const uint32_t k = pending_[order[next].second].copy;
    std::vector<MeshBlock> batch;
    while (next < order.size() && pending_[order[next].second].copy == k && batch.size() < kBatchBlocks) {
      PendingRegion& p = pending_[order[next].second];
      batch.insert(batch.end(), p.blocks.begin(), p.blocks.end());
      finished[order[next].second] = 1;
      waiting_[k][p.region] = 0;
      ++next;
    }
    const BrickVolume& v = k == 0 ? volume : copies_[k].volume;
    for (auto& surface : copies_[k].surfaces) DS_TRY_STATUS(surface->meshBlocks(v, batch));
    blocks_done_ += batch.size();
    touched[k] = 1;
    if (std::chrono::duration<double, std::milli>(Clock::now() - t0).count() >= budget_ms) break;
  }
  std::vector<PendingRegion> left;
  for (size_t i = 0; i < pending_.size(); ++i)
    if (!finished[i]) left.push_back(std::move(pending_[i]));
  pending_ = std::move(left);
  for (uint32_t k = 0; k < copies_.size(); ++k) {
    if (!touched[k]) continue;
    markReady(k);
    const bool whole = std::none_of(pending_.begin(), pending_.end(), [&](const PendingRegion& p) { return p.copy == k; });
    // A coarse copy meshed whole: its error, which the choice of copies needs, is measured now.
    if (whole && k > 0) measureCopyError(volume, copies_[k].volume, k, kLodRegionBricks, {}, error_[k]);
  }
  if (pending_.empty()) {
    ready_.clear();
    waiting_.clear();
  }
  return Ok{};
}

double ToothSurfaces::progress() const {
  return blocks_total_ ? double(blocks_done_) / double(blocks_total_) : 1.0;
}

std::span<const std::vector<uint8_t>> ToothSurfaces::readyRegions() const { return ready_; }

bool ToothSurfaces::coarseLagging() const {
  for (size_t k = 1; k < copies_.size(); ++k)
    if (!copies_[k].pending.empty()) return true;
  return false;
}

void ToothSurfaces::markLagging(uint32_t k, std::span<const BrickCoord> bricks) {
  // A coarse brick's voxels reach the cells one voxel out and the normals half the box's side plus
  // one: the regions of copy k that may draw something else than its surface does now.
  const int64_t scale = int64_t(1) << k, side = int64_t(kLodRegionBricks * DS_BRICK_DIM);
  const int64_t reach = int64_t(normalBoxSide(coarseNormalMode(normals_, k))) / 2 + 1;
  const int64_t last = int64_t(region_dim_) - 1;
  std::vector<uint8_t>& flags = lagging_[k];
  for (const BrickCoord& c : bricks) {
    const int64_t at[3] = {c.x, c.y, c.z};
    int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::clamp((at[a] * DS_BRICK_DIM - reach) * scale / side, int64_t(0), last);
      hi[a] = std::clamp(((at[a] + 1) * DS_BRICK_DIM + reach) * scale / side, int64_t(0), last);
    }
    for (int64_t z = lo[2]; z <= hi[2]; ++z)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t x = lo[0]; x <= hi[0]; ++x) flags[size_t((z * (last + 1) + y) * (last + 1) + x)] = 1;
  }
}

Status ToothSurfaces::settleCopy(const BrickVolume& volume, uint32_t k) {
  Copy& c = copies_[k];
  std::sort(c.pending.begin(), c.pending.end(), [](const BrickCoord& a, const BrickCoord& b) {
    return std::tuple(a.z, a.y, a.x) < std::tuple(b.z, b.y, b.x);
  });
  c.pending.erase(std::unique(c.pending.begin(), c.pending.end(),
                              [](const BrickCoord& a, const BrickCoord& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }),
                  c.pending.end());
  for (auto& surface : c.surfaces) DS_TRY_STATUS(surface->update(c.volume, c.pending));
  c.pending.clear();
  measureCopyError(volume, c.volume, k, kLodRegionBricks, lagging_[k], error_[k]);
  std::fill(lagging_[k].begin(), lagging_[k].end(), uint8_t{0});
  return Ok{};
}

Status ToothSurfaces::update(const BrickVolume& volume, std::span<const BrickCoord> dirty,
                             gpu::SurfaceUpdateStats* stats) {
  if (!built_) return makeError("tooth surfaces", "update before the first build");
  if (mode_changed_) return build(volume, stats);
  gpu::SurfaceUpdateStats total;
  for (auto& surface : copies_[0].surfaces) {
    gpu::SurfaceUpdateStats one;
    DS_TRY_STATUS(surface->update(volume, dirty, &one));
    accumulate(total, one);
  }
  ++updates_;
  if (!dirty.empty()) {
    for (uint32_t k = 1; k < copies_.size(); ++k) {
      const std::vector<BrickCoord> changed = downsampleBricks(volume, k, dirty, copies_[k].volume);
      if (copies_[k].pending.empty()) copies_[k].pending_since = updates_;
      copies_[k].pending.insert(copies_[k].pending.end(), changed.begin(), changed.end());
      markLagging(k, changed);
    }
  }
  // At most one copy catches up per update, so that no frame pays for all of them: the one that
  // has lagged longest, once it has for kCoarseSettleUpdates updates or nothing was cut.
  uint32_t oldest = 0;
  for (uint32_t k = 1; k < copies_.size(); ++k)
    if (!copies_[k].pending.empty() && (oldest == 0 || copies_[k].pending_since < copies_[oldest].pending_since))
      oldest = k;
  if (oldest != 0 && (dirty.empty() || updates_ - copies_[oldest].pending_since >= kCoarseSettleUpdates))
    DS_TRY_STATUS(settleCopy(volume, oldest));
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
