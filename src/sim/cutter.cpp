// Cutter: the voxels under a bur's cutting contacts lose fill in proportion to fill x hardness, rounded without bias.
#include "sim/cutter.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace dentsim {

namespace {

uint64_t mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// A uniform number in [0, 1) fixed by the voxel and the step (step_hash = mix64(step)): the same
// dice on every replay.
double dice(uint64_t voxel, uint64_t step_hash) {
  return double(mix64(voxel * 0x2545f4914f6cdd1dull ^ step_hash) >> 11) * 0x1.0p-53;
}

}  // namespace

Cutter::Cutter(size_t max_candidates, size_t max_voxels_per_step)
    : max_voxels_(std::min(max_voxels_per_step, max_candidates)), marks_(kMarkBits / 64, 0ull) {
  candidates_.reserve(max_candidates);
  touched_.reserve(kMaxTouched);
  brick_keys_.reserve(max_candidates);
}

CutStep Cutter::cut(BrickVolume& volume, VoxelField& field, std::span<const ContactPoint> contacts,
                    const SimParams& params, double ability, double speed, double dt, uint64_t step,
                    EditChannel* edits) {
  CutStep out;
  if (!(speed > 0) || !(ability > 0) || !(dt > 0)) return out;
  out.demand_mm3 = params.cutting.removal_rate_mm3_per_s * ability * std::min(speed, 1.0) * dt;
  if (!(out.demand_mm3 > 0)) return out;

  // The step takes voxels until they hold kFillMargin times the fill its demand needs at the
  // hardest tissue among them: no voxel is then asked for more than 1/kFillMargin of its fill.
  constexpr double kFillMargin = 2.0;
  const double unit_mm3 = field.frame().voxelVolumeMm3() / DS_FILL_FULL;
  const Taken taken = gather(field, contacts, params, kFillMargin * out.demand_mm3 / unit_mm3);
  out.candidates = uint32_t(candidates_.size());
  if (candidates_.empty()) return out;
  out.expected_mm3 = out.demand_mm3 * taken.hard_fill / taken.fill;

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
  return remove(volume, field, params, step, edits, taken.fill, out);
}

Cutter::Taken Cutter::gather(VoxelField& field, std::span<const ContactPoint> contacts, const SimParams& params,
                             double fill_needed) {
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
      r.lo[i] = std::max<int64_t>(0, -voxelFloor(rho - std::min(r.a[i], r.b[i])));  // ceil(min - rho)
      r.hi[i] = std::min<int64_t>(dim - 1, voxelFloor(std::max(r.a[i], r.b[i]) + rho));
    }
    return r;
  };

  // The contacts take turns: a step starts where the last one stopped, so that a step costs a
  // bounded time and, over a few steps, every contact gets its turn. The marks cover a window
  // centred on the first of them, wider than any head; a contact reaching outside it waits.
  const size_t n = contacts.size();
  const size_t first = n > 0 ? size_t(turn_ % n) : 0;
  Taken taken;
  double hardest = 0;
  size_t k0 = 0;
  while (k0 < n && !contacts[(first + k0) % n].cutting) ++k0;
  if (k0 == n) return taken;
  const Vec3 centre = field.toVoxel(contacts[(first + k0) % n].position);
  const int64_t half = int64_t(kMarkSide / 2);
  const int64_t origin[3] = {voxelFloor(centre.x) - half, voxelFloor(centre.y) - half, voxelFloor(centre.z) - half};
  clearMarks();

  // The voxels, each once, up to the per-step limit. Neighbouring contacts reach mostly the same
  // voxels: the mark is read before the distance is worked out.
  const double rho2 = rho * rho;
  for (size_t k = k0; k < n; ++k) {
    const ContactPoint& cp = contacts[(first + k) % n];
    if (!cp.cutting) continue;
    const Reach r = reach(cp);
    bool inside = true;
    for (int i = 0; i < 3; ++i) inside &= r.lo[i] >= origin[i] && r.hi[i] < origin[i] + int64_t(kMarkSide);
    if (!inside) continue;
    const Vec3 ab = r.b - r.a;
    const double len2 = dot(ab, ab);
    const double inv_len2 = len2 > 0 ? 1.0 / len2 : 0.0;
    for (int64_t z = r.lo[2]; z <= r.hi[2]; ++z)
      for (int64_t y = r.lo[1]; y <= r.hi[1]; ++y) {
        // Along the row only x changes: ap = (x - a.x, py, pz).
        const double py = double(y) - r.a.y, pz = double(z) - r.a.z;
        const double row_dot = py * ab.y + pz * ab.z;
        const uint64_t row_bit = (uint64_t(y - origin[1]) + kMarkSide * uint64_t(z - origin[2])) * kMarkSide -
                                 uint64_t(origin[0]);
        for (int64_t x = r.lo[0]; x <= r.hi[0]; ++x) {
          const uint64_t bit = row_bit + uint64_t(x);
          uint64_t& word = marks_[size_t(bit >> 6)];
          const uint64_t mask = uint64_t{1} << (bit & 63);
          if (word & mask) continue;
          const double px = double(x) - r.a.x;
          const double t = std::clamp((px * ab.x + row_dot) * inv_len2, 0.0, 1.0);
          const double dx = px - ab.x * t, dy = py - ab.y * t, dz = pz - ab.z * t;
          if (dx * dx + dy * dy + dz * dz > rho2) continue;
          if (word == 0) touch(size_t(bit >> 6));
          word |= mask;
          const Voxel v = field.voxel(x, y, z);
          if (v == 0 || params.tissue(voxelMaterial(v)).hardness <= 0) continue;
          candidates_.push_back({uint32_t(x), uint32_t(y), uint32_t(z), v});
          const double hardness = params.tissue(voxelMaterial(v)).hardness;
          taken.fill += voxelFill(v);
          taken.hard_fill += hardness * voxelFill(v);
          hardest = std::max(hardest, hardness);
          if (taken.fill >= fill_needed * hardest || candidates_.size() == max_voxels_) {
            turn_ = first + k;  // this contact may reach more: it starts the next step
            return taken;
          }
        }
      }
  }
  return taken;
}

void Cutter::touch(size_t word) {
  if (touched_.size() < touched_.capacity())
    touched_.push_back(word);
  else
    marks_overflow_ = true;
}

void Cutter::clearMarks() {
  if (marks_overflow_)
    std::fill(marks_.begin(), marks_.end(), 0ull);
  else
    for (const size_t w : touched_) marks_[w] = 0;
  touched_.clear();
  marks_overflow_ = false;
}

bool Cutter::roomForBricks(const BrickVolume& volume) {
  brick_keys_.clear();
  for (const Candidate& c : candidates_)
    brick_keys_.push_back((uint64_t(c.z >> DS_BRICK_LOG2) << 42) | (uint64_t(c.y >> DS_BRICK_LOG2) << 21) |
                          uint64_t(c.x >> DS_BRICK_LOG2));
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
  // Candidates come contact by contact, from a few bricks that neighbouring contacts share: the
  // bricks written keep their addresses in a small table instead of walking the index again.
  struct Written {
    BrickCoord brick{~0u, ~0u, ~0u};
    Voxel* voxels = nullptr;
  };
  std::array<Written, 16> written{};
  const uint64_t step_hash = mix64(step);
  for (const Candidate& c : candidates_) {
    const Material m = voxelMaterial(c.value);
    const uint32_t fill = voxelFill(c.value);
    const uint64_t index = uint64_t(c.x) + dim * (uint64_t(c.y) + dim * uint64_t(c.z));
    const double share = per_fill * params.tissue(m).hardness * fill;
    // floor, as both terms are >= 0; a voxel cannot lose more than it holds.
    const auto lost = uint32_t(std::min(share + dice(index, step_hash), double(DS_FILL_FULL)));
    const uint32_t left = lost >= fill ? 0u : fill - lost;
    if (left == fill) continue;
    const Voxel now = left == 0 ? Voxel{0} : makeVoxel(m, left);
    const BrickCoord b{c.x >> DS_BRICK_LOG2, c.y >> DS_BRICK_LOG2, c.z >> DS_BRICK_LOG2};
    Written& w = written[(b.x & 3u) | ((b.y & 1u) << 2) | ((b.z & 1u) << 3)];
    if (b.x != w.brick.x || b.y != w.brick.y || b.z != w.brick.z) w = {b, volume.writableBrick(b)};
    const uint32_t m7 = DS_BRICK_DIM - 1;
    w.voxels[layout::brickCoordToOffset(c.x & m7, c.y & m7, c.z & m7)] = now;
    field.written(c.x, c.y, c.z, now);
    if (edits != nullptr) edits->push(packVoxelEdit(index, now));
    ++out.voxels_changed;
    out.removed_mm3 += double(fill - left) * unit_mm3;
    out.removed_by_material_mm3[size_t(m)] += double(fill - left) * unit_mm3;
  }
  if (edits != nullptr) edits->publish();
  return out;
}

}  // namespace dentsim
