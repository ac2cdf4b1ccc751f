// ToothSurfaces: one GPU marching-cubes surface per tissue and per copy of the tooth (full, averaged 2^3, 4^3, 8^3), so that a translucent enamel shows the layers beneath it and far parts cost few triangles.
//
// Copy 0 is the full volume, the one the haptic loop cuts. Copy k (k = 1, 2, 3) is the volume with
// each voxel averaged over 2^k x 2^k x 2^k (volume/brick_pyramid.h), meshed by the same marching cubes
// with the normal box nearest in millimetres to the full copy's. The renderer draws each region from
// one copy (render/tooth_lod.h).
//
// Keeping the copies up to date. A cut re-meshes the full copy at once. The coarse copies' voxels
// follow at once too (a brick average is cheap), but their surfaces are re-meshed only every few
// updates or when nothing was cut, one copy per update: until then the regions a copy lags in are
// flagged, and the renderer draws those from a finer copy. So a cut never shows stale, and drilling pays little for copies
// it does not see.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/result.h"
#include "gpu/context.h"
#include "gpu/gpu_surface.h"
#include "render/tooth_lod.h"
#include "volume/brick_volume.h"
#include "volume/normal_mode.h"
#include "volume/tissue_table.h"

namespace dentsim::render {

// The tissues drawn, in the tissue table's draw order, which is the order their surfaces are kept:
// the renderer draws opaque surfaces first to last and translucent ones last to first.
inline constexpr std::array<Material, kTissueCount> kDrawnTissues = tissuesInDrawOrder();

// Averaged 2^3, 4^3 and 8^3. The third serves level 10 and finer: there the 4^3 copy still has about
// seven triangles to each pixel of the tooth in a default view, the 8^3 copy under two.
inline constexpr uint32_t kDefaultCoarseCopies = 3;
inline constexpr uint32_t kCoarseSettleUpdates = 8;  // cutting updates before the coarse copies are re-meshed

// The normal mode of copy k: the box whose side in millimetres is nearest the full copy's (ties to
// the wider one), at least 2 voxels. 216 gives 216, 64, 8; 64 gives 64, 8, 8.
NormalMode coarseNormalMode(NormalMode full, uint32_t k);

class ToothSurfaces {
 public:
  // Empty surfaces for every drawn tissue and copy, with normals of `normals` (LookParams::view),
  // meshed by `mesher` (on the CPU mesher all of them share one pool of threads). coarse_copies 0
  // keeps the full copy alone. Errors: a Vulkan failure.
  static Result<ToothSurfaces> create(gpu::Context& ctx, NormalMode normals = NormalMode::Box216,
                                      uint32_t coarse_copies = kDefaultCoarseCopies,
                                      gpu::MesherKind mesher = gpu::MesherKind::Auto);

  // Meshes the whole volume, every tissue and copy; stats (may be null) are summed over the
  // tissues of the full copy.
  Status build(const BrickVolume& volume, gpu::SurfaceUpdateStats* stats = nullptr);

  // The same in parts, so that a first frame comes early: beginBuild meshes the coarsest copy
  // whole (a sixteenth of the triangles or less) and nothing of the others; each continueBuild
  // meshes their blocks region by region, the next coarser copy first and within a copy nearest
  // to `focus_mm` first, for at least one batch of regions and until `budget_ms` has passed. done()
  // says when every copy is whole; progress() is the share of their blocks meshed. A volume too
  // small for coarse copies is built whole at once.
  Status beginBuild(const BrickVolume& volume, const VolumeFrame& frame);
  Status continueBuild(const BrickVolume& volume, const glm::vec3& focus_mm, double budget_ms);
  bool done() const { return pending_.empty(); }
  double progress() const;

  // Re-meshes what `dirty` bricks touch in the full copy, and brings the coarse copies' voxels up
  // to date; their surfaces follow one copy per update, once it has lagged kCoarseSettleUpdates
  // updates or on an update with nothing dirty. After setNormalMode changed the mode it rebuilds instead. Errors: no build yet, a
  // Vulkan failure.
  Status update(const BrickVolume& volume, std::span<const BrickCoord> dirty, gpu::SurfaceUpdateStats* stats = nullptr);
  // Takes a new normal mode; the next update() rebuilds with it.
  void setNormalMode(NormalMode normals);

  NormalMode normalMode() const { return normals_; }
  gpu::MesherKind mesher() const { return mesher_; }  // as resolved for the device
  bool built() const { return built_; }
  uint32_t copies() const { return uint32_t(copies_.size()); }
  // Whether the coarse copies lag behind cuts (an update with nothing dirty settles them).
  bool coarseLagging() const;
  // The surface of kDrawnTissues[i] in copy k; what the renderer binds.
  gpu::GpuSurface& surface(size_t i, uint32_t k = 0) const { return *copies_[k].surfaces[i]; }
  // Per copy, per region (render/tooth_lod.h), 1 where the copy lags behind a cut: the region is
  // drawn from a finer copy there. Copy 0's list is empty.
  std::span<const std::vector<uint8_t>> laggingRegions() const { return lagging_; }
  // Per copy, per region, 1 where the copy is meshed; empty when every copy is whole.
  std::span<const std::vector<uint8_t>> readyRegions() const;
  // Per copy, per region, how far the copy's surface lies from the full one [full voxels]
  // (measureCopyError); copy 0's list is empty.
  std::span<const std::vector<float>> copyErrors() const { return error_; }

 private:
  struct Copy {
    std::array<std::unique_ptr<gpu::GpuSurface>, kDrawnTissues.size()> surfaces;
    BrickVolume volume;                  // the averaged voxels (copy 0 keeps none: it is the caller's)
    std::vector<BrickCoord> pending;     // coarse bricks changed since the surfaces were last meshed
    uint64_t pending_since = 0;          // the update that found the first of them
  };

  ToothSurfaces() = default;
  Status recreate();
  Result<std::unique_ptr<gpu::GpuSurface>> makeSurface(Material tissue, NormalMode normals);
  // The coarse copies' voxels, and the surfaces of copies `from` .. coarsest whole; the others left.
  Status buildCoarse(const BrickVolume& volume, uint32_t from);
  void markReady(uint32_t k);
  Status settleCopy(const BrickVolume& volume, uint32_t k);  // copy k's surfaces catch up with its voxels
  void markLagging(uint32_t k, std::span<const BrickCoord> bricks);

  gpu::Context* ctx_ = nullptr;
  std::vector<Copy> copies_;
  uint32_t coarse_wanted_ = kDefaultCoarseCopies;
  NormalMode normals_ = NormalMode::Box216;
  gpu::MesherKind mesher_ = gpu::MesherKind::Auto;
  std::shared_ptr<WorkerPool> workers_;  // the CPU mesher's threads, one pool for every surface
  bool mode_changed_ = false;  // the next update() rebuilds
  bool built_ = false;
  uint32_t region_dim_ = 0;
  std::vector<std::vector<uint8_t>> lagging_;  // per copy, per region
  uint64_t updates_ = 0;                        // update() calls so far
  // A build in parts: the candidate blocks of one copy in one region, still to mesh.
  struct PendingRegion {
    uint32_t copy = 0;
    uint32_t region = 0;
    std::vector<MeshBlock> blocks;  // in the copy's own block coordinates
  };
  std::vector<PendingRegion> pending_;
  std::vector<std::vector<uint8_t>> waiting_;  // per copy, per region: 1 while its blocks wait
  VolumeFrame frame_;                          // where regions are, for the focus
  std::vector<std::vector<uint8_t>> ready_;  // per copy; empty when whole
  std::vector<std::vector<float>> error_;    // per copy, per region [full voxels]
  size_t blocks_total_ = 0, blocks_done_ = 0;
};

}  // namespace dentsim::render
