// VoxelField: fast reads of a brick volume for the haptic thread, and its fill as a smooth field with a gradient.
//
// The haptic step reads a few thousand voxels a millisecond, mostly near one another, so the
// reader keeps the bricks it touched in a small direct-mapped table (an 8 x 8 x 4 brick window,
// 1.3 mm at level 10, without conflicts) and skips the index walk when a read falls in one.
// The field is the trilinear interpolation of fill/31 between voxel centres, minus 1/2: positive
// inside tissue, zero on the surface that marching cubes draws (the 0.5 iso-surface), so what the
// student feels is where the student sees the surface.
#pragma once

#include <array>
#include <cstdint>

#include "core/rigid.h"
#include "core/volume_frame.h"
#include "volume/brick_volume.h"

namespace dentsim {

// One sample of the field.
struct FieldSample {
  double phi = -0.5;          // interpolated fill - 1/2, in [-1/2, 1/2]; > 0 inside tissue
  Vec3 gradient;              // d(phi)/d(voxel coordinate) [1/voxel]
  Material material = Material::Empty;  // tissue of the corner that holds the most of it
};

class VoxelField {
 public:
  // The volume must outlive the field. After the volume changes, call invalidate() before reading.
  VoxelField(const BrickVolume& volume, const VolumeFrame& frame);

  const VolumeFrame& frame() const { return frame_; }
  double voxelMm() const { return frame_.voxel_mm; }
  int64_t dim() const { return dim_; }  // voxels per side

  // Continuous voxel coordinate of a simulation-frame point: voxel centres sit at integers.
  Vec3 toVoxel(const Vec3& p_mm) const {
    const double inv = 1.0 / frame_.voxel_mm;
    return {(p_mm.x - frame_.origin_mm[0]) * inv - 0.5, (p_mm.y - frame_.origin_mm[1]) * inv - 0.5,
            (p_mm.z - frame_.origin_mm[2]) * inv - 0.5};
  }
  Vec3 toMm(const Vec3& u) const {
    return {frame_.origin_mm[0] + (u.x + 0.5) * frame_.voxel_mm, frame_.origin_mm[1] + (u.y + 0.5) * frame_.voxel_mm,
            frame_.origin_mm[2] + (u.z + 0.5) * frame_.voxel_mm};
  }

  // The voxel at integer coordinates; empty outside the grid.
  Voxel voxel(int64_t x, int64_t y, int64_t z);
  // The field at continuous voxel coordinate u. Outside tissue (phi <= 0) the material is left empty,
  // and the gradient zero unless with_outside is set.
  FieldSample sample(const Vec3& u, bool with_outside = false);
  // sample(u).phi alone: the cheap test most shell points need.
  double phi(const Vec3& u);
  // A lower bound on the distance [voxel] from u to tissue (phi >= 0), given phi = sample(u).phi;
  // 0 inside tissue. Cutting only removes tissue, so the bound stays true until tissue is added:
  // a point that has moved less than this since it was sampled is still outside. look_around: where
  // u's cell is empty, read the voxels and bricks around for a longer bound (up to ~100 ns more).
  double clearance(const Vec3& u, double phi, bool look_around = true);
  // True when every voxel with x0 <= x <= x1, y0 <= y <= y1, z0 <= z <= z1 is empty (outside the grid
  // counts as empty). tiles_only: answer from the index tables alone, false at the first dense brick.
  bool regionEmpty(int64_t x0, int64_t x1, int64_t y0, int64_t y1, int64_t z0, int64_t z1, bool tiles_only = false);
  // True when every voxel of the 64^3 chunks overlapping the box [lo, hi] (voxel coordinates) is
  // empty, read from the chunk table alone: the coarse test that lets a cluster of points skip.
  bool chunksEmpty(const Vec3& lo, const Vec3& hi) const;

  // Forget the cached bricks: the volume's storage changed.
  void invalidate();

 private:
  static constexpr uint64_t kNoBrick = ~0ull;
  struct CachedBrick {
    uint64_t key = kNoBrick;         // packed brick coordinate, or kNoBrick
    const Voxel* voxels = nullptr;   // the dense brick's 512 voxels, or null for a tile
    Voxel tile = 0;                  // the tile's value
  };
  // The corners of u's cell, x fastest, and u's place in it [0,1)^3; false when all eight are empty.
  bool cell(const Vec3& u, Voxel c[8], double t[3]);
  // The cache entry of brick (bx,by,bz), loaded on a miss; the brick lies inside the grid.
  const CachedBrick& brick(uint32_t bx, uint32_t by, uint32_t bz);
  void load(CachedBrick* entry, uint32_t bx, uint32_t by, uint32_t bz) const;

  const BrickVolume& volume_;
  VolumeFrame frame_;
  int64_t dim_ = 0;
  std::array<CachedBrick, 256> cache_{};  // slot: low 3 bits of bx and by, low 2 of bz
};

}  // namespace dentsim
