// Ball carving on the brick volume: brick-at-a-time edits that visit only the ball's bounding box.
#include "volume/volume_edit.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

namespace dentsim {
namespace {

// The ball in grid units (one voxel = 1, voxel (i,j,k) centred at i+0.5, ...), with the two radii
// that bound the soft shell: inside r_in a voxel loses everything, beyond r_out nothing.
struct GridBall {
  double cx = 0, cy = 0, cz = 0;  // centre [voxels]
  double r = 0;                   // radius [voxels]
  double r_out2 = 0;              // (r + 1/2)^2 [voxels^2]
  double r_in2 = -1;              // (r - 1/2)^2, or -1 when the ball is thinner than one voxel [voxels^2]
};

// Half-open index range [lo, hi) of voxel centres within `reach` of `centre` along one axis,
// clipped to [0, dim). It is widened by one on each side, since the per-voxel test decides, and
// clamped as doubles, so that a ball far off the grid converts no out-of-range value to an integer.
void axisRange(double centre, double reach, uint32_t dim, int64_t* lo, int64_t* hi) {
  *lo = int64_t(std::clamp(std::floor(centre - reach - 0.5) - 1.0, 0.0, double(dim)));
  *hi = int64_t(std::clamp(std::ceil(centre + reach - 0.5) + 2.0, 0.0, double(dim)));
}

// The cap on a voxel's fill at squared distance d2 from the centre: round(31 * (1 - c)) with
// c = clamp(0.5 - d, 0, 1) and d the signed distance to the sphere in voxels.
uint32_t fillCap(const GridBall& b, double d2) {
  if (d2 >= b.r_out2) return DS_FILL_FULL;
  if (d2 <= b.r_in2) return 0;
  const double keep = std::clamp(0.5 + (std::sqrt(d2) - b.r), 0.0, 1.0);
  return uint32_t(DS_FILL_FULL * keep + 0.5);  // keep >= 0: rounds half up, as lround would
}

// What an edit changed so far, summed brick by brick.
struct Tally {
  uint64_t voxels = 0;  // voxels whose byte changed
  uint64_t fill = 0;    // fill removed [1/31 voxel]
};

// Squared distances from the ball centre to the nearest point of a brick's box and to its
// farthest voxel centre [voxels^2].
double brickNear2(const GridBall& b, BrickCoord c) {
  const double lo[3] = {double(c.x) * DS_BRICK_DIM, double(c.y) * DS_BRICK_DIM, double(c.z) * DS_BRICK_DIM};
  const double p[3] = {b.cx, b.cy, b.cz};
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double g = std::max({lo[a] - p[a], 0.0, p[a] - (lo[a] + DS_BRICK_DIM)});
    d2 += g * g;
  }
  return d2;
}
double brickFar2(const GridBall& b, BrickCoord c) {
  const double lo[3] = {double(c.x) * DS_BRICK_DIM, double(c.y) * DS_BRICK_DIM, double(c.z) * DS_BRICK_DIM};
  const double p[3] = {b.cx, b.cy, b.cz};
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double g = std::max(std::abs(lo[a] + 0.5 - p[a]), std::abs(lo[a] + DS_BRICK_DIM - 0.5 - p[a]));
    d2 += g * g;
  }
  return d2;
}

// Carves one brick's copy in place over the voxel box [lo, hi) (grid indices inside this brick).
// Rows are at most 8 voxels, so each voxel is tested directly rather than through the chord of the
// sphere: a square root and rounding per row cost more than eight multiply-adds. The sums stay in
// locals because stores through a byte pointer may alias anything, so a Tally field would go back
// to memory on every voxel.
void carveBrick(const GridBall& b, const int64_t lo[3], const int64_t hi[3], Voxel* voxels, Tally* t) {
  const uint32_t m = DS_BRICK_DIM - 1;
  double dx2[DS_BRICK_DIM];  // squared x distance of each column of the box [voxels^2]
  for (int64_t x = lo[0]; x < hi[0]; ++x) {
    const double dx = double(x) + 0.5 - b.cx;
    dx2[x & m] = dx * dx;
  }
  uint64_t changed = 0, removed = 0;
  for (int64_t z = lo[2]; z < hi[2]; ++z) {
    const double dz = double(z) + 0.5 - b.cz;
    for (int64_t y = lo[1]; y < hi[1]; ++y) {
      const double dy = double(y) + 0.5 - b.cy;
      const double dyz2 = dy * dy + dz * dz;
      if (dyz2 >= b.r_out2) continue;
      Voxel* row = voxels + layout::brickCoordToOffset(0, uint32_t(y) & m, uint32_t(z) & m);
      for (int64_t x = lo[0]; x < hi[0]; ++x) {
        Voxel& v = row[x & m];
        const uint32_t fill = voxelFill(v);
        if (fill == 0) continue;  // empty stays empty
        const uint32_t cap = fillCap(b, dx2[x & m] + dyz2);
        if (cap >= fill) continue;
        removed += fill - cap;
        changed += 1;
        v = cap == 0 ? Voxel(0) : makeVoxel(voxelMaterial(v), cap);
      }
    }
  }
  t->voxels += changed;
  t->fill += removed;
}

}  // namespace

EditResult carveBall(BrickVolume& volume, const VolumeFrame& frame, const std::array<double, 3>& centre_mm,
                     double radius_mm) {
  assert(frame.level == volume.level());
  assert(frame.voxel_mm > 0.0);
  assert(radius_mm >= 0.0 && std::isfinite(radius_mm));
  assert(std::isfinite(centre_mm[0]) && std::isfinite(centre_mm[1]) && std::isfinite(centre_mm[2]));
  EditResult result;

  const double h = frame.voxel_mm;
  GridBall b;
  b.cx = (centre_mm[0] - frame.origin_mm[0]) / h;
  b.cy = (centre_mm[1] - frame.origin_mm[1]) / h;
  b.cz = (centre_mm[2] - frame.origin_mm[2]) / h;
  b.r = radius_mm / h;
  b.r_out2 = (b.r + 0.5) * (b.r + 0.5);
  if (b.r > 0.5) b.r_in2 = (b.r - 0.5) * (b.r - 0.5);

  // Voxel box of the shell's outer sphere, clipped to the grid; nothing to do when it misses.
  const uint32_t dim = volume.dim();
  const double reach = b.r + 0.5;
  int64_t lo[3], hi[3];
  axisRange(b.cx, reach, dim, &lo[0], &hi[0]);
  axisRange(b.cy, reach, dim, &lo[1], &hi[1]);
  axisRange(b.cz, reach, dim, &lo[2], &hi[2]);
  if (lo[0] >= hi[0] || lo[1] >= hi[1] || lo[2] >= hi[2]) return result;

  Tally total;
  alignas(16) Voxel copy[DS_BRICK_VOXELS];
  // Bricks in (z, y, x) order, so the dirty list comes out sorted and unique.
  for (int64_t bz = lo[2] >> DS_BRICK_LOG2; bz <= (hi[2] - 1) >> DS_BRICK_LOG2; ++bz)
    for (int64_t by = lo[1] >> DS_BRICK_LOG2; by <= (hi[1] - 1) >> DS_BRICK_LOG2; ++by)
      for (int64_t bx = lo[0] >> DS_BRICK_LOG2; bx <= (hi[0] - 1) >> DS_BRICK_LOG2; ++bx) {
        const BrickCoord c{uint32_t(bx), uint32_t(by), uint32_t(bz)};
        // Corner bricks of the box often lie wholly outside the shell; they cost no read.
        if (brickNear2(b, c) >= b.r_out2) continue;
        const BrickView view = volume.brick(c);
        if (view.uniform && view.value == 0) continue;
        Tally t;
        if (brickFar2(b, c) < b.r_in2) {
          // Wholly inside the inner sphere: the brick becomes an empty tile without a copy.
          if (view.uniform) {
            t.voxels = DS_BRICK_VOXELS;
            t.fill = uint64_t(DS_BRICK_VOXELS) * voxelFill(view.value);
          } else {
            for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
              t.fill += voxelFill(view.voxels[i]);
              t.voxels += view.voxels[i] != 0 ? 1 : 0;
            }
          }
          volume.setBrickUniform(c, 0);
        } else {
          if (view.uniform) std::memset(copy, view.value, DS_BRICK_VOXELS);
          else std::memcpy(copy, view.voxels, DS_BRICK_VOXELS);
          int64_t blo[3], bhi[3];
          const int64_t base[3] = {bx << DS_BRICK_LOG2, by << DS_BRICK_LOG2, bz << DS_BRICK_LOG2};
          for (int a = 0; a < 3; ++a) {
            blo[a] = std::max(lo[a], base[a]);
            bhi[a] = std::min(hi[a], base[a] + int64_t(DS_BRICK_DIM));
          }
          carveBrick(b, blo, bhi, copy, &t);
          if (t.voxels != 0) volume.setBrick(c, copy);
        }
        if (t.voxels == 0) continue;
        total.voxels += t.voxels;
        total.fill += t.fill;
        result.dirty.push_back(c);
      }
  result.voxels_changed = total.voxels;
  result.removed_mm3 = double(total.fill) / DS_FILL_FULL * frame.voxelVolumeMm3();
  return result;
}

}  // namespace dentsim
