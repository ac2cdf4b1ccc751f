// VoxelField: fast reads of a brick volume for the haptic thread, and its fill as a smooth field with a gradient.
//
// The haptic step reads thousands of cells a millisecond, mostly near one another, so the reader
// keeps copies of the bricks it touched in a direct-mapped table (a 16^3-brick window, 2.6 mm at
// level 10, without conflicts). Each copy is 9^3 voxels: the brick and the first voxel layer of its
// +x, +y and +z neighbours, so the eight corners of any cell sit in one copy at fixed offsets and a
// sample never asks which brick a corner is in. Writes (the cutter's) go through written(), which
// keeps every cached copy that holds the voxel up to date.
// The field is the trilinear interpolation of fill/31 between voxel centres, minus 1/2: positive
// inside tissue, zero on the surface that marching cubes draws (the 0.5 iso-surface), so what the
// student feels is where the student sees the surface.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/rigid.h"
#include "core/volume_frame.h"
#include "volume/brick_volume.h"

namespace dentsim {

// floor(v) as an integer, without the library call (baseline x86-64 has no instruction for it).
inline int64_t voxelFloor(double v) {
  const auto i = int64_t(v);  // toward zero
  return i - int64_t(v < double(i));
}

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
  // phi at n points given as float voxel coordinates, four at a time: the same field to float
  // rounding (|error| below 1e-3 within 2048 voxels of the origin). Each array, phi included, must
  // have room for n rounded up to a multiple of 4.
  void phiBatch(const float* ux, const float* uy, const float* uz, uint32_t n, float* phi);
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
  // A box clear of the tissue's bounding box answers at once: a mirror's long handle or a tool far
  // off then costs a comparison per cluster, even where every chunk holds some tissue.
  bool chunksEmpty(const Vec3& lo, const Vec3& hi) const;

  // Forget the cached bricks and the tissue's box: the volume changed other than through written().
  void invalidate();
  // Voxel (x, y, z) of the volume now holds v: the cached copies that hold it follow.
  void written(uint32_t x, uint32_t y, uint32_t z, Voxel v);

 private:
  static constexpr uint64_t kNoBrick = ~0ull;
  static constexpr uint32_t kSide = DS_BRICK_DIM + 1;                       // a copy's side [voxel]
  static constexpr uint32_t kCopyBytes = 768;                               // 9^3 = 729, in whole cache lines
  static constexpr uint32_t kSlots = 4096;                                  // 16^3 bricks
  struct CachedBrick {
    uint64_t key = kNoBrick;  // packed brick coordinate, or kNoBrick
    bool is_tile = false;     // the brick itself is uniform (a tile) of value `tile`
    Voxel tile = 0;
  };
  static uint32_t slot(uint32_t bx, uint32_t by, uint32_t bz) { return (bx & 15u) | ((by & 15u) << 4) | ((bz & 15u) << 8); }
  static uint64_t brickKey(uint32_t bx, uint32_t by, uint32_t bz) {
    return (uint64_t(bx) << 42) | (uint64_t(by) << 21) | uint64_t(bz);
  }
  // The copy of brick (bx,by,bz), made on a miss; the brick lies inside the grid.
  const Voxel* copy(uint32_t bx, uint32_t by, uint32_t bz) {
    const uint32_t s = slot(bx, by, bz);
    if (cache_[s].key != brickKey(bx, by, bz)) [[unlikely]]
      load(s, bx, by, bz);
    return &copies_[size_t(s) * kCopyBytes];
  }
  void load(uint32_t s, uint32_t bx, uint32_t by, uint32_t bz);
  // The corners of u's cell, x fastest, and u's place in it [0,1)^3; false when all eight are empty.
  bool cell(const Vec3& u, Voxel c[8], double t[3]);

  const BrickVolume& volume_;
  VolumeFrame frame_;
  int64_t dim_ = 0;
  std::vector<CachedBrick> cache_;  // (kSlots) slot: low 4 bits of bx, by and bz
  std::vector<Voxel> copies_;       // (kSlots * kCopyBytes) the slots' 9^3 copies, x fastest
  // The bricks holding tissue, as a box in voxel coordinates (empty: lo > hi). Cutting only removes
  // tissue, so the box found at construction stays a bound until invalidate().
  Vec3 tissue_lo_, tissue_hi_;
  void findTissueBox();
};

}  // namespace dentsim
