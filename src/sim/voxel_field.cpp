// VoxelField: cached brick reads and the trilinear fill field the haptic contact model samples.
#include "sim/voxel_field.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

namespace dentsim {

namespace {
bool isTile(uint32_t entry) { return (entry & DS_ENTRY_UNIFORM) != 0; }
Voxel tileValue(uint32_t entry) { return Voxel(entry & 0xffu); }
// A voxel byte's fill as a fraction: a table is cheaper than masking and converting eight corners.
// Doubles for the exact samples, floats for the batched ones.
template <class Real>
constexpr std::array<Real, 256> fillTable() {
  std::array<Real, 256> t{};
  for (uint32_t v = 0; v < 256; ++v) t[v] = Real(layout::voxelFill(v)) / Real(DS_FILL_FULL);
  return t;
}
constexpr std::array<double, 256> kFillOf = fillTable<double>();
constexpr std::array<float, 256> kFillOfFloat = fillTable<float>();
// A brick as the index tables give it: its voxels, or the value of a tile.
struct BrickRef {
  const Voxel* voxels = nullptr;
  Voxel tile = 0;
  Voxel at(uint32_t x, uint32_t y, uint32_t z) const {
    return voxels ? voxels[layout::brickCoordToOffset(x, y, z)] : tile;
  }
};

BrickRef lookupBrick(const BrickVolume& volume, uint32_t bx, uint32_t by, uint32_t bz) {
  BrickRef r;
  if (bx >= volume.brickDim() || by >= volume.brickDim() || bz >= volume.brickDim()) return r;  // outside: empty
  const uint32_t centry = volume.chunkWords()[layout::chunkCoordToIndex(bx >> DS_CHUNK_LOG2, by >> DS_CHUNK_LOG2,
                                                                        bz >> DS_CHUNK_LOG2, volume.chunkDim())];
  if (isTile(centry)) {
    r.tile = tileValue(centry);
    return r;
  }
  const uint32_t m = DS_CHUNK_DIM - 1;
  const uint32_t bentry = volume.blockWords()[size_t(centry & DS_ENTRY_INDEX_MASK) * DS_CHUNK_BRICKS +
                                              layout::brickCoordToOffset(bx & m, by & m, bz & m)];
  if (isTile(bentry)) {
    r.tile = tileValue(bentry);
    return r;
  }
  r.voxels = reinterpret_cast<const Voxel*>(volume.brickWords().data() +
                                            size_t(bentry & DS_ENTRY_INDEX_MASK) * DS_BRICK_WORDS);
  return r;
}
using Float4 = float __attribute__((vector_size(16)));
using Int4 = int32_t __attribute__((vector_size(16)));
Float4 load4(const float* p) {
  Float4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
}  // namespace

VoxelField::VoxelField(const BrickVolume& volume, const VolumeFrame& frame)
    : volume_(volume), frame_(frame), dim_(int64_t(volume.dim())), cache_(kSlots), copies_(size_t(kSlots) * kCopyBytes) {
  assert(frame.level == volume.level() && frame.voxel_mm > 0);
  findTissueBox();
}

void VoxelField::findTissueBox() {
  const BrickBox b = tissueBricks(volume_);
  if (b.empty()) {  // no tissue: a box no query meets
    tissue_lo_ = Vec3{1, 1, 1};
    tissue_hi_ = Vec3{-1, -1, -1};
    return;
  }
  tissue_lo_ = Vec3{double(b.lo.x), double(b.lo.y), double(b.lo.z)} * double(DS_BRICK_DIM);
  tissue_hi_ = Vec3{double(b.hi.x + 1), double(b.hi.y + 1), double(b.hi.z + 1)} * double(DS_BRICK_DIM);
}

void VoxelField::invalidate() {
  for (CachedBrick& e : cache_) e.key = kNoBrick;
  findTissueBox();
}

void VoxelField::load(uint32_t s, uint32_t bx, uint32_t by, uint32_t bz) {
  CachedBrick& e = cache_[s];
  e.key = brickKey(bx, by, bz);
  Voxel* const c = &copies_[size_t(s) * kCopyBytes];
  constexpr uint32_t n = DS_BRICK_DIM, sy = kSide, sz = kSide * kSide;
  const BrickRef own = lookupBrick(volume_, bx, by, bz);
  e.is_tile = own.voxels == nullptr;
  e.tile = own.tile;
  for (uint32_t z = 0; z < n; ++z)
    for (uint32_t y = 0; y < n; ++y) {
      Voxel* row = c + y * sy + z * sz;
      if (own.voxels)
        std::memcpy(row, own.voxels + layout::brickCoordToOffset(0, y, z), n);
      else
        std::memset(row, own.tile, n);
    }
  // The first layer of the +x, +y and +z neighbours, their shared edges and the far corner: a tile
  // fills its part, a dense brick is read without asking again per voxel.
  // Copy entry at + a step_a + b step_b takes the neighbour's voxel a from_a + b from_b.
  auto face = [&](const BrickRef& nb, uint32_t at, uint32_t step_a, uint32_t step_b, uint32_t from_a, uint32_t from_b,
                  uint32_t count_b) {
    for (uint32_t a = 0; a < n; ++a)
      for (uint32_t b = 0; b < count_b; ++b)
        c[at + a * step_a + b * step_b] = nb.voxels ? nb.voxels[a * from_a + b * from_b] : nb.tile;
  };
  constexpr uint32_t by_ = DS_BRICK_DIM, bz_ = DS_BRICK_DIM * DS_BRICK_DIM;  // a brick's own strides
  face(lookupBrick(volume_, bx + 1, by, bz), n, sy, sz, by_, bz_, n);               // x = 8: (y, z)
  face(lookupBrick(volume_, bx, by + 1, bz), n * sy, 1, sz, 1, bz_, n);             // y = 8: (x, z)
  face(lookupBrick(volume_, bx, by, bz + 1), n * sz, 1, sy, 1, by_, n);             // z = 8: (x, y)
  face(lookupBrick(volume_, bx + 1, by + 1, bz), n + n * sy, sz, 0, bz_, 0, 1);     // x = y = 8: z
  face(lookupBrick(volume_, bx + 1, by, bz + 1), n + n * sz, sy, 0, by_, 0, 1);     // x = z = 8: y
  face(lookupBrick(volume_, bx, by + 1, bz + 1), n * sy + n * sz, 1, 0, 1, 0, 1);   // y = z = 8: x
  const BrickRef corner = lookupBrick(volume_, bx + 1, by + 1, bz + 1);
  c[n + n * sy + n * sz] = corner.at(0, 0, 0);
}

void VoxelField::written(uint32_t x, uint32_t y, uint32_t z, Voxel v) {
  const uint32_t bx = x >> DS_BRICK_LOG2, by = y >> DS_BRICK_LOG2, bz = z >> DS_BRICK_LOG2;
  const uint32_t m = DS_BRICK_DIM - 1, lx = x & m, ly = y & m, lz = z & m;
  // The voxel is in its own brick's copy, and in the apron of the -x, -y, -z neighbours' when it
  // lies on the brick's low faces.
  const uint32_t ex = lx == 0 && bx > 0, ey = ly == 0 && by > 0, ez = lz == 0 && bz > 0;
  for (uint32_t dz = 0; dz <= ez; ++dz)
    for (uint32_t dy = 0; dy <= ey; ++dy)
      for (uint32_t dx = 0; dx <= ex; ++dx) {
        const uint32_t cx = bx - dx, cy = by - dy, cz = bz - dz;
        const uint32_t s = slot(cx, cy, cz);
        CachedBrick& e = cache_[s];
        if (e.key != brickKey(cx, cy, cz)) continue;
        if ((dx | dy | dz) == 0 && e.is_tile && v != e.tile) e.is_tile = false;
        copies_[size_t(s) * kCopyBytes + (lx + dx * DS_BRICK_DIM) + (ly + dy * DS_BRICK_DIM) * kSide +
                (lz + dz * DS_BRICK_DIM) * kSide * kSide] = v;
      }
}

Voxel VoxelField::voxel(int64_t x, int64_t y, int64_t z) {
  if (x < 0 || y < 0 || z < 0 || x >= dim_ || y >= dim_ || z >= dim_) return 0;
  const int64_t m = DS_BRICK_DIM - 1;
  return copy(uint32_t(x >> DS_BRICK_LOG2), uint32_t(y >> DS_BRICK_LOG2),
              uint32_t(z >> DS_BRICK_LOG2))[(x & m) + (y & m) * kSide + (z & m) * kSide * kSide];
}

bool VoxelField::cell(const Vec3& u, Voxel c[8], double t[3]) {
  const int64_t x0 = voxelFloor(u.x), y0 = voxelFloor(u.y), z0 = voxelFloor(u.z);
  t[0] = u.x - double(x0), t[1] = u.y - double(y0), t[2] = u.z - double(z0);
  // Unsigned, a negative coordinate is out of range too. A cell whose low corner is in the grid has
  // all eight in its brick's copy (the copies of the last bricks hold empty beyond the grid).
  const auto ux = uint64_t(x0), uy = uint64_t(y0), uz = uint64_t(z0), n = uint64_t(dim_);
  if ((ux < n) & (uy < n) & (uz < n)) {
    const uint64_t m = DS_BRICK_DIM - 1;
    const Voxel* const v =
        copy(uint32_t(ux >> DS_BRICK_LOG2), uint32_t(uy >> DS_BRICK_LOG2), uint32_t(uz >> DS_BRICK_LOG2)) +
        ((ux & m) + (uy & m) * kSide + (uz & m) * kSide * kSide);
    constexpr uint32_t dy = kSide, dz = kSide * kSide;
    c[0] = v[0], c[1] = v[1], c[2] = v[dy], c[3] = v[dy + 1];
    c[4] = v[dz], c[5] = v[dz + 1], c[6] = v[dz + dy], c[7] = v[dz + dy + 1];
  } else {
    for (int i = 0; i < 8; ++i) c[i] = voxel(x0 + (i & 1), y0 + ((i >> 1) & 1), z0 + ((i >> 2) & 1));
  }
  return (c[0] | c[1] | c[2] | c[3] | c[4] | c[5] | c[6] | c[7]) != 0;
}

void VoxelField::phiBatch(const float* ux, const float* uy, const float* uz, uint32_t n, float* phi) {
  const auto dim = uint32_t(dim_);
  constexpr float kFar = 1 << 30;  // keeps the conversion to integers defined
  for (uint32_t i = 0; i < n; i += 4) {
    Float4 u[3] = {load4(ux + i), load4(uy + i), load4(uz + i)};
    Int4 low[3];
    Float4 t[3];
    for (int a = 0; a < 3; ++a) {
      u[a] = u[a] < -kFar ? -kFar : (u[a] > kFar ? kFar : u[a]);
      const Int4 toward_zero = __builtin_convertvector(u[a], Int4);
      low[a] = toward_zero + (u[a] < __builtin_convertvector(toward_zero, Float4));  // floor: -1 where it rounded up
      t[a] = u[a] - __builtin_convertvector(low[a], Float4);
    }
    // The corners lane by lane, from the cell's brick copy; the fills as vectors again.
    alignas(16) float c[8][4];
    for (uint32_t k = 0; k < 4; ++k) {
      const auto x = uint32_t(low[0][k]), y = uint32_t(low[1][k]), z = uint32_t(low[2][k]);
      if ((x < dim) & (y < dim) & (z < dim)) {
        const uint32_t m = DS_BRICK_DIM - 1;
        const Voxel* const v = copy(x >> DS_BRICK_LOG2, y >> DS_BRICK_LOG2, z >> DS_BRICK_LOG2) +
                               ((x & m) + (y & m) * kSide + (z & m) * kSide * kSide);
        constexpr uint32_t dy = kSide, dz = kSide * kSide;
        c[0][k] = kFillOfFloat[v[0]], c[1][k] = kFillOfFloat[v[1]];
        c[2][k] = kFillOfFloat[v[dy]], c[3][k] = kFillOfFloat[v[dy + 1]];
        c[4][k] = kFillOfFloat[v[dz]], c[5][k] = kFillOfFloat[v[dz + 1]];
        c[6][k] = kFillOfFloat[v[dz + dy]], c[7][k] = kFillOfFloat[v[dz + dy + 1]];
      } else {
        for (int j = 0; j < 8; ++j)
          c[j][k] = kFillOfFloat[voxel(int64_t(low[0][k]) + (j & 1), int64_t(low[1][k]) + ((j >> 1) & 1),
                                       int64_t(low[2][k]) + (j >> 2))];
      }
    }
    Float4 f[8];
    for (int j = 0; j < 8; ++j) std::memcpy(&f[j], c[j], sizeof f[j]);
    const Float4 f00 = f[0] + t[0] * (f[1] - f[0]), f10 = f[2] + t[0] * (f[3] - f[2]);
    const Float4 f01 = f[4] + t[0] * (f[5] - f[4]), f11 = f[6] + t[0] * (f[7] - f[6]);
    const Float4 f0 = f00 + t[1] * (f10 - f00), f1 = f01 + t[1] * (f11 - f01);
    const Float4 out = f0 + t[2] * (f1 - f0) - 0.5f;
    std::memcpy(phi + i, &out, sizeof out);
  }
}

FieldSample VoxelField::sample(const Vec3& u, bool with_outside) {
  Voxel c[8];
  double t[3];
  if (!cell(u, c, t)) return FieldSample{};
  const double tx = t[0], ty = t[1], tz = t[2];
  double f[8];
  for (int i = 0; i < 8; ++i) f[i] = kFillOf[c[i]];
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
  if (s.phi <= 0) return s;

  // The tissue: the corner whose weighted fill is largest (the first of equals), picked without a
  // branch per corner, which a contact's corners would mispredict.
  double score[8];
  for (int i = 0; i < 8; ++i)
    score[i] = (((i & 1) ? tx : 1 - tx) * ((i & 2) ? ty : 1 - ty) * ((i & 4) ? tz : 1 - tz) + 1e-9) * f[i];
  int best = 0;
  for (int i = 1; i < 8; ++i) best = score[i] > score[best] ? i : best;
  s.material = voxelMaterial(c[best]);
  return s;
}

double VoxelField::clearance(const Vec3& u, double phi, bool look_around) {
  if (phi >= 0) return 0.0;
  // phi is trilinear in cells whose corners differ by at most 1, so it changes by at most sqrt(3)
  // per voxel: tissue is at least -phi / sqrt(3) away.
  constexpr double kInvSlope = 0.57735026918962576;
  if (phi > -0.5 || !look_around) return -phi * kInvSlope;
  // Nothing here: if every voxel within r of the cell is empty, phi = -1/2 on the box they span, and
  // tissue is at least the distance to the box's faces plus 1/(2 sqrt(3)) away.
  const int64_t x0 = voxelFloor(u.x), y0 = voxelFloor(u.y), z0 = voxelFloor(u.z);
  auto beyond = [&](int64_t r) {
    const double d = std::min({u.x - double(x0 - r), double(x0 + 1 + r) - u.x, u.y - double(y0 - r),
                               double(y0 + 1 + r) - u.y, u.z - double(z0 - r), double(z0 + 1 + r) - u.z});
    return d + 0.5 * kInvSlope;
  };
  double bound = 0.5 * kInvSlope;
  auto empty = [&](int64_t r, bool tiles_only) {
    return regionEmpty(x0 - r, x0 + 1 + r, y0 - r, y0 + 1 + r, z0 - r, z0 + 1 + r, tiles_only);
  };
  // Far from the tooth, a brick's width all round, from the index tables alone; near it, smaller
  // boxes voxel by voxel. Each box costs more, and the point skips longer for it.
  constexpr int64_t kFar = DS_BRICK_DIM;
  if (empty(kFar, true)) return beyond(kFar);
  for (const int64_t r : {int64_t{1}, int64_t{3}}) {
    if (!empty(r, false)) break;
    bound = beyond(r);
  }
  return bound;
}

bool VoxelField::regionEmpty(int64_t x0, int64_t x1, int64_t y0, int64_t y1, int64_t z0, int64_t z1,
                             bool tiles_only) {
  x0 = std::max<int64_t>(x0, 0), y0 = std::max<int64_t>(y0, 0), z0 = std::max<int64_t>(z0, 0);
  x1 = std::min(x1, dim_ - 1), y1 = std::min(y1, dim_ - 1), z1 = std::min(z1, dim_ - 1);
  if (x0 > x1 || y0 > y1 || z0 > z1) return true;
  const int64_t m = DS_BRICK_DIM - 1;
  for (int64_t bz = z0 >> DS_BRICK_LOG2; bz <= z1 >> DS_BRICK_LOG2; ++bz)
    for (int64_t by = y0 >> DS_BRICK_LOG2; by <= y1 >> DS_BRICK_LOG2; ++by)
      for (int64_t bx = x0 >> DS_BRICK_LOG2; bx <= x1 >> DS_BRICK_LOG2; ++bx) {
        // From the brick's copy when cached; otherwise from the volume itself, without making a copy
        // (the boxes reach far beyond the cells the step samples).
        const uint32_t s = slot(uint32_t(bx), uint32_t(by), uint32_t(bz));
        const CachedBrick& b = cache_[s];
        const bool cached = b.key == brickKey(uint32_t(bx), uint32_t(by), uint32_t(bz));
        const BrickRef ref = cached ? BrickRef{b.is_tile ? nullptr : &copies_[size_t(s) * kCopyBytes], b.tile}
                                    : lookupBrick(volume_, uint32_t(bx), uint32_t(by), uint32_t(bz));
        if (ref.voxels == nullptr) {
          if (ref.tile != 0) return false;
          continue;
        }
        if (tiles_only) return false;
        const int64_t row_y = cached ? kSide : DS_BRICK_DIM, row_z = cached ? kSide * kSide : DS_BRICK_DIM * DS_BRICK_DIM;
        // A brick row of 8 voxels is one 64-bit word: test the row's x range at once.
        const int64_t lx = std::max(x0, bx << DS_BRICK_LOG2) & m, hx = std::min(x1, (bx << DS_BRICK_LOG2) + m) & m;
        const uint64_t mask = (hx - lx == 7 ? ~0ull : ((uint64_t{1} << (8 * (hx - lx + 1))) - 1)) << (8 * lx);
        const int64_t ly = std::max(y0, by << DS_BRICK_LOG2) & m, hy = std::min(y1, (by << DS_BRICK_LOG2) + m) & m;
        const int64_t lz = std::max(z0, bz << DS_BRICK_LOG2) & m, hz = std::min(z1, (bz << DS_BRICK_LOG2) + m) & m;
        for (int64_t z = lz; z <= hz; ++z)
          for (int64_t y = ly; y <= hy; ++y) {
            uint64_t row;
            std::memcpy(&row, ref.voxels + y * row_y + z * row_z, sizeof row);
            if (row & mask) return false;
          }
      }
  return true;
}

bool VoxelField::chunksEmpty(const Vec3& lo, const Vec3& hi) const {
  if (hi.x < tissue_lo_.x || hi.y < tissue_lo_.y || hi.z < tissue_lo_.z || lo.x > tissue_hi_.x || lo.y > tissue_hi_.y ||
      lo.z > tissue_hi_.z)
    return true;
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
