// The voxel comparison: one pass over the bricks of the three volumes, then the leeway split of the over-cut voxels.
//
// Contents
//   1. Frame checks
//   2. The brick pass: fill amounts per tissue, ideal-cavity masks, over-cut voxels, pulp exposure
//   3. The leeway split: near-margin or gross, by the distance to the ideal cavity computed per brick
//      that has over-cut, axis by axis, in a dense copy of the cavity's bits around it
//   4. compareTeeth
#include "eval/tooth_diff.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace dentsim {

TissueAmounts& TissueAmounts::operator+=(const TissueAmounts& o) {
  initial += o.initial;
  remaining += o.remaining;
  removed += o.removed;
  ideal_cavity += o.ideal_cavity;
  undercut += o.undercut;
  overcut += o.overcut;
  overcut_near += o.overcut_near;
  overcut_gross += o.overcut_gross;
  return *this;
}

const TissueAmounts& ToothDiff::tissue(Material m) const {
  for (size_t t = 0; t < kScoredTissues.size(); ++t)
    if (kScoredTissues[t] == m) return tissues[t];
  assert(false && "not a scored tissue");
  return tissues[0];
}

TissueAmounts ToothDiff::total() const {
  TissueAmounts sum;
  for (const TissueAmounts& t : tissues) sum += t;
  return sum;
}

double ToothDiff::mm3(uint64_t units) const { return double(units) * (voxel_mm * voxel_mm * voxel_mm) / DS_FILL_FULL; }

namespace {

// Index into kScoredTissues of an initial material code, or -1 for empty and the spare codes.
int tissueIndex(uint32_t material) {
  return material >= DS_MAT_ENAMEL && material <= DS_MAT_CARIES ? int(material) - int(DS_MAT_ENAMEL) : -1;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

// ---- 1. frame checks -----------------------------------------------------------------------------

// The frames must place every voxel at the same spot; sub-nanometre differences are rounding.
Status sameFrame(const ToothVolume& a, const std::string& a_name, const ToothVolume& b, const std::string& b_name) {
  const std::string of_a = " differs from " + a_name + "'s ";
  if (b.voxels.level() != a.voxels.level())
    return makeError(b_name, "octree level " + std::to_string(b.voxels.level()) + of_a +
                                 std::to_string(a.voxels.level()) + "; score volumes of one level");
  const double tol = 1e-9 * std::max(1.0, std::abs(a.frame.voxel_mm));
  if (std::abs(b.frame.voxel_mm - a.frame.voxel_mm) > tol)
    return makeError(b_name, "voxel size " + number(b.frame.voxel_mm) + " mm" + of_a + number(a.frame.voxel_mm) + " mm");
  for (int axis = 0; axis < 3; ++axis) {
    const double pa = a.frame.origin_mm[size_t(axis)], pb = b.frame.origin_mm[size_t(axis)];
    if (std::abs(pb - pa) > 1e-6 * std::max(1.0, a.frame.voxel_mm))
      return makeError(b_name, std::string("origin ") + "xyz"[axis] + " " + number(pb) + " mm" + of_a + number(pa) + " mm");
  }
  return Ok{};
}

// ---- 2. the brick pass ---------------------------------------------------------------------------

// One over-cut voxel, kept for the leeway split.
struct OverVoxel {
  uint32_t x, y, z;   // voxel coordinates
  uint32_t units;     // its over-cut [fill units]
  uint32_t tissue;    // index into kScoredTissues
};

using CavityMask = std::array<uint64_t, DS_BRICK_VOXELS / 64>;  // bit n: voxel n of the brick has c > 0

// The ideal-cavity bits of the bricks that have any, by linear brick index.
class CavityMasks {
 public:
  explicit CavityMasks(uint32_t brick_dim) : brick_dim_(brick_dim) {}

  void set(uint64_t brick, uint32_t offset) { masks_[brick][offset >> 6] |= uint64_t{1} << (offset & 63u); }
  const CavityMask* find(uint64_t brick) const {
    auto it = masks_.find(brick);
    return it == masks_.end() ? nullptr : &it->second;
  }

  uint64_t linearBrick(uint32_t bx, uint32_t by, uint32_t bz) const {
    return bx + uint64_t{brick_dim_} * (by + uint64_t{brick_dim_} * bz);
  }

 private:
  uint32_t brick_dim_;
  std::unordered_map<uint64_t, CavityMask> masks_;
};

Voxel at(const BrickView& b, uint32_t offset) { return b.uniform ? b.value : b.voxels[offset]; }

bool sameBrick(const BrickView& a, const BrickView& b) {
  if (a.uniform != b.uniform) return false;
  if (a.uniform) return a.value == b.value;
  return a.voxels == b.voxels || std::memcmp(a.voxels, b.voxels, DS_BRICK_VOXELS) == 0;
}

// Everything the pass gathers.
struct Pass {
  std::array<TissueAmounts, 4> tissues{};
  std::vector<OverVoxel> over;             // in brick order
  std::vector<uint64_t> exposed_pulp;      // linear voxel indices, with repeats
};

class BrickPass {
 public:
  BrickPass(const BrickVolume& initial, const BrickVolume& final_, const BrickVolume* ideal, CavityMasks* masks)
      : i_(initial), f_(final_), k_(ideal), masks_(masks), dim_(initial.dim()) {}

  void run(Pass* out) {
    out_ = out;
    const uint32_t bd = i_.brickDim();
    for (uint32_t bz = 0; bz < bd; ++bz)
      for (uint32_t by = 0; by < bd; ++by)
        for (uint32_t bx = 0; bx < bd; ++bx) brick({bx, by, bz});
  }

 private:
  void brick(BrickCoord c) {
    const BrickView vi = i_.brick(c), vf = f_.brick(c);
    const BrickView vk = k_ ? k_->brick(c) : vi;
    if (sameBrick(vi, vf) && sameBrick(vi, vk)) return untouched(vi);
    const uint64_t linear_brick = masks_->linearBrick(c.x, c.y, c.z);
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
      const Voxel v = at(vi, n);
      const int t = tissueIndex(layout::voxelMaterial(v));
      if (t < 0) continue;
      const uint32_t fi = voxelFill(v);
      const uint32_t r = std::min(voxelFill(at(vf, n)), fi);
      const uint32_t k = k_ ? std::min(voxelFill(at(vk, n)), fi) : fi;
      TissueAmounts& a = out_->tissues[size_t(t)];
      a.initial += fi;
      a.remaining += r;
      a.removed += fi - r;
      const uint32_t x = c.x * DS_BRICK_DIM + (n & 7u), y = c.y * DS_BRICK_DIM + ((n >> 3) & 7u),
                     z = c.z * DS_BRICK_DIM + (n >> 6);
      if (k_) {
        a.ideal_cavity += fi - k;
        if (k < fi) masks_->set(linear_brick, n);
        if (r > k) a.undercut += r - k;
        if (k > r) {
          a.overcut += k - r;
          out_->over.push_back({x, y, z, k - r, uint32_t(t)});
        }
      }
      if (layout::voxelMaterial(v) == DS_MAT_PULP && r < fi) out_->exposed_pulp.push_back(linear(x, y, z));
      if (r == 0 && fi > 0) pulpNextTo(vi, vf, x, y, z);
    }
  }

  // A brick equal in all volumes: nothing removed, nothing to compare.
  void untouched(const BrickView& b) {
    if (b.uniform) {
      const int t = tissueIndex(layout::voxelMaterial(b.value));
      if (t < 0) return;
      const uint64_t units = uint64_t{voxelFill(b.value)} * DS_BRICK_VOXELS;
      out_->tissues[size_t(t)].initial += units;
      out_->tissues[size_t(t)].remaining += units;
      return;
    }
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
      const int t = tissueIndex(layout::voxelMaterial(b.voxels[n]));
      if (t < 0) continue;
      out_->tissues[size_t(t)].initial += voxelFill(b.voxels[n]);
      out_->tissues[size_t(t)].remaining += voxelFill(b.voxels[n]);
    }
  }

  // The voxel at (x,y,z) was cut empty: a face neighbour that is pulp and still holds fill lies open.
  void pulpNextTo(const BrickView& vi, const BrickView& vf, uint32_t x, uint32_t y, uint32_t z) {
    constexpr int kFace[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (const auto& d : kFace) {
      const int64_t nx = int64_t{x} + d[0], ny = int64_t{y} + d[1], nz = int64_t{z} + d[2];
      if (nx < 0 || ny < 0 || nz < 0 || nx >= dim_ || ny >= dim_ || nz >= dim_) continue;
      const auto ux = uint32_t(nx), uy = uint32_t(ny), uz = uint32_t(nz);
      Voxel ni, nf;
      // Most neighbours share the brick: read them from the views, not through the index.
      if ((ux >> DS_BRICK_LOG2) == (x >> DS_BRICK_LOG2) && (uy >> DS_BRICK_LOG2) == (y >> DS_BRICK_LOG2) &&
          (uz >> DS_BRICK_LOG2) == (z >> DS_BRICK_LOG2)) {
        const uint32_t o = layout::brickCoordToOffset(ux & 7u, uy & 7u, uz & 7u);
        ni = at(vi, o);
        nf = at(vf, o);
      } else {
        ni = i_.voxel(ux, uy, uz);
        nf = f_.voxel(ux, uy, uz);
      }
      if (layout::voxelMaterial(ni) == DS_MAT_PULP && voxelFill(ni) > 0 && voxelFill(nf) > 0)
        out_->exposed_pulp.push_back(linear(ux, uy, uz));
    }
  }

  uint64_t linear(uint32_t x, uint32_t y, uint32_t z) const { return x + uint64_t{dim_} * (y + uint64_t{dim_} * z); }

  const BrickVolume& i_;
  const BrickVolume& f_;
  const BrickVolume* k_;
  CavityMasks* masks_;
  uint32_t dim_;
  Pass* out_ = nullptr;
};

// ---- 3. the leeway split -------------------------------------------------------------------------

// The ideal-cavity bits around one brick, copied into a dense block so that a voxel's search reads
// memory directly instead of hashing a brick per offset: the brick and `reach` bricks on each side.
class CavityBlock {
 public:
  explicit CavityBlock(int32_t brick_reach)
      : reach_(brick_reach), side_(int64_t(DS_BRICK_DIM) * (2 * brick_reach + 1)),
        bits_(size_t(side_ * side_ * side_), 0) {}

  // Fills the block around brick (bx,by,bz); false when no ideal cavity lies in it.
  bool load(const CavityMasks& masks, uint32_t bx, uint32_t by, uint32_t bz, int64_t brick_dim) {
    std::fill(bits_.begin(), bits_.end(), uint8_t{0});
    origin_ = {(int64_t{bx} - reach_) * DS_BRICK_DIM, (int64_t{by} - reach_) * DS_BRICK_DIM,
               (int64_t{bz} - reach_) * DS_BRICK_DIM};
    bool any = false;
    for (int32_t dz = -reach_; dz <= reach_; ++dz)
      for (int32_t dy = -reach_; dy <= reach_; ++dy)
        for (int32_t dx = -reach_; dx <= reach_; ++dx) {
          const int64_t nx = int64_t{bx} + dx, ny = int64_t{by} + dy, nz = int64_t{bz} + dz;
          if (nx < 0 || ny < 0 || nz < 0 || nx >= brick_dim || ny >= brick_dim || nz >= brick_dim) continue;
          const CavityMask* m = masks.find(masks.linearBrick(uint32_t(nx), uint32_t(ny), uint32_t(nz)));
          if (!m) continue;
          any = true;
          for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n)
            if (((*m)[n >> 6] >> (n & 63u)) & 1u)
              bits_[index(nx * DS_BRICK_DIM + (n & 7u), ny * DS_BRICK_DIM + ((n >> 3) & 7u),
                          nz * DS_BRICK_DIM + (n >> 6))] = 1;
        }
    return any;
  }
  // Squared distance [voxels^2] from each voxel of the central brick (offset n, x fastest) to the
  // nearest ideal-cavity voxel, or kFar when none lies within `reach` voxels on every axis. Squared
  // Euclidean distance separates by axis: min over x, then add dy^2 and take the min over y, then z.
  // Only the rows that reach the central brick are computed: O((8 + 2 reach)^2 x (8 + 2 reach)).
  static constexpr int64_t kFar = std::numeric_limits<int64_t>::max() / 4;
  void centreDistances(int32_t reach, std::array<int64_t, DS_BRICK_VOXELS>* out) const {
    const int64_t c = int64_t(reach_) * DS_BRICK_DIM;  // the central brick's first voxel in block coordinates
    const int64_t w = DS_BRICK_DIM + 2 * int64_t{reach};  // rows and columns that can reach it
    const int64_t lo = c - reach;
    // Along x: per row (y, z), the nearest set bit to each central x, by one sweep each way.
    std::vector<int64_t> fx(size_t(w * w * DS_BRICK_DIM), kFar);  // [z][y][x], x central
    for (int64_t z = 0; z < w; ++z)
      for (int64_t y = 0; y < w; ++y) {
        const uint8_t* row = &bits_[size_t(side_ * ((lo + y) + side_ * (lo + z)))];
        for (int64_t x = 0; x < int64_t{DS_BRICK_DIM}; ++x) {
          int64_t best = kFar;
          for (int64_t d = 0; d <= reach && best == kFar; ++d)
            if (row[c + x - d] || row[c + x + d]) best = d * d;
          fx[size_t(x + DS_BRICK_DIM * (y + w * z))] = best;
        }
      }
    // Along y, then z: add the squared step and keep the minimum over the window.
    std::vector<int64_t> fy(size_t(w * DS_BRICK_DIM * DS_BRICK_DIM), kFar);  // [z][y][x], x and y central
    for (int64_t z = 0; z < w; ++z)
      for (int64_t y = 0; y < int64_t{DS_BRICK_DIM}; ++y)
        for (int64_t x = 0; x < int64_t{DS_BRICK_DIM}; ++x) {
          int64_t best = kFar;
          for (int64_t d = -reach; d <= reach; ++d) {
            const int64_t v = fx[size_t(x + DS_BRICK_DIM * ((y + reach + d) + w * z))];
            if (v != kFar) best = std::min(best, v + d * d);
          }
          fy[size_t(x + DS_BRICK_DIM * (y + DS_BRICK_DIM * z))] = best;
        }
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
      const int64_t x = n & 7u, y = (n >> 3) & 7u, z = n >> 6;
      int64_t best = kFar;
      for (int64_t d = -reach; d <= reach; ++d) {
        const int64_t v = fy[size_t(x + DS_BRICK_DIM * (y + DS_BRICK_DIM * (z + reach + d)))];
        if (v != kFar) best = std::min(best, v + d * d);
      }
      (*out)[n] = best;
    }
  }

 private:
  size_t index(int64_t x, int64_t y, int64_t z) const {
    return size_t((x - origin_[0]) + side_ * ((y - origin_[1]) + side_ * (z - origin_[2])));
  }
  int32_t reach_;
  int64_t side_;
  std::array<int64_t, 3> origin_{};
  std::vector<uint8_t> bits_;  // (side^3), x fastest
};

void splitOverCut(const std::vector<OverVoxel>& over, const CavityMasks& masks, uint32_t dim, double leeway_voxels,
                  std::array<TissueAmounts, 4>* tissues) {
  if (over.empty()) return;
  // 1e-9 keeps a leeway that is an exact multiple of the voxel (0.2 mm at 0.05 mm) inclusive.
  const double limit = leeway_voxels * leeway_voxels * (1.0 + 1e-9);
  const auto reach = int32_t(std::floor(leeway_voxels * (1.0 + 1e-9)));
  const int32_t brick_reach = std::max(1, (reach + int32_t(DS_BRICK_DIM) - 1) / int32_t(DS_BRICK_DIM));
  const int64_t brick_dim = dim >> DS_BRICK_LOG2;
  CavityBlock block(brick_reach);
  std::array<int64_t, DS_BRICK_VOXELS> dist2{};
  uint64_t loaded_brick = ~uint64_t{0};
  bool cavity_nearby = false;
  for (const OverVoxel& v : over) {
    // The voxels come brick by brick: one block per brick. A block without ideal cavity makes every
    // over-cut voxel of the brick gross at once.
    const uint32_t bx = v.x >> DS_BRICK_LOG2, by = v.y >> DS_BRICK_LOG2, bz = v.z >> DS_BRICK_LOG2;
    const uint64_t brick = masks.linearBrick(bx, by, bz);
    if (brick != loaded_brick) {
      loaded_brick = brick;
      cavity_nearby = block.load(masks, bx, by, bz, brick_dim);
      if (cavity_nearby) block.centreDistances(reach, &dist2);
    }
    const uint32_t n = layout::brickCoordToOffset(v.x & 7u, v.y & 7u, v.z & 7u);
    const bool near = cavity_nearby && dist2[n] != CavityBlock::kFar && double(dist2[n]) <= limit;
    (near ? (*tissues)[v.tissue].overcut_near : (*tissues)[v.tissue].overcut_gross) += v.units;
  }
}

}  // namespace

// ---- 4. compareTeeth -----------------------------------------------------------------------------

Result<ToothDiff> compareTeeth(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal,
                               double leeway_mm, const DiffNames& names) {
  if (!(leeway_mm >= 0) || !std::isfinite(leeway_mm)) return makeError("", "leeway " + number(leeway_mm) + " mm is not >= 0");
  if (!(initial.frame.voxel_mm > 0))
    return makeError(names.initial, "voxel size " + number(initial.frame.voxel_mm) + " mm is not > 0");
  if (initial.frame.level != initial.voxels.level())
    return makeError(names.initial, "frame level " + std::to_string(initial.frame.level) + " differs from its grid's " +
                                        std::to_string(initial.voxels.level()));
  if (auto s = sameFrame(initial, names.initial, final_, names.final_); !s) return s.error();
  if (ideal)
    if (auto s = sameFrame(initial, names.initial, *ideal, names.ideal); !s) return s.error();

  ToothDiff diff;
  diff.voxel_mm = initial.frame.voxel_mm;
  diff.has_ideal = ideal != nullptr;
  diff.leeway_mm = leeway_mm;

  CavityMasks masks(initial.voxels.brickDim());
  Pass pass;
  BrickPass(initial.voxels, final_.voxels, ideal ? &ideal->voxels : nullptr, &masks).run(&pass);
  diff.tissues = pass.tissues;
  if (ideal) splitOverCut(pass.over, masks, initial.voxels.dim(), leeway_mm / diff.voxel_mm, &diff.tissues);

  std::sort(pass.exposed_pulp.begin(), pass.exposed_pulp.end());
  diff.exposed_pulp_voxels =
      uint64_t(std::unique(pass.exposed_pulp.begin(), pass.exposed_pulp.end()) - pass.exposed_pulp.begin());
  diff.pulp_exposed = diff.exposed_pulp_voxels > 0;
  return diff;
}

}  // namespace dentsim
