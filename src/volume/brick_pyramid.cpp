// Coarse copies of a brick volume, brick by brick, with whole empty or solid chunks copied as tiles.
#include "volume/brick_pyramid.h"
#include "volume/half_fill.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <optional>
#include <tuple>

namespace dentsim {

namespace {

// Summed fill per material beneath one coarse voxel; f^3 * 31 <= 512 * 31 fits 16 bits.
using FillSums = std::array<uint16_t, DS_MATERIAL_COUNT>;

Voxel coarseFromSums(const FillSums& sums, uint32_t count) {
  uint32_t total = 0, best = 0;
  size_t best_material = 0;
  for (size_t m = 1; m < sums.size(); ++m) {
    total += sums[m];
    if (sums[m] > best) {
      best = sums[m];
      best_material = m;
    }
  }
  const uint32_t fill = (total + count / 2) / count;
  if (fill == 0) return makeVoxel(Material::Empty);
  return makeVoxel(Material(best_material), fill);
}

// A voxel as the coarse rule sees f^3 copies of it: the same tissue and fill, or empty at fill 0.
Voxel normalised(Voxel v) { return voxelFill(v) == 0 ? makeVoxel(Material::Empty) : v; }

// Rewrites coarse brick c from the f^3 full bricks beneath it.
void downsampleBrick(const BrickVolume& fine, uint32_t k, BrickCoord c, BrickVolume& coarse) {
  const uint32_t f = 1u << k;
  const uint32_t per = DS_BRICK_DIM / f;  // coarse voxels per axis that one full brick covers (0 when f > 8)
  std::array<BrickView, 512> views;
  bool all_same = true;
  uint32_t n = 0;
  // f <= 8 here: k is at most 3 (see downsampleVolume), so f^3 <= 512 full bricks.
  for (uint32_t z = 0; z < f; ++z)
    for (uint32_t y = 0; y < f; ++y)
      for (uint32_t x = 0; x < f; ++x) {
        views[n] = fine.brick({c.x * f + x, c.y * f + y, c.z * f + z});
        all_same = all_same && views[n].uniform && views[n].value == views[0].value;
        ++n;
      }
  if (all_same) {
    coarse.setBrickUniform(c, normalised(views[0].value));
    return;
  }
  std::array<FillSums, DS_BRICK_VOXELS> sums{};
  n = 0;
  for (uint32_t z = 0; z < f; ++z)
    for (uint32_t y = 0; y < f; ++y)
      for (uint32_t x = 0; x < f; ++x) {
        const BrickView& v = views[n++];
        if (v.uniform) {
          const uint32_t fill = voxelFill(v.value);
          if (fill == 0) continue;
          const size_t m = size_t(voxelMaterial(v.value));
          // The full brick covers a per^3 box of coarse voxels, each over f^3 of its voxels.
          const uint32_t under = f * f * f;
          for (uint32_t cz = 0; cz < per; ++cz)
            for (uint32_t cy = 0; cy < per; ++cy)
              for (uint32_t cx = 0; cx < per; ++cx)
                sums[layout::brickCoordToOffset(x * per + cx, y * per + cy, z * per + cz)][m] +=
                    uint16_t(fill * under);
          continue;
        }
        for (uint32_t vz = 0; vz < DS_BRICK_DIM; ++vz)
          for (uint32_t vy = 0; vy < DS_BRICK_DIM; ++vy) {
            const Voxel* row = v.voxels + layout::brickCoordToOffset(0, vy, vz);
            const uint32_t cy = (y * DS_BRICK_DIM + vy) / f, cz = (z * DS_BRICK_DIM + vz) / f;
            for (uint32_t vx = 0; vx < DS_BRICK_DIM; ++vx) {
              const Voxel voxel = row[vx];
              const uint32_t fill = voxelFill(voxel);
              if (fill == 0) continue;
              sums[layout::brickCoordToOffset((x * DS_BRICK_DIM + vx) / f, cy, cz)][size_t(voxelMaterial(voxel))] +=
                  uint16_t(fill);
            }
          }
      }
  std::array<Voxel, DS_BRICK_VOXELS> out;
  for (size_t i = 0; i < out.size(); ++i) out[i] = coarseFromSums(sums[i], f * f * f);
  coarse.setBrick(c, out.data());
}

}  // namespace

Voxel coarseVoxelReference(const BrickVolume& fine, uint32_t x, uint32_t y, uint32_t z, uint32_t k) {
  const uint32_t f = 1u << k;
  FillSums sums{};
  for (uint32_t dz = 0; dz < f; ++dz)
    for (uint32_t dy = 0; dy < f; ++dy)
      for (uint32_t dx = 0; dx < f; ++dx) {
        const Voxel v = fine.voxel(x + dx, y + dy, z + dz);
        sums[size_t(voxelMaterial(v))] += uint16_t(voxelFill(v));
      }
  sums[size_t(Material::Empty)] = 0;
  return coarseFromSums(sums, f * f * f);
}

BrickVolume downsampleVolume(const BrickVolume& fine, uint32_t k) {
  assert(k >= 1 && k <= 3 && fine.level() - int(k) >= DS_MIN_LEVEL);
  const uint32_t f = 1u << k;
  BrickVolume coarse(fine.level() - int(k));
  const uint32_t cbd = coarse.brickDim(), fcd = fine.chunkDim();
  for (uint32_t cz = 0; cz < coarse.chunkDim(); ++cz)
    for (uint32_t cy = 0; cy < coarse.chunkDim(); ++cy)
      for (uint32_t cx = 0; cx < coarse.chunkDim(); ++cx) {
        // The coarse chunk's bricks, and the full chunks beneath them.
        const uint32_t lo[3] = {cx * DS_CHUNK_DIM, cy * DS_CHUNK_DIM, cz * DS_CHUNK_DIM};
        uint32_t hi[3], flo[3], fhi[3];
        for (int a = 0; a < 3; ++a) {
          hi[a] = std::min(lo[a] + DS_CHUNK_DIM, cbd);
          flo[a] = lo[a] * f / DS_CHUNK_DIM;
          fhi[a] = std::min(fcd, (hi[a] * f + DS_CHUNK_DIM - 1) / DS_CHUNK_DIM);
        }
        std::optional<Voxel> tile;
        bool tiled = true;
        for (uint32_t z = flo[2]; z < fhi[2] && tiled; ++z)
          for (uint32_t y = flo[1]; y < fhi[1] && tiled; ++y)
            for (uint32_t x = flo[0]; x < fhi[0] && tiled; ++x) {
              const std::optional<Voxel> t = fine.chunkTile(x, y, z);
              tiled = t && (!tile || *t == *tile);
              if (tiled) tile = t;
            }
        if (tiled && tile) {
          coarse.setChunkUniform(cx, cy, cz, normalised(*tile));
          continue;
        }
        for (uint32_t z = lo[2]; z < hi[2]; ++z)
          for (uint32_t y = lo[1]; y < hi[1]; ++y)
            for (uint32_t x = lo[0]; x < hi[0]; ++x) downsampleBrick(fine, k, {x, y, z}, coarse);
      }
  return coarse;
}

std::vector<BrickCoord> downsampleBricks(const BrickVolume& fine, uint32_t k, std::span<const BrickCoord> fine_dirty,
                                         BrickVolume& coarse) {
  assert(coarse.level() == fine.level() - int(k));
  std::vector<BrickCoord> out;
  out.reserve(fine_dirty.size());
  for (const BrickCoord& b : fine_dirty) out.push_back({b.x >> k, b.y >> k, b.z >> k});
  const auto key = [](const BrickCoord& b) { return std::tuple(b.z, b.y, b.x); };
  std::sort(out.begin(), out.end(), [&](const BrickCoord& a, const BrickCoord& b) { return key(a) < key(b); });
  out.erase(std::unique(out.begin(), out.end(), [&](const BrickCoord& a, const BrickCoord& b) { return key(a) == key(b); }),
            out.end());
  for (const BrickCoord& c : out) downsampleBrick(fine, k, c, coarse);
  return out;
}

}  // namespace dentsim

namespace dentsim {

namespace {


// Where along an edge from fill fa to fb (one inside, one not) marching cubes puts the vertex, in
// [0, 1] from the first voxel's centre: the same t the mesher computes.
double crossingT(uint32_t fa, uint32_t fb) {
  return (double(DS_FILL_FULL) - 2.0 * double(fa)) / (2.0 * (double(fb) - double(fa)));
}

// The distance from position p (full voxels, along `axis`) to the nearest crossing of the full fill
// on the row of full voxels at `row` (the other two coordinates), looking `window` voxels each way.
double nearestFullCrossing(const BrickVolume& full, int axis, const int64_t row[3], double p, double window) {
  const int64_t dim = int64_t(full.dim());
  const int64_t lo = std::max<int64_t>(0, int64_t(std::floor(p - 0.5 - window)));
  const int64_t hi = std::min<int64_t>(dim - 1, int64_t(std::ceil(p - 0.5 + window)));
  double best = window;
  int64_t at[3] = {row[0], row[1], row[2]};
  at[axis] = lo;
  uint32_t prev = voxelFill(full.voxel(uint32_t(at[0]), uint32_t(at[1]), uint32_t(at[2])));
  for (int64_t i = lo + 1; i <= hi; ++i) {
    at[axis] = i;
    const uint32_t cur = voxelFill(full.voxel(uint32_t(at[0]), uint32_t(at[1]), uint32_t(at[2])));
    if ((prev >= kHalfFill) != (cur >= kHalfFill)) {
      const double q = double(i - 1) + 0.5 + crossingT(prev, cur);
      best = std::min(best, std::fabs(q - p));
    }
    prev = cur;
  }
  return best;
}

// Whether a brick holds both inside and outside voxels (so surface passes through it).
bool holdsSurface(const BrickView& b) {
  if (b.uniform) return false;
  bool in = false, out = false;
  for (uint32_t i = 0; i < DS_BRICK_VOXELS && !(in && out); ++i) (isHalfFull(b.voxels[i]) ? in : out) = true;
  return in && out;
}

}  // namespace

void measureCopyError(const BrickVolume& full, const BrickVolume& coarse, uint32_t k, uint32_t region_bricks,
                      std::span<const uint8_t> only, std::vector<float>& error) {
  const uint32_t region_voxels = region_bricks * DS_BRICK_DIM;
  const uint32_t rd = (full.brickDim() + region_bricks - 1) / region_bricks;
  const size_t regions = size_t(rd) * rd * rd;
  if (error.size() != regions) error.assign(regions, 0.0f);
  const auto measured = [&](size_t r) { return only.empty() || only[r]; };
  // Per measured region: the sum of squared vertex distances and their count, and the lost-feature
  // floor; the error is the root mean square, or the floor when that is larger.
  std::vector<double> sum2(regions, 0.0);
  std::vector<uint32_t> count(regions, 0);
  std::vector<float> lost(regions, 0.0f);
  const uint32_t f = 1u << k;
  const double window = double(2u * f);
  const auto region_of = [&](const double p[3]) {
    size_t r[3];
    for (int a = 0; a < 3; ++a) r[a] = std::min<size_t>(rd - 1, size_t(std::max(0.0, p[a]) / double(region_voxels)));
    return (r[2] * rd + r[1]) * rd + r[0];
  };
  const int64_t cdim = int64_t(coarse.dim());
  // The region of full brick (x, y, z).
  const auto region_of_full_brick = [&](uint32_t x, uint32_t y, uint32_t z) {
    return (size_t(std::min(z / region_bricks, rd - 1)) * rd + std::min(y / region_bricks, rd - 1)) * rd +
           std::min(x / region_bricks, rd - 1);
  };
  const auto visit = [&](const BrickView& b) {
    // Only bricks over a measured region: a coarse brick covers f^3 full bricks, in one region or
    // (f above the region's side) several.
    bool any = false;
    for (uint32_t z = 0; z < f && !any; z += region_bricks)
      for (uint32_t y = 0; y < f && !any; y += region_bricks)
        for (uint32_t x = 0; x < f && !any; x += region_bricks)
          any = measured(region_of_full_brick(b.coord.x * f + x, b.coord.y * f + y, b.coord.z * f + z));
    if (!any) return;
    if (!holdsSurface(b)) {
      // A copy with no surface here or next to it: any full brick beneath that holds surface is a
      // feature the copy lost. (Next to it, the copy's surface may just cross the brick border
      // elsewhere than the full one does; its vertices are measured there.)
      bool near_surface = false;
      const int64_t cb = int64_t(coarse.brickDim());
      for (int64_t dz = -1; dz <= 1 && !near_surface; ++dz)
        for (int64_t dy = -1; dy <= 1 && !near_surface; ++dy)
          for (int64_t dx = -1; dx <= 1 && !near_surface; ++dx) {
            const int64_t x = int64_t(b.coord.x) + dx, y = int64_t(b.coord.y) + dy, z = int64_t(b.coord.z) + dz;
            if ((dx | dy | dz) == 0 || x < 0 || y < 0 || z < 0 || x >= cb || y >= cb || z >= cb) continue;
            near_surface = holdsSurface(coarse.brick({uint32_t(x), uint32_t(y), uint32_t(z)}));
          }
      if (near_surface) {
        if (b.uniform) return;
      } else {
      for (uint32_t z = 0; z < f; ++z)
        for (uint32_t y = 0; y < f; ++y)
          for (uint32_t x = 0; x < f; ++x)
            if (holdsSurface(full.brick({b.coord.x * f + x, b.coord.y * f + y, b.coord.z * f + z}))) {
              const size_t r = region_of_full_brick(b.coord.x * f + x, b.coord.y * f + y, b.coord.z * f + z);
              if (measured(r)) lost[r] = float(window);
            }
      }
      if (b.uniform) return;
    }
    for (uint32_t vz = 0; vz < DS_BRICK_DIM; ++vz)
      for (uint32_t vy = 0; vy < DS_BRICK_DIM; ++vy)
        for (uint32_t vx = 0; vx < DS_BRICK_DIM; ++vx) {
          const int64_t c[3] = {int64_t(b.coord.x * DS_BRICK_DIM + vx), int64_t(b.coord.y * DS_BRICK_DIM + vy),
                                int64_t(b.coord.z * DS_BRICK_DIM + vz)};
          const Voxel here = b.voxels[layout::brickCoordToOffset(vx, vy, vz)];
          for (int axis = 0; axis < 3; ++axis) {
            if (c[axis] + 1 >= cdim) continue;
            int64_t n[3] = {c[0], c[1], c[2]};
            ++n[axis];
            const uint32_t local[3] = {vx, vy, vz};
            const Voxel there = local[axis] + 1 < DS_BRICK_DIM
                                    ? b.voxels[layout::brickCoordToOffset(vx + (axis == 0), vy + (axis == 1), vz + (axis == 2))]
                                    : coarse.voxel(uint32_t(n[0]), uint32_t(n[1]), uint32_t(n[2]));
            if (isHalfFull(here) == isHalfFull(there)) continue;
            // The coarse vertex in full voxels, and the full row through it (the lower of the two
            // rows its other coordinates fall between).
            double p[3];
            int64_t row[3];
            for (int a = 0; a < 3; ++a) {
              p[a] = (double(c[a]) + 0.5) * double(f);
              row[a] = std::min<int64_t>(int64_t(full.dim()) - 1, int64_t(std::floor(p[a] - 0.5)));
            }
            p[axis] += crossingT(voxelFill(here), voxelFill(there)) * double(f);
            // Along the edge's axis, then across the surface: times the normal's share of the axis
            // (the copy's fill gradient at the edge), so that a surface grazing the axis, whose
            // crossing on a row beside the vertex moves far along it, is not counted as far off.
            double g[3], g2 = 0.0;
            for (int a = 0; a < 3; ++a) {
              int64_t lo[3] = {c[0], c[1], c[2]}, hi[3] = {n[0], n[1], n[2]};
              --lo[a];
              ++hi[a];
              // Clamped at the grid's faces, so that they add no gradient of their own.
              const auto fill_at = [&](const int64_t q[3]) {
                const auto at = [&](int i) { return uint32_t(std::clamp<int64_t>(q[i], 0, cdim - 1)); };
                return double(voxelFill(coarse.voxel(at(0), at(1), at(2))));
              };
              // Central differences at both ends of the edge, summed: the gradient at its middle.
              int64_t c_hi[3] = {c[0], c[1], c[2]}, n_lo[3] = {n[0], n[1], n[2]};
              ++c_hi[a];
              --n_lo[a];
              g[a] = fill_at(c_hi) - fill_at(lo) + fill_at(hi) - fill_at(n_lo);
              g2 += g[a] * g[a];
            }
            const double share = g2 > 0.0 ? std::fabs(g[axis]) / std::sqrt(g2) : 1.0;
            const double d = nearestFullCrossing(full, axis, row, p[axis], window) * share;
            const size_t r = region_of(p);
            if (!measured(r)) continue;
            sum2[r] += d * d;
            ++count[r];
          }
        }
  };
  if (only.empty()) {
    coarse.forEachBrick(visit);
  } else {
    // Only the coarse bricks over flagged regions: a settle after a cut measures a few regions, and
    // walking every brick of the copy for them would cost more than the measuring.
    const uint32_t cbd = coarse.brickDim();
    std::vector<uint8_t> seen(size_t(cbd) * cbd * cbd, 0);
    for (size_t r = 0; r < regions; ++r) {
      if (!only[r]) continue;
      const uint32_t at[3] = {uint32_t(r % rd), uint32_t(r / rd % rd), uint32_t(r / rd / rd)};
      uint32_t lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        lo[a] = at[a] * region_bricks / f;
        hi[a] = std::min(cbd, ((at[a] + 1) * region_bricks + f - 1) / f);
      }
      for (uint32_t z = lo[2]; z < hi[2]; ++z)
        for (uint32_t y = lo[1]; y < hi[1]; ++y)
          for (uint32_t x = lo[0]; x < hi[0]; ++x) {
            uint8_t& mark = seen[(size_t(z) * cbd + y) * cbd + x];
            if (mark) continue;
            mark = 1;
            visit(coarse.brick({x, y, z}));
          }
    }
  }
  for (size_t r = 0; r < regions; ++r)
    if (measured(r))
      error[r] = std::max(lost[r], count[r] ? float(std::sqrt(sum2[r] / double(count[r]))) : 0.0f);
}

}  // namespace dentsim
