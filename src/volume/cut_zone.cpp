// The cut zone: target masks, the caries' access footprint, and the leeway's exact distances per brick.
#include "volume/cut_zone.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>

namespace dentsim {

// ---- 1. target masks -----------------------------------------------------------------------------

std::vector<uint64_t> TargetMasks::bricks() const {
  std::vector<uint64_t> out;
  out.reserve(masks_.size());
  for (const auto& [brick, mask] : masks_) out.push_back(brick);
  std::sort(out.begin(), out.end());
  return out;
}

// ---- 2. the caries' access -------------------------------------------------------------------------

namespace {

// Lines along the axis through the grid. With a the axis's largest component and sigma its sign,
// a line steps one voxel along a per (du, dv) across: every voxel p on the line from q satisfies
// p[u] - sigma p[a] du = q[u] - sigma q[a] du (likewise v), so that pair, rounded, names the line
// (its footprint cell), and t = sigma p[a] says how far along it p lies. All voxels of one slice
// share the rounding's fraction, so a solid cross-section has a solid footprint.
struct AxisLines {
  int a = 2, u = 0, v = 1;
  int sigma = 1;
  double du = 0.0, dv = 0.0;

  explicit AxisLines(const Vec3& axis) {
    for (int k = 1; k < 3; ++k)
      if (std::abs(axis[k]) > std::abs(axis[a])) a = k;
    // Ties keep the last of x, y, z: an axis of +z stays the plain column case.
    if (std::abs(axis[2]) == std::abs(axis[a])) a = 2;
    u = (a + 1) % 3;
    v = (a + 2) % 3;
    sigma = axis[a] >= 0 ? 1 : -1;
    du = axis[u] / std::abs(axis[a]);
    dv = axis[v] / std::abs(axis[a]);
  }
  int64_t cellU(const std::array<int64_t, 3>& p) const { return roundHalfUp(double(p[size_t(u)]) - sigma * double(p[size_t(a)]) * du); }
  int64_t cellV(const std::array<int64_t, 3>& p) const { return roundHalfUp(double(p[size_t(v)]) - sigma * double(p[size_t(a)]) * dv); }
  int64_t along(const std::array<int64_t, 3>& p) const { return sigma * p[size_t(a)]; }
  static int64_t roundHalfUp(double x) { return int64_t(std::floor(x + 0.5)); }
};

// The lowest `along` of a caries voxel in each footprint cell, over the cells' bounding rectangle.
class Footprint {
 public:
  static constexpr int64_t kNone = std::numeric_limits<int64_t>::max();

  void build(const std::vector<std::array<int64_t, 3>>& cells) {  // (cell u, cell v, along)
    for (const auto& c : cells) {
      lo_u_ = std::min(lo_u_, c[0]);
      hi_u_ = std::max(hi_u_, c[0]);
      lo_v_ = std::min(lo_v_, c[1]);
      hi_v_ = std::max(hi_v_, c[1]);
      min_along_ = std::min(min_along_, c[2]);
    }
    if (cells.empty()) return;
    width_ = hi_u_ - lo_u_ + 1;
    first_.assign(size_t(width_ * (hi_v_ - lo_v_ + 1)), kNone);
    for (const auto& c : cells) {
      int64_t& f = first_[size_t((c[0] - lo_u_) + width_ * (c[1] - lo_v_))];
      f = std::min(f, c[2]);
    }
  }
  bool empty() const { return first_.empty(); }
  // Could a voxel with cells in [u0, u1] x [v0, v1] and along <= max_along be on a line?
  bool mayHold(int64_t u0, int64_t u1, int64_t v0, int64_t v1, int64_t max_along) const {
    return !empty() && u1 >= lo_u_ && u0 <= hi_u_ && v1 >= lo_v_ && v0 <= hi_v_ && max_along >= min_along_;
  }
  bool holds(int64_t cu, int64_t cv, int64_t along) const {
    if (cu < lo_u_ || cu > hi_u_ || cv < lo_v_ || cv > hi_v_) return false;
    const int64_t f = first_[size_t((cu - lo_u_) + width_ * (cv - lo_v_))];
    return f != kNone && along >= f;
  }

 private:
  int64_t lo_u_ = std::numeric_limits<int64_t>::max(), hi_u_ = std::numeric_limits<int64_t>::min();
  int64_t lo_v_ = std::numeric_limits<int64_t>::max(), hi_v_ = std::numeric_limits<int64_t>::min();
  int64_t min_along_ = std::numeric_limits<int64_t>::max();
  int64_t width_ = 0;
  std::vector<int64_t> first_;
};

bool isCaries(Voxel v) { return layout::voxelMaterial(v) == DS_MAT_CARIES && voxelFill(v) > 0; }
// An adjacent tooth's voxel: never target nor allowed, since the exercise is on the treated tooth.
bool isNeighbour(Voxel v) { return layout::voxelMaterial(v) == DS_MAT_NEIGHBOUR && voxelFill(v) > 0; }

}  // namespace

void markCariesAccess(const BrickVolume& initial, const Vec3& axis, uint32_t brick_reach, TargetMasks* masks) {
  assert(norm(axis) > 0.5);
  const AxisLines lines(axis);
  std::vector<std::array<int64_t, 3>> cells;
  initial.forEachBrick([&](const BrickView& b) {
    if (b.uniform && !isCaries(b.value)) return;
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
      if (!isCaries(b.uniform ? b.value : b.voxels[n])) continue;
      const std::array<int64_t, 3> p{int64_t(b.coord.x * DS_BRICK_DIM + (n & 7u)),
                                     int64_t(b.coord.y * DS_BRICK_DIM + ((n >> 3) & 7u)),
                                     int64_t(b.coord.z * DS_BRICK_DIM + (n >> 6))};
      cells.push_back({lines.cellU(p), lines.cellV(p), lines.along(p)});
    }
  });
  Footprint footprint;
  footprint.build(cells);
  if (footprint.empty()) return;

  const BrickBox tissue = tissueBricks(initial);
  if (tissue.empty()) return;
  const int64_t bd = initial.brickDim();
  auto lo = [&](uint32_t c) { return uint32_t(std::max<int64_t>(0, int64_t(c) - brick_reach)); };
  auto hi = [&](uint32_t c) { return uint32_t(std::min<int64_t>(bd - 1, int64_t(c) + brick_reach)); };
  const double spread_u = std::abs(lines.du) * (DS_BRICK_DIM - 1), spread_v = std::abs(lines.dv) * (DS_BRICK_DIM - 1);
  for (uint32_t bz = lo(tissue.lo.z); bz <= hi(tissue.hi.z); ++bz)
    for (uint32_t by = lo(tissue.lo.y); by <= hi(tissue.hi.y); ++by)
      for (uint32_t bx = lo(tissue.lo.x); bx <= hi(tissue.hi.x); ++bx) {
        const BrickCoord b{bx, by, bz};
        // The brick's cells lie within its first voxel's cells, widened by the slant over 8 slices.
        const std::array<int64_t, 3> first{int64_t(bx * DS_BRICK_DIM), int64_t(by * DS_BRICK_DIM), int64_t(bz * DS_BRICK_DIM)};
        const int64_t cu = lines.cellU(first), cv = lines.cellV(first);
        const int64_t max_along = lines.along(first) + (lines.sigma > 0 ? int64_t(DS_BRICK_DIM) - 1 : 0);
        const auto su = int64_t(std::ceil(spread_u)) + 1, sv = int64_t(std::ceil(spread_v)) + 1;
        if (!footprint.mayHold(cu - su - 1, cu + DS_BRICK_DIM + su, cv - sv - 1, cv + DS_BRICK_DIM + sv, max_along))
          continue;
        // A line that runs on into an adjacent tooth does not take it: the access is through the
        // treated tooth only.
        const BrickView view = initial.brick(b);
        for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
          const std::array<int64_t, 3> p{first[0] + (n & 7u), first[1] + ((n >> 3) & 7u), first[2] + (n >> 6)};
          if (footprint.holds(lines.cellU(p), lines.cellV(p), lines.along(p)) && !isNeighbour(view.at(n))) masks->set(b, n);
        }
      }
}

// ---- 3. the leeway --------------------------------------------------------------------------------

namespace {
constexpr int64_t kFar = std::numeric_limits<int64_t>::max() / 4;
}  // namespace

LeewayField::LeewayField(const TargetMasks& masks, double leeway_voxels) : masks_(masks) {
  // 1e-9 keeps a leeway that is an exact multiple of the voxel (0.2 mm at 0.05 mm) inclusive.
  limit2_ = leeway_voxels * leeway_voxels * (1.0 + 1e-9);
  reach_ = int32_t(std::floor(leeway_voxels * (1.0 + 1e-9)));
  brick_reach_ = std::max(1, (reach_ + int32_t(DS_BRICK_DIM) - 1) / int32_t(DS_BRICK_DIM));
  side_ = int64_t(DS_BRICK_DIM) + 2 * int64_t{reach_};
  bits_.assign(size_t(side_ * side_ * side_), 0);
  fx_.assign(size_t(side_ * side_ * DS_BRICK_DIM), kFar);
  fy_.assign(size_t(side_ * DS_BRICK_DIM * DS_BRICK_DIM), kFar);
  const int64_t bd = masks.brickDim();
  for (uint64_t brick : masks.bricks()) {
    const int64_t bx = int64_t(brick % uint64_t(bd)), by = int64_t((brick / uint64_t(bd)) % uint64_t(bd)),
                  bz = int64_t(brick / uint64_t(bd * bd));
    for (int64_t z = std::max<int64_t>(0, bz - brick_reach_); z <= std::min(bd - 1, bz + brick_reach_); ++z)
      for (int64_t y = std::max<int64_t>(0, by - brick_reach_); y <= std::min(bd - 1, by + brick_reach_); ++y)
        for (int64_t x = std::max<int64_t>(0, bx - brick_reach_); x <= std::min(bd - 1, bx + brick_reach_); ++x)
          band_.insert(uint64_t(x + bd * (y + bd * z)));
  }
}

// The target bits in the window of `reach` voxels around brick b, into bits_.
void LeewayField::load(BrickCoord b) {
  std::fill(bits_.begin(), bits_.end(), uint8_t{0});
  const int64_t bd = masks_.brickDim();
  origin_ = {int64_t(b.x * DS_BRICK_DIM) - reach_, int64_t(b.y * DS_BRICK_DIM) - reach_, int64_t(b.z * DS_BRICK_DIM) - reach_};
  const int64_t c[3] = {b.x, b.y, b.z};
  for (int64_t dz = -brick_reach_; dz <= brick_reach_; ++dz)
    for (int64_t dy = -brick_reach_; dy <= brick_reach_; ++dy)
      for (int64_t dx = -brick_reach_; dx <= brick_reach_; ++dx) {
        const int64_t nx = c[0] + dx, ny = c[1] + dy, nz = c[2] + dz;
        if (nx < 0 || ny < 0 || nz < 0 || nx >= bd || ny >= bd || nz >= bd) continue;
        const TargetMasks::Mask* m = masks_.find({uint32_t(nx), uint32_t(ny), uint32_t(nz)});
        if (!m) continue;
        for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
          if (!TargetMasks::test(*m, n)) continue;
          const int64_t x = nx * DS_BRICK_DIM + (n & 7u) - origin_[0], y = ny * DS_BRICK_DIM + ((n >> 3) & 7u) - origin_[1],
                        z = nz * DS_BRICK_DIM + (n >> 6) - origin_[2];
          if (x < 0 || y < 0 || z < 0 || x >= side_ || y >= side_ || z >= side_) continue;
          bits_[size_t(x + side_ * (y + side_ * z))] = 1;
        }
      }
}

// Squared Euclidean distance separates by axis: the nearest bit along x per row, then add dy^2 and
// take the minimum over the window in y, then the same in z. Only rows that reach the central
// brick are computed: O(side^2 x 8 x reach) for the first pass, less for the others.
const std::array<uint8_t, DS_BRICK_VOXELS>& LeewayField::near(BrickCoord b) {
  const uint64_t linear = linearBrick(b, masks_.brickDim());
  if (linear == loaded_) return near_;
  loaded_ = linear;
  load(b);
  const int64_t w = side_, r = reach_, dim = DS_BRICK_DIM;
  for (int64_t z = 0; z < w; ++z)
    for (int64_t y = 0; y < w; ++y) {
      const uint8_t* row = &bits_[size_t(w * (y + w * z))];
      for (int64_t x = 0; x < dim; ++x) {
        int64_t best = kFar;
        for (int64_t d = 0; d <= r && best == kFar; ++d)
          if (row[r + x - d] || row[r + x + d]) best = d * d;
        fx_[size_t(x + dim * (y + w * z))] = best;
      }
    }
  for (int64_t z = 0; z < w; ++z)
    for (int64_t y = 0; y < dim; ++y)
      for (int64_t x = 0; x < dim; ++x) {
        int64_t best = kFar;
        for (int64_t d = -r; d <= r; ++d) {
          const int64_t v = fx_[size_t(x + dim * ((y + r + d) + w * z))];
          if (v != kFar) best = std::min(best, v + d * d);
        }
        fy_[size_t(x + dim * (y + dim * z))] = best;
      }
  for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
    const int64_t x = n & 7u, y = (n >> 3) & 7u, z = n >> 6;
    int64_t best = kFar;
    for (int64_t d = -r; d <= r; ++d) {
      const int64_t v = fy_[size_t(x + dim * (y + dim * (z + r + d)))];
      if (v != kFar) best = std::min(best, v + d * d);
    }
    near_[n] = best != kFar && double(best) <= limit2_ ? 1 : 0;
  }
  return near_;
}

// ---- 4. the allowed zone as a grid -------------------------------------------------------------------

ZoneGrid::ZoneGrid(const BrickVolume& initial, const TargetMasks& masks, LeewayField& leeway, std::array<int64_t, 3> lo,
                   std::array<int64_t, 3> hi) {
  const auto dim = int64_t(initial.dim());
  for (size_t a = 0; a < 3; ++a) {
    lo_[a] = std::clamp<int64_t>(lo[a], 0, dim);
    hi_[a] = std::clamp<int64_t>(hi[a], lo_[a], dim);
    size_[a] = hi_[a] - lo_[a];
  }
  cells_.assign(size_t(size_[0] * size_[1] * size_[2]), 0);
  if (cells_.empty()) return;
  // Brick by brick, so that each brick's leeway is worked out once.
  for (int64_t bz = lo_[2] >> DS_BRICK_LOG2; bz <= (hi_[2] - 1) >> DS_BRICK_LOG2; ++bz)
    for (int64_t by = lo_[1] >> DS_BRICK_LOG2; by <= (hi_[1] - 1) >> DS_BRICK_LOG2; ++by)
      for (int64_t bx = lo_[0] >> DS_BRICK_LOG2; bx <= (hi_[0] - 1) >> DS_BRICK_LOG2; ++bx) {
        const BrickCoord b{uint32_t(bx), uint32_t(by), uint32_t(bz)};
        const BrickView view = initial.brick(b);
        const TargetMasks::Mask* mask = masks.find(b);
        const bool band = leeway.inBand(b);
        for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
          const int64_t x = bx * DS_BRICK_DIM + (n & 7u), y = by * DS_BRICK_DIM + ((n >> 3) & 7u), z = bz * DS_BRICK_DIM + (n >> 6);
          if (x < lo_[0] || y < lo_[1] || z < lo_[2] || x >= hi_[0] || y >= hi_[1] || z >= hi_[2]) continue;
          const Voxel v = view.uniform ? view.value : view.voxels[n];
          uint8_t cell = 0;
          if (isNeighbour(v)) cell = 0;  // an adjacent tooth is never the cut's to take, leeway or not
          else if (mask && TargetMasks::test(*mask, n)) cell = kTarget;
          else if (voxelFill(v) == 0 || layout::voxelMaterial(v) == DS_MAT_EMPTY || (band && leeway.near(b)[n])) cell = kAllowed;
          cells_[size_t((x - lo_[0]) + size_[0] * ((y - lo_[1]) + size_[1] * (z - lo_[2])))] = cell;
        }
      }
}

}  // namespace dentsim
