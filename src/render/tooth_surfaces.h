// ToothSurfaces: one GPU marching-cubes surface per tissue, so that a translucent enamel shows the layers beneath it.
#pragma once

#include <array>
#include <memory>
#include <span>

#include "core/result.h"
#include "gpu/context.h"
#include "gpu/gpu_surface.h"
#include "volume/brick_volume.h"
#include "volume/normal_mode.h"
#include "volume/tissue_table.h"

namespace dentsim::render {

// The tissues drawn, in the tissue table's draw order, which is the order their surfaces are kept:
// the renderer draws opaque surfaces first to last and translucent ones last to first.
inline constexpr std::array<Material, kTissueCount> kDrawnTissues = tissuesInDrawOrder();

class ToothSurfaces {
 public:
  // Empty surfaces for every drawn tissue, with normals of `normals` (LookParams::view).
  // Errors: a Vulkan failure.
  static Result<ToothSurfaces> create(gpu::Context& ctx, NormalMode normals = NormalMode::Box216);

  // Meshes the whole volume, every tissue; stats (may be null) are summed over the tissues.
  Status build(const BrickVolume& volume, gpu::SurfaceUpdateStats* stats = nullptr);
  // Re-meshes what `dirty` bricks touch. After setNormalMode changed the mode it rebuilds
  // instead. Errors: no build yet, a Vulkan failure.
  Status update(const BrickVolume& volume, std::span<const BrickCoord> dirty, gpu::SurfaceUpdateStats* stats = nullptr);
  // Takes a new normal mode; the next update() rebuilds with it.
  void setNormalMode(NormalMode normals);

  NormalMode normalMode() const { return normals_; }
  bool built() const { return built_; }
  // The surface of kDrawnTissues[i]; what the renderer binds.
  gpu::GpuSurface& surface(size_t i) const { return *surfaces_[i]; }

 private:
  ToothSurfaces() = default;
  Status recreate();

  gpu::Context* ctx_ = nullptr;
  std::array<std::unique_ptr<gpu::GpuSurface>, kDrawnTissues.size()> surfaces_;
  NormalMode normals_ = NormalMode::Box216;
  bool mode_changed_ = false;  // the next update() rebuilds
  bool built_ = false;
};

}  // namespace dentsim::render
