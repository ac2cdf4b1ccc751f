// Cutter: the voxels under a bur's cutting contacts lose fill in proportion to fill x hardness, rounded without bias.
#include "sim/cutter.h"

#include <algorithm>
#include <cmath>

namespace dentsim {

namespace {

uint64_t mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// A uniform number in [0, 1) fixed by the voxel and the step: the same dice on every replay.
double dice(uint64_t voxel, uint64_t step) {
  return double(mix64(voxel * 0x2545f4914f6cdd1dull ^ mix64(step)) >> 11) * 0x1.0p-53;
}

}  // namespace

Cutter::Cutter(size_t max_candidates, size_t max_voxels_per_step)
    : max_voxels_(std::min(max_voxels_per_step, max_candidates)), marks_(kMarkBits / 64, 0ull) {
  candidates_.reserve(max_candidates);
  brick_keys_.reserve(max_candidates);
}

CutStep Cutter::cut(BrickVolume& volume, VoxelField& field, std::span<const ContactPoint> contacts,
                    const SimParams& params, double ability, double speed, double dt, uint64_t step,
                    EditChannel* edits) {
  CutStep out;
  if (!(speed > 0) || !(ability > 0) || !(dt > 0)) return out;
  out.demand_mm3 = params.cutting.removal_rate_mm3_per_s * ability * std::min(speed, 1.0) * dt;
  if (!(out.demand_mm3 > 0)) return out;

  constexpr double kFillMargin = 3.0;
  constexpr size_t kMinVoxels = 512;
  const double voxels_of_demand = kFillMargin * out.demand_mm3 / field.frame().voxelVolumeMm3();
  const size_t limit = std::min(max_voxels_, std::max(kMinVoxels, size_t(std::ceil(voxels_of_demand))));
  gather(field, contacts, params, step, limit);
  out.candidates = uint32_t(candidates_.size());
  if (candidates_.empty()) return out;

  double fill_sum = 0, hard_fill_sum = 0;
  for (const Candidate& c : candidates_) {
    fill_sum += voxelFill(c.value);
    hard_fill_sum += params.tissue(voxelMaterial(c.value)).hardness * voxelFill(c.value);
  }
  out.expected_mm3 = out.demand_mm3 * hard_fill_sum / fill_sum;

  // ---- room: the channel takes every edit, the volume's reserve every tile turned dense ----
  if (edits != nullptr && edits->freeSlots() < candidates_.size()) {
    out.deferred = true;
    return out;
  }
  if (volume.spareBricks() < candidates_.size() || volume.spareBlocks() < candidates_.size()) {
    if (!roomForBricks(volume)) {
      out.deferred = true;
      return out;
    }
  }
  return remove(volume, field, params, step, edits, fill_sum, out);
}

void Cutter::gather(VoxelField& field, std::span<const ContactPoint> contacts, const SimParams& params,
                    uint64_t step, size_t limit) {
  candidates_.clear();
  const int64_t dim = int64_t(field.dim());
  const double rho = std::max(params.cutting.reach_mm / field.voxelMm(), 0.5);  // [voxel]
  // The voxels one contact reaches: centres within rho of the segment from the point out to the
  // tissue surface, inside the box [lo, hi].
  struct Reach {
    Vec3 a, b;
    int64_t lo[3], hi[3];
  };
  auto reach = [&](const ContactPoint& cp) {
    Reach r{field.toVoxel(cp.position), field.toVoxel(cp.position + cp.normal * cp.depth_mm), {}, {}};
    for (int i = 0; i < 3; ++i) {
      r.lo[i] = std::max<int64_t>(0, int64_t(std::ceil(std::min(r.a[i], r.b[i]) - rho)));
      r.hi[i] = std::min<int64_t>(dim - 1, int64_t(std::floor(std::max(r.a[i], r.b[i]) + rho)));
    }
    return r;
  };

  // The contacts take turns from one that moves on every step, so that a buried head costs a
  // bounded time and, over a few steps, every contact gets its turn. First the box they reach,
  // which must fit the marks; the contacts beyond the first that does not fit wait.
  const size_t n = contacts.size();
  const size_t first = n > 0 ? size_t(step % n) : 0;
  int64_t lo[3] = {dim, dim, dim}, hi[3] = {-1, -1, -1};
  size_t turns = 0;
  for (; turns < n; ++turns) {
    const ContactPoint& cp = contacts[(first + turns) % n];
    if (!cp.cutting) continue;
    const Reach r = reach(cp);
    if (r.lo[0] > r.hi[0] || r.lo[1] > r.hi[1] || r.lo[2] > r.hi[2]) continue;
    int64_t nlo[3], nhi[3];
    uint64_t cells = 1;
    for (int i = 0; i < 3; ++i) {
      nlo[i] = std::min(lo[i], r.lo[i]);
      nhi[i] = std::max(hi[i], r.hi[i]);
      cells *= uint64_t(nhi[i] - nlo[i] + 1);
    }
    if (cells > kMarkBits) break;
    std::copy(nlo, nlo + 3, lo);
    std::copy(nhi, nhi + 3, hi);
  }
  if (hi[0] < 0) return;
  const uint64_t sx = uint64_t(hi[0] - lo[0] + 1), sy = uint64_t(hi[1] - lo[1] + 1);
  std::fill_n(marks_.begin(), (sx * sy * uint64_t(hi[2] - lo[2] + 1) + 63) / 64, 0ull);

  // Then the voxels, each once, up to the per-step limit.
  for (size_t k = 0; k < turns; ++k) {
    const ContactPoint& cp = contacts[(first + k) % n];
    if (!cp.cutting) continue;
    const Reach r = reach(cp);
    const Vec3 ab = r.b - r.a;
    const double len2 = dot(ab, ab);
    const double inv_len2 = len2 > 0 ? 1.0 / len2 : 0.0;
    for (int64_t z = r.lo[2]; z <= r.hi[2]; ++z)
      for (int64_t y = r.lo[1]; y <= r.hi[1]; ++y)
        for (int64_t x = r.lo[0]; x <= r.hi[0]; ++x) {
          const Vec3 ap = Vec3{double(x), double(y), double(z)} - r.a;
          const Vec3 d = ap - ab * std::clamp(dot(ap, ab) * inv_len2, 0.0, 1.0);
          if (dot(d, d) > rho * rho) continue;
          const uint64_t bit = uint64_t(x - lo[0]) + sx * (uint64_t(y - lo[1]) + sy * uint64_t(z - lo[2]));
          uint64_t& word = marks_[size_t(bit >> 6)];
          const uint64_t mask = uint64_t{1} << (bit & 63);
          if (word & mask) continue;
          word |= mask;
          const Voxel v = field.voxel(x, y, z);
          if (v == 0 || params.tissue(voxelMaterial(v)).hardness <= 0) continue;
          candidates_.push_back({uint64_t(x) + uint64_t(dim) * (uint64_t(y) + uint64_t(dim) * uint64_t(z)), v});
          if (candidates_.size() == limit) return;
        }
  }
}

bool Cutter::roomForBricks(const BrickVolume& volume) {
  const uint64_t dim = volume.dim();
  brick_keys_.clear();
  for (const Candidate& c : candidates_) {
    const uint64_t x = c.index % uint64_t(dim), y = (c.index / uint64_t(dim)) % uint64_t(dim), z = c.index / uint64_t(dim) / uint64_t(dim);
    brick_keys_.push_back(((z >> DS_BRICK_LOG2) << 42) | ((y >> DS_BRICK_LOG2) << 21) | (x >> DS_BRICK_LOG2));
  }
  std::sort(brick_keys_.begin(), brick_keys_.end());
  const size_t bricks = size_t(std::unique(brick_keys_.begin(), brick_keys_.end()) - brick_keys_.begin());
  // The chunks those bricks lie in: each may need an index block.
  const uint64_t field_mask = (uint64_t{1} << 21) - 1;
  for (size_t i = 0; i < bricks; ++i) {
    const uint64_t k = brick_keys_[i];
    brick_keys_[i] = (((k >> 42) >> DS_CHUNK_LOG2) << 42) | ((((k >> 21) & field_mask) >> DS_CHUNK_LOG2) << 21) |
                     ((k & field_mask) >> DS_CHUNK_LOG2);
  }
  std::sort(brick_keys_.begin(), brick_keys_.begin() + std::ptrdiff_t(bricks));
  const size_t chunks = size_t(std::unique(brick_keys_.begin(), brick_keys_.begin() + std::ptrdiff_t(bricks)) -
                               brick_keys_.begin());
  return volume.spareBricks() >= bricks && volume.spareBlocks() >= chunks;
}

CutStep Cutter::remove(BrickVolume& volume, VoxelField& field, const SimParams& params, uint64_t step,
                       EditChannel* edits, double fill_sum, CutStep out) {
  const uint64_t dim = volume.dim();
  const double unit_mm3 = field.frame().voxelVolumeMm3() / DS_FILL_FULL;
  const double per_fill = out.demand_mm3 / (unit_mm3 * fill_sum);  // fill units lost per unit held, at hardness 1
  for (const Candidate& c : candidates_) {
    const Material m = voxelMaterial(c.value);
    const uint32_t fill = voxelFill(c.value);
    const double share = per_fill * params.tissue(m).hardness * fill;
    const double lost = std::floor(share + dice(c.index, step));
    const uint32_t left = lost >= double(fill) ? 0u : fill - uint32_t(lost);
    if (left == fill) continue;
    const Voxel now = left == 0 ? Voxel{0} : makeVoxel(m, left);
    const auto x = uint32_t(c.index % uint64_t(dim)), y = uint32_t((c.index / uint64_t(dim)) % uint64_t(dim));
    const auto z = uint32_t(c.index / uint64_t(dim) / uint64_t(dim));
    volume.setVoxel(x, y, z, now);
    if (edits != nullptr) edits->push(packVoxelEdit(c.index, now));
    ++out.voxels_changed;
    out.removed_mm3 += double(fill - left) * unit_mm3;
  }
  if (edits != nullptr) edits->publish();
  if (out.voxels_changed > 0) field.invalidate();
  return out;
}

}  // namespace dentsim
