// The voxel comparison: the target's masks, then one pass over the bricks of the three volumes that files every voxel's fill by tissue and zone.
//
// Contents
//   1. Frame checks
//   2. The ideal cavity's masks
//   3. The brick pass: fill amounts per tissue and zone, cut marks, pulp exposure
//   4. compareTeeth
#include "eval/tooth_diff.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <vector>

namespace dentsim {

TissueAmounts& TissueAmounts::operator+=(const TissueAmounts& o) {
  initial += o.initial;
  remaining += o.remaining;
  removed += o.removed;
  target += o.target;
  target_removed += o.target_removed;
  leeway += o.leeway;
  leeway_removed += o.leeway_removed;
  container += o.container;
  container_removed += o.container_removed;
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
  for (size_t t = 0; t < kScoredTissues.size(); ++t)
    if (isToothTissue(kScoredTissues[t])) sum += tissues[t];
  return sum;
}

TissueAmounts ToothDiff::healthy() const {
  TissueAmounts sum;
  for (size_t t = 0; t < kScoredTissues.size(); ++t)
    if (isHealthyTissue(kScoredTissues[t])) sum += tissues[t];
  return sum;
}

const TissueAmounts& ToothDiff::adjacent() const { return tissue(Material::Neighbour); }

double ToothDiff::mm3(uint64_t units) const { return double(units) * (voxel_mm * voxel_mm * voxel_mm) / DS_FILL_FULL; }

namespace {

// Index into kScoredTissues of an initial material code, or -1 for empty and the spare codes.
int scoredTissueIndex(uint32_t material) { return kTissueIndexByCode[material & (DS_MATERIAL_COUNT - 1)]; }

std::string number(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

}  // namespace

// ---- 1. frame checks -----------------------------------------------------------------------------

// The frames must place every voxel at the same spot; sub-nanometre differences are rounding.
Status checkSameFrame(const ToothVolume& a, const std::string& a_name, const ToothVolume& b, const std::string& b_name) {
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

namespace {

// ---- 2. the ideal cavity's masks ---------------------------------------------------------------------

// The ideal's share of a voxel's initial fill: c = i - min(k, i), for the tooth's tissue only. A
// neighbour the professional cut is the professional's slip, not a cavity the student must copy.
uint32_t idealCavityOf(Voxel initial, Voxel ideal) {
  if (!isToothTissue(voxelMaterial(initial))) return 0;
  const uint32_t fi = voxelFill(initial);
  return fi - std::min(voxelFill(ideal), fi);
}

void markIdealCavity(const BrickVolume& initial, const BrickVolume& ideal, TargetMasks* masks) {
  const uint32_t bd = initial.brickDim();
  for (uint32_t bz = 0; bz < bd; ++bz)
    for (uint32_t by = 0; by < bd; ++by)
      for (uint32_t bx = 0; bx < bd; ++bx) {
        const BrickCoord c{bx, by, bz};
        const BrickView vi = initial.brick(c), vk = ideal.brick(c);
        if (vi.sameVoxels(vk)) continue;
        for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n)
          if (idealCavityOf(vi.at(n), vk.at(n)) > 0) masks->set(c, n);
      }
}

// ---- 3. the brick pass ---------------------------------------------------------------------------

struct Pass {
  std::array<TissueAmounts, kTissueCount> tissues{};
  std::vector<uint64_t> exposed_pulp;      // linear voxel indices, with repeats
  uint64_t target_in_crown_half = 0;
  CutMarks beyond_target, healthy_outside_zone, adjacent_removed;
};

class BrickPass {
 public:
  BrickPass(const BrickVolume& initial, const BrickVolume& final_, const BrickVolume* ideal, const TargetMasks& masks,
            LeewayField& leeway, const CrownEstimate& crown)
      : i_(initial), f_(final_), k_(ideal), masks_(masks), leeway_(leeway), crown_(crown), dim_(initial.dim()) {}

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
    const TargetMasks::Mask* target = masks_.find(c);
    const bool band = leeway_.inBand(c);
    if (!target && !band && vi.sameVoxels(vf) && vi.sameVoxels(vk)) return untouched(vi);
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
      const Voxel v = vi.at(n);
      const int t = scoredTissueIndex(layout::voxelMaterial(v));
      if (t < 0) continue;
      const uint32_t fi = voxelFill(v);
      const uint32_t r = std::min(voxelFill(vf.at(n)), fi);
      const uint32_t removed = fi - r;
      const bool neighbour = layout::voxelMaterial(v) == DS_MAT_NEIGHBOUR;
      // A neighbour is never target: all of it cut is adjacent-tooth damage (markCariesAccess
      // already leaves it out; the test keeps a hand-made mask honest).
      const uint32_t share = neighbour ? 0u : k_ ? idealCavityOf(v, vk.at(n)) : (target && TargetMasks::test(*target, n) ? fi : 0u);
      const uint32_t in_target = std::min(removed, share), beyond = removed - in_target, kept = fi - share;
      TissueAmounts& a = out_->tissues[size_t(t)];
      a.initial += fi;
      a.remaining += r;
      a.removed += removed;
      a.target += share;
      a.target_removed += in_target;
      const uint32_t x = c.x * DS_BRICK_DIM + (n & 7u), y = c.y * DS_BRICK_DIM + ((n >> 3) & 7u),
                     z = c.z * DS_BRICK_DIM + (n >> 6);
      if (kept > 0) {
        // A voxel with a share in the target is at distance 0 from it.
        const bool near = share > 0 || (band && leeway_.near(c)[n] != 0);
        (near ? a.leeway : a.container) += kept;
        (near ? a.leeway_removed : a.container_removed) += beyond;
        if (neighbour) out_->adjacent_removed.add(x, y, z, beyond);
        else out_->beyond_target.add(x, y, z, beyond);
        if (!near && isHealthyTissue(voxelMaterial(v))) out_->healthy_outside_zone.add(x, y, z, beyond);
      }
      if (share > 0 && dot(Vec3{x + 0.5, y + 0.5, z + 0.5}, crown_.axis) >= crown_.middle())
        out_->target_in_crown_half += share;
      if (layout::voxelMaterial(v) == DS_MAT_PULP && r < fi) out_->exposed_pulp.push_back(linear(x, y, z));
      if (r == 0 && fi > 0) pulpNextTo(vi, vf, x, y, z);
    }
  }

  // A brick equal in all volumes and away from the target: all of it remains, in the container.
  void untouched(const BrickView& b) {
    auto add = [&](Voxel v, uint64_t count) {
      const int t = scoredTissueIndex(layout::voxelMaterial(v));
      if (t < 0) return;
      const uint64_t units = uint64_t{voxelFill(v)} * count;
      TissueAmounts& a = out_->tissues[size_t(t)];
      a.initial += units;
      a.remaining += units;
      a.container += units;
    };
    if (b.uniform) return add(b.value, DS_BRICK_VOXELS);
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) add(b.voxels[n], 1);
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
        ni = vi.at(o);
        nf = vf.at(o);
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
  const TargetMasks& masks_;
  LeewayField& leeway_;
  const CrownEstimate& crown_;
  uint32_t dim_;
  Pass* out_ = nullptr;
};

}  // namespace

// ---- 4. compareTeeth -----------------------------------------------------------------------------

Result<ToothDiff> compareTeeth(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal,
                               const ZoneOptions& zone, const DiffNames& names) {
  if (!(zone.leeway_mm >= 0) || !std::isfinite(zone.leeway_mm))
    return makeError("", "leeway " + number(zone.leeway_mm) + " mm is not >= 0");
  if (!finite(zone.access_axis) || !(norm(zone.access_axis) > 1e-9))
    return makeError("", "the insertion axis has no direction");
  if (!(initial.frame.voxel_mm > 0))
    return makeError(names.initial, "voxel size " + number(initial.frame.voxel_mm) + " mm is not > 0");
  if (initial.frame.level != initial.voxels.level())
    return makeError(names.initial, "frame level " + std::to_string(initial.frame.level) + " differs from its grid's " +
                                        std::to_string(initial.voxels.level()));
  if (auto s = checkSameFrame(initial, names.initial, final_, names.final_); !s) return s.error();
  if (ideal)
    if (auto s = checkSameFrame(initial, names.initial, *ideal, names.ideal); !s) return s.error();

  ToothDiff diff;
  diff.voxel_mm = initial.frame.voxel_mm;
  diff.has_ideal = ideal != nullptr;
  diff.target_kind = ideal ? TargetKind::IdealCavity : TargetKind::CariesAccess;
  diff.access_axis = normalized(zone.access_axis);
  diff.leeway_mm = zone.leeway_mm;
  diff.crown = estimateCrown(initial.voxels);

  const double leeway_voxels = zone.leeway_mm / diff.voxel_mm;
  TargetMasks masks(initial.voxels.brickDim());
  if (ideal)
    markIdealCavity(initial.voxels, ideal->voxels, &masks);
  else
    markCariesAccess(initial.voxels, diff.access_axis, uint32_t(std::ceil(leeway_voxels / DS_BRICK_DIM)) + 1, &masks);
  LeewayField leeway(masks, leeway_voxels);

  Pass pass;
  BrickPass(initial.voxels, final_.voxels, ideal ? &ideal->voxels : nullptr, masks, leeway, diff.crown).run(&pass);
  diff.tissues = pass.tissues;
  diff.target_in_crown_half = pass.target_in_crown_half;
  diff.beyond_target = std::move(pass.beyond_target);
  diff.healthy_outside_zone = std::move(pass.healthy_outside_zone);
  diff.adjacent_removed = std::move(pass.adjacent_removed);

  std::sort(pass.exposed_pulp.begin(), pass.exposed_pulp.end());
  diff.exposed_pulp_voxels =
      uint64_t(std::unique(pass.exposed_pulp.begin(), pass.exposed_pulp.end()) - pass.exposed_pulp.begin());
  diff.pulp_exposed = diff.exposed_pulp_voxels > 0;
  return diff;
}

}  // namespace dentsim
