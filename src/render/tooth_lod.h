// Screen-sized detail: which copy of the tooth (full, or averaged 2^3, 4^3, 8^3) each region is drawn from, per pass and per frame.
//
// The tooth's grid is cut into regions of 32^3 full voxels (4^3 bricks). Each region is drawn from
// the coarsest copy k whose error, seen from the pass's camera, stays under `pixel_error` pixels:
//   error(k) = the copy's measured distance from the full surface in the region (volume/
//              brick_pyramid.h measureCopyError), at least a quarter of the copy's voxel (its
//              shading differs over features smaller than its voxel, which the distance misses);
//              half a coarse voxel where no measure is given; the full copy's error counts as 0
//   pixels   = error(k) * focal_px / depth,   focal_px = max(|P00| w, |P11| h) / 2,
// with depth the region's nearest view depth. A region the pass cannot see (outside the frustum)
// is not drawn. A region near the bur, or that the eye is inside, is drawn from the full copy;
// where the chosen copy still lags behind a cut, from the next finer one.
//
// Borders between copies are closed by overlap, not by stitching: a copy's mesh blocks are drawn
// wherever they reach into a region of that copy, so at a border both copies are drawn over a strip
// of a few voxels and no gap can open between them. docs/MESHING.md says why.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/volume_frame.h"
#include "volume/surface_mesher.h"

namespace dentsim::render {

inline constexpr uint32_t kLodRegionBricks = 4;  // region side [bricks]; 32 full voxels
inline constexpr uint8_t kLodHidden = 0xff;       // a region the pass does not draw
inline constexpr double kMaxDetailPixels = 16.0;  // the largest error a user may allow [px]

struct LodSettings {
  float pixel_error = 1.0f;    // largest error on screen [px]; 0 draws everything from the full copy
  float bur_radius_mm = 1.0f;  // regions this close to the bur tip are drawn from the full copy [mm]
};

// One pass's camera as the choice needs it.
struct LodView {
  glm::mat4 view{1.0f};        // world [mm] to eye (right-handed, looking down -Z)
  glm::mat4 projection{1.0f};  // eye to clip
  uint32_t width = 1, height = 1;  // the pass's image [px]
  std::optional<glm::vec3> bur_tip;  // [mm]
};

// Regions per side for a full grid of `brick_dim` bricks per side.
inline uint32_t lodRegionDim(uint32_t brick_dim) { return (brick_dim + kLodRegionBricks - 1) / kLodRegionBricks; }

// The copy each region is drawn from in one pass.
struct LodChoice {
  uint32_t region_dim = 0;      // regions per side
  std::vector<uint8_t> copy;    // per region (x fastest): 0 full, k the 2^k copy, kLodHidden not drawn

  uint8_t at(uint32_t x, uint32_t y, uint32_t z) const { return copy[(size_t(z) * region_dim + y) * region_dim + x]; }
  // Whether block `b` of copy k is drawn: some region its cells reach into (widened by one full
  // voxel, so that neighbouring copies overlap) is drawn from copy k.
  bool drawsBlock(uint32_t k, MeshBlock b) const;
};

// What the tooth's surfaces know per region (each may be empty).
struct LodRegions {
  std::span<const std::vector<uint8_t>> ready;       // [k][region] 1: copy k is meshed here; empty: all are
  std::span<const std::vector<uint8_t>> lagging;     // [k][region] 1: copy k lags behind a cut here
  std::span<const std::vector<float>> error;         // [k][region] copy k's measured error [full voxels]; [0] unused
};

// Chooses a copy per region. `full` is the full copy's frame. A region whose chosen copy lags
// behind a cut takes the next finer copy that does not (the full copy never lags); one whose chosen
// copy is not meshed yet takes the next coarser one that is, else the next finer.
LodChoice chooseLod(const VolumeFrame& full, uint32_t coarse_copies, const LodView& view, const LodSettings& settings,
                    const LodRegions& regions = {});

}  // namespace dentsim::render
