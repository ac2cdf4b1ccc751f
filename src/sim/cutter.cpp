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

double segmentDistance2(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  const Vec3 d = p - (a + ab * t);
  return dot(d, d);
}

}  // namespace

Cutter::Cutter(size_t max_candidates, size_t max_voxels_per_step)
    : max_voxels_(std::min(max_voxels_per_step, max_candidates)) {
  candidates_.reserve(max_candidates);
  brick_keys_.reserve(max_candidates);
  size_t table = 16;
  while (table < 2 * max_candidates) table *= 2;
  set_keys_.assign(table, 0);
  set_stamps_.assign(table, 0);
}

bool Cutter::insert(uint64_t key) {
  const size_t mask = set_keys_.size() - 1;
  for (size_t i = size_t(mix64(key)) & mask, probes = 0; probes < set_keys_.size(); i = (i + 1) & mask, ++probes) {
    if (set_stamps_[i] != stamp_) {
      set_stamps_[i] = stamp_;
      set_keys_[i] = key;
      return true;
    }
    if (set_keys_[i] == key) return false;
  }
  return false;
}

CutStep Cutter::cut(BrickVolume& volume, VoxelField& field, std::span<const ContactPoint> contacts,
                    const SimParams& params, double ability, double speed, double dt, uint64_t step,
                    EditChannel* edits) {
  CutStep out;
  if (!(speed > 0) || !(ability > 0) || !(dt > 0)) return out;
  out.demand_mm3 = params.cutting.removal_rate_mm3_per_s * ability * std::min(speed, 1.0) * dt;
  if (!(out.demand_mm3 > 0)) return out;

  // ---- the voxels under the head ----
  if (++stamp_ == 0) {  // the stamps wrapped: clear once every 2^32 steps
    std::fill(set_stamps_.begin(), set_stamps_.end(), 0u);
    stamp_ = 1;
  }
  candidates_.clear();
  const int64_t dim = int64_t(volume.dim());
  const double rho = std::max(params.cutting.reach_mm / field.voxelMm(), 0.5);  // [voxel]
  // A step takes at most max_voxels_ voxels, starting from a contact that moves on every step, so a
  // buried head costs a bounded time and, over a few steps, every contact gets its turn.
  const size_t n = contacts.size();
  const size_t first = n > 0 ? size_t(step % n) : 0;
  for (size_t k = 0; k < n && candidates_.size() < max_voxels_; ++k) {
    const ContactPoint& cp = contacts[(first + k) % n];
    if (!cp.cutting) continue;
    const Vec3 a = field.toVoxel(cp.position);
    const Vec3 b = field.toVoxel(cp.position + cp.normal * cp.depth_mm);
    const int64_t x0 = std::max<int64_t>(0, int64_t(std::ceil(std::min(a.x, b.x) - rho)));
    const int64_t y0 = std::max<int64_t>(0, int64_t(std::ceil(std::min(a.y, b.y) - rho)));
    const int64_t z0 = std::max<int64_t>(0, int64_t(std::ceil(std::min(a.z, b.z) - rho)));
    const int64_t x1 = std::min<int64_t>(dim - 1, int64_t(std::floor(std::max(a.x, b.x) + rho)));
    const int64_t y1 = std::min<int64_t>(dim - 1, int64_t(std::floor(std::max(a.y, b.y) + rho)));
    const int64_t z1 = std::min<int64_t>(dim - 1, int64_t(std::floor(std::max(a.z, b.z) + rho)));
    for (int64_t z = z0; z <= z1; ++z)
      for (int64_t y = y0; y <= y1; ++y)
        for (int64_t x = x0; x <= x1; ++x) {
          if (segmentDistance2(Vec3{double(x), double(y), double(z)}, a, b) > rho * rho) continue;
          const uint64_t key = uint64_t(x) + uint64_t(dim) * (uint64_t(y) + uint64_t(dim) * uint64_t(z));
          if (!insert(key)) continue;
          const Voxel v = field.voxel(x, y, z);
          if (v == 0 || params.tissue(voxelMaterial(v)).hardness <= 0) continue;
          if (candidates_.size() == max_voxels_) break;
          candidates_.push_back({key, v});
        }
  }
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
