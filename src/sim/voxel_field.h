// VoxelField: fast reads of a brick volume for the haptic thread, and its fill as a smooth field with a gradient.
//
// The haptic step reads a few thousand voxels a millisecond, mostly near one another, so the
// reader keeps the last brick it touched and skips the index walk when the next read falls in it.
// The field is the trilinear interpolation of fill/31 between voxel centres, minus 1/2: positive
// inside tissue, zero on the surface that marching cubes draws (the 0.5 iso-surface), so what the
// student feels is where the student sees the surface.
#pragma once

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
  // The field at continuous voxel coordinate u. Outside tissue (phi <= 0) the gradient and material
  // are left zero and empty unless with_outside is set.
  FieldSample sample(const Vec3& u, bool with_outside = false);
  // True when every voxel of the 64^3 chunks overlapping the box [lo, hi] (voxel coordinates) is
  // empty, read from the chunk table alone: the coarse test that lets a cluster of points skip.
  bool chunksEmpty(const Vec3& lo, const Vec3& hi) const;

  // Forget the cached brick: the volume's storage changed.
  void invalidate() { cached_key_ = kNoBrick; }

 private:
  static constexpr uint64_t kNoBrick = ~0ull;
  // Points cached_voxels_ at the brick holding (x,y,z) (or sets cached_tile_); x,y,z inside the grid.
  void loadBrick(uint32_t bx, uint32_t by, uint32_t bz);

  const BrickVolume& volume_;
  VolumeFrame frame_;
  int64_t dim_ = 0;
  uint64_t cached_key_ = kNoBrick;          // packed brick coordinate of the cache, or kNoBrick
  const Voxel* cached_voxels_ = nullptr;   // the cached dense brick's 512 voxels, or null for a tile
  Voxel cached_tile_ = 0;                  // the cached tile's value
};

}  // namespace dentsim
