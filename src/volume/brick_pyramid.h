// Coarser copies of a brick volume for drawing far-away parts of the tooth: each voxel averages 2^k x 2^k x 2^k voxels of the full one.
//
// The renderer meshes these with the same marching cubes as the full volume and draws each part of
// the tooth at the coarsest copy whose error stays under about a pixel (render/tooth_lod.h). The
// haptic loop and the scores never read them: they always see the full volume.
//
// The rule for one coarse voxel of factor f = 2^k (f^3 full voxels beneath it):
// - fill: the mean fill of the f^3 voxels, rounded half up (so the solid share is the mean share);
// - tissue: the tissue with the largest summed fill beneath it (ties go to the lower Material code);
// - a mean that rounds to 0 is empty.
// It is applied to the full volume directly, not to the next finer copy, so a 4^3 copy does not
// round twice.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "volume/brick_volume.h"

namespace dentsim {

// The coarse voxel over the f^3 voxels of `fine` whose lowest corner is (x, y, z), f = 2^k: the
// rule above, voxel by voxel. The reference the brick-wise code is tested against.
Voxel coarseVoxelReference(const BrickVolume& fine, uint32_t x, uint32_t y, uint32_t z, uint32_t k);

// The whole coarse copy of `fine` at level fine.level() - k (k >= 1, the result's level >= DS_MIN_LEVEL).
BrickVolume downsampleVolume(const BrickVolume& fine, uint32_t k);

// Brings `coarse` (a copy made by downsampleVolume with the same k) up to date after the full
// volume changed only inside `fine_dirty` bricks. Returns the coarse bricks it rewrote, sorted and
// unique: what the coarse surface must re-mesh. The result equals downsampleVolume(fine, k).
std::vector<BrickCoord> downsampleBricks(const BrickVolume& fine, uint32_t k, std::span<const BrickCoord> fine_dirty,
                                         BrickVolume& coarse);

// How far copy k's surface (the outer surface: any tissue's fill) lies from the full one, per region
// of `region_bricks` full bricks a side [full voxels]. For each lattice edge of the copy where its
// fill crosses one half, the vertex marching cubes puts there is compared with the nearest crossing
// of the full fill on the full voxel row through it along the same axis, and that distance is
// scaled by the axis's share of the copy's normal (the distance across the surface). A vertex with
// no full crossing within 2^(k+1) voxels counts that far. A region's error is the root mean square
// over its vertices: one grazing edge does not decide it, a surface that moved does. A full brick
// holding surface where the copy holds none, nor next to it (a feature the copy lost), sets its
// region's error to 2^(k+1) at least.
// `error` has one entry per region (x fastest); with `only` non-empty (one flag per region) just the
// flagged regions are measured again, the others kept.
void measureCopyError(const BrickVolume& full, const BrickVolume& coarse, uint32_t k, uint32_t region_bricks,
                      std::span<const uint8_t> only, std::vector<float>& error);

}  // namespace dentsim
