// VoxelField: cached brick reads and the trilinear fill field the haptic contact model samples.
#include "sim/voxel_field.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace dentsim {

namespace {
bool isTile(uint32_t entry) { return (entry & DS_ENTRY_UNIFORM) != 0; }
Voxel tileValue(uint32_t entry) { return Voxel(entry & 0xffu); }
uint64_t brickKey(uint32_t bx, uint32_t by, uint32_t bz) {
  return (uint64_t(bx) << 42) | (uint64_t(by) << 21) | uint64_t(bz);
}
}  // namespace

VoxelField::VoxelField(const BrickVolume& volume, const VolumeFrame& frame)
    : volume_(volume), frame_(frame), dim_(int64_t(volume.dim())) {
  assert(frame.level == volume.level() && frame.voxel_mm > 0);
}

void VoxelField::loadBrick(uint32_t bx, uint32_t by, uint32_t bz) {
  cached_key_ = brickKey(bx, by, bz);
  cached_voxels_ = nullptr;
  const uint32_t centry = volume_.chunkWords()[layout::chunkCoordToIndex(
      bx >> DS_CHUNK_LOG2, by >> DS_CHUNK_LOG2, bz >> DS_CHUNK_LOG2, volume_.chunkDim())];
  if (isTile(centry)) {
    cached_tile_ = tileValue(centry);
    return;
  }
  const uint32_t m = DS_CHUNK_DIM - 1;
  const uint32_t bentry = volume_.blockWords()[size_t(centry & DS_ENTRY_INDEX_MASK) * DS_CHUNK_BRICKS +
                                               layout::brickCoordToOffset(bx & m, by & m, bz & m)];
  if (isTile(bentry)) {
    cached_tile_ = tileValue(bentry);
    return;
  }
  cached_voxels_ = reinterpret_cast<const Voxel*>(volume_.brickWords().data() +
                                                  size_t(bentry & DS_ENTRY_INDEX_MASK) * DS_BRICK_WORDS);
}

Voxel VoxelField::voxel(int64_t x, int64_t y, int64_t z) {
  if (x < 0 || y < 0 || z < 0 || x >= dim_ || y >= dim_ || z >= dim_) return 0;
  const auto bx = uint32_t(x >> DS_BRICK_LOG2), by = uint32_t(y >> DS_BRICK_LOG2), bz = uint32_t(z >> DS_BRICK_LOG2);
  if (brickKey(bx, by, bz) != cached_key_) loadBrick(bx, by, bz);
  if (cached_voxels_ == nullptr) return cached_tile_;
  const uint32_t m = DS_BRICK_DIM - 1;
  return cached_voxels_[layout::brickCoordToOffset(uint32_t(x) & m, uint32_t(y) & m, uint32_t(z) & m)];
}

FieldSample VoxelField::sample(const Vec3& u, bool with_outside) {
  const double fx = std::floor(u.x), fy = std::floor(u.y), fz = std::floor(u.z);
  const auto x0 = int64_t(fx), y0 = int64_t(fy), z0 = int64_t(fz);
  const double tx = u.x - fx, ty = u.y - fy, tz = u.z - fz;

  // The eight corners, x fastest. Most footprints lie inside one brick: read it once.
  Voxel c[8];
  const int64_t m = DS_BRICK_DIM - 1;
  const bool one_brick = x0 >= 0 && y0 >= 0 && z0 >= 0 && x0 + 1 < dim_ && y0 + 1 < dim_ && z0 + 1 < dim_ &&
                         (x0 & m) != m && (y0 & m) != m && (z0 & m) != m;
  if (one_brick) {
    const auto bx = uint32_t(x0 >> DS_BRICK_LOG2), by = uint32_t(y0 >> DS_BRICK_LOG2), bz = uint32_t(z0 >> DS_BRICK_LOG2);
    if (brickKey(bx, by, bz) != cached_key_) loadBrick(bx, by, bz);
    if (cached_voxels_ == nullptr) {
      FieldSample s;
      if (cached_tile_ == 0) return s;
      s.phi = double(voxelFill(cached_tile_)) / DS_FILL_FULL - 0.5;
      s.material = voxelMaterial(cached_tile_);
      return s;
    }
    const uint32_t o = layout::brickCoordToOffset(uint32_t(x0 & m), uint32_t(y0 & m), uint32_t(z0 & m));
    const uint32_t dy = DS_BRICK_DIM, dz = DS_BRICK_DIM * DS_BRICK_DIM;
    c[0] = cached_voxels_[o];
    c[1] = cached_voxels_[o + 1];
    c[2] = cached_voxels_[o + dy];
    c[3] = cached_voxels_[o + dy + 1];
    c[4] = cached_voxels_[o + dz];
    c[5] = cached_voxels_[o + dz + 1];
    c[6] = cached_voxels_[o + dz + dy];
    c[7] = cached_voxels_[o + dz + dy + 1];
  } else {
    for (int i = 0; i < 8; ++i) c[i] = voxel(x0 + (i & 1), y0 + ((i >> 1) & 1), z0 + ((i >> 2) & 1));
  }
  if ((c[0] | c[1] | c[2] | c[3] | c[4] | c[5] | c[6] | c[7]) == 0) return FieldSample{};

  double f[8];
  for (int i = 0; i < 8; ++i) f[i] = double(voxelFill(c[i])) * (1.0 / DS_FILL_FULL);
  // Trilinear value and its exact derivative inside the cell.
  const double f00 = f[0] + tx * (f[1] - f[0]), f10 = f[2] + tx * (f[3] - f[2]);
  const double f01 = f[4] + tx * (f[5] - f[4]), f11 = f[6] + tx * (f[7] - f[6]);
  const double f0 = f00 + ty * (f10 - f00), f1 = f01 + ty * (f11 - f01);
  FieldSample s;
  s.phi = f0 + tz * (f1 - f0) - 0.5;
  // Most samples of a step are outside tissue: they need no gradient and no material.
  if (s.phi <= 0 && !with_outside) return s;
  const double ex00 = f[1] - f[0], ex10 = f[3] - f[2], ex01 = f[5] - f[4], ex11 = f[7] - f[6];
  const double ex0 = ex00 + ty * (ex10 - ex00), ex1 = ex01 + ty * (ex11 - ex01);
  s.gradient.x = ex0 + tz * (ex1 - ex0);
  const double ey0 = f10 - f00, ey1 = f11 - f01;
  s.gradient.y = ey0 + tz * (ey1 - ey0);
  s.gradient.z = f1 - f0;

  // The tissue: the corner whose weighted fill is largest.
  double best = 0;
  for (int i = 0; i < 8; ++i) {
    const double w = ((i & 1) ? tx : 1 - tx) * ((i & 2) ? ty : 1 - ty) * ((i & 4) ? tz : 1 - tz);
    const double score = (w + 1e-9) * f[i];
    if (score > best) {
      best = score;
      s.material = voxelMaterial(c[i]);
    }
  }
  return s;
}

bool VoxelField::chunksEmpty(const Vec3& lo, const Vec3& hi) const {
  const double top = double(dim_ - 1);
  if (hi.x < 0 || hi.y < 0 || hi.z < 0 || lo.x > top || lo.y > top || lo.z > top) return true;
  auto chunkOf = [&](double v) {
    return uint32_t(int64_t(std::clamp(std::floor(v), 0.0, top)) >> DS_CHUNK_VOXEL_LOG2);
  };
  const std::span<const uint32_t> chunks = volume_.chunkWords();
  const uint32_t cd = volume_.chunkDim();
  for (uint32_t cz = chunkOf(lo.z); cz <= chunkOf(hi.z); ++cz)
    for (uint32_t cy = chunkOf(lo.y); cy <= chunkOf(hi.y); ++cy)
      for (uint32_t cx = chunkOf(lo.x); cx <= chunkOf(hi.x); ++cx) {
        const uint32_t e = chunks[layout::chunkCoordToIndex(cx, cy, cz, cd)];
        if (!isTile(e) || tileValue(e) != 0) return false;
      }
  return true;
}

}  // namespace dentsim
