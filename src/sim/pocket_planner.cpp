// The pocket planner: bur heads from the catalog, rays into the tooth, and the paced, layered path through a pocket's columns.
#include "sim/pocket_planner.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "model/tool_generator.h"
#include "sim/surface_probe.h"

namespace dentsim {

// ---- 1. the head, and frames along the bur's axis -------------------------------------------------------

Result<BurHead> burHead(const std::string& bur) {
  for (const ToolSpec& t : toolCatalog()) {
    if (t.name != bur) continue;
    if (t.kind == ToolKind::RoundBur) return BurHead{true, 0.5 * t.head_diameter_mm, t.head_diameter_mm};
    if (t.kind == ToolKind::FissureBur) return BurHead{false, 0.5 * t.head_diameter_mm, t.cutting_length_mm};
    // A tapered bur by its narrowest part, the tip: what it claims is never more than it cuts.
    if (t.kind == ToolKind::ChamferBur) return BurHead{true, 0.5 * t.tip_diameter_mm, t.tip_diameter_mm};
    if (t.kind == ToolKind::ShoulderBur) return BurHead{false, 0.5 * t.tip_diameter_mm, t.cutting_length_mm};
    break;
  }
  return makeError(bur, "not a bur of the tool catalog");
}

AxisFrame AxisFrame::along(const Vec3& origin, const Vec3& axis, const Vec3& u_hint) {
  AxisFrame f;
  f.origin = origin;
  f.axis = normalized(axis);
  f.e_u = normalized(u_hint - f.axis * dot(u_hint, f.axis));
  f.e_v = cross(f.axis, f.e_u);
  return f;
}

// ---- 2. rays into the tooth --------------------------------------------------------------------------------

std::optional<TissueRay::Hit> TissueRay::first(const Vec3& from, const Vec3& dir, double max_mm) {
  const double step = field_.voxelMm();
  auto inside = [&](double d) { return field_.sample(field_.toVoxel(from + dir * d)).phi > 0; };
  auto materialAt = [&](double d) { return field_.sample(field_.toVoxel(from + dir * d)).material; };
  const auto steps = int64_t(std::ceil(max_mm / step));
  bool outside_before = true;  // the step before lay outside all tissue: there is a crossing to bisect
  for (int64_t i = 0; i <= steps; ++i) {
    double below = double(i) * step;  // "below" the surface: inside
    if (!inside(below)) {
      outside_before = true;
      continue;
    }
    // An adjacent tooth is in the way, not the tooth the paths are worked out on: the ray passes
    // through it. Where it touches the tooth, the tooth begins at the first step past it.
    if (materialAt(below + 0.25 * step) == Material::Neighbour) {
      outside_before = false;
      continue;
    }
    double above = i == 0 ? 0.0 : below - step;
    if (i > 0 && outside_before)
      for (int k = 0; k < 12; ++k) {  // to 1/4096 voxel
        const double mid = 0.5 * (above + below);
        (inside(mid) ? below : above) = mid;
      }
    Hit hit;
    hit.distance_mm = 0.5 * (above + below);
    hit.point = from + dir * hit.distance_mm;
    // The tissue a quarter voxel in: the surface voxel's own, not the air's.
    hit.material = materialAt(below + 0.25 * step);
    return hit;
  }
  return std::nullopt;
}

// ---- 3. the pocket -------------------------------------------------------------------------------------------

namespace {

// Which voxels the positions so far have claimed for removal, over one box of the grid, and what
// each new claim costs in time at the parameter set's rates.
class TissueLedger {
 public:
  TissueLedger(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params, const BurHead& head,
               const Vec3& axis, double rate, const Vec3& lo_mm, const Vec3& hi_mm)
      : volume_(volume), frame_(frame), params_(params), head_(head), axis_(axis), rate_(rate) {
    box(lo_mm, hi_mm, lo_, hi_);
    for (size_t a = 0; a < 3; ++a) size_[a] = std::max<int64_t>(0, hi_[a] - lo_[a] + 1);
    claimed_.assign(size_t(size_[0] * size_[1] * size_[2]), false);
  }

  // Claims the tissue in the head with its tip at `tip` that no earlier position claimed: the
  // seconds it takes to cut at full speed; its volume is added to *mm3.
  double claim(const Vec3& tip, double* mm3) {
    const double r = head_.radius_mm, r2 = r * r;
    const Vec3 end = tip + axis_ * head_.length_mm;
    const Vec3 pad{r, r, r};
    int64_t lo[3], hi[3];
    box(min(tip, end) - pad, max(tip, end) + pad, lo, hi);
    const double v = frame_.voxel_mm, voxel_mm3 = frame_.voxelVolumeMm3();
    double seconds = 0.0;
    for (int64_t z = std::max(lo[2], lo_[2]); z <= std::min(hi[2], hi_[2]); ++z)
      for (int64_t y = std::max(lo[1], lo_[1]); y <= std::min(hi[1], hi_[1]); ++y)
        for (int64_t x = std::max(lo[0], lo_[0]); x <= std::min(hi[0], hi_[0]); ++x) {
          const Vec3 c{frame_.origin_mm[0] + (double(x) + 0.5) * v, frame_.origin_mm[1] + (double(y) + 0.5) * v,
                       frame_.origin_mm[2] + (double(z) + 0.5) * v};
          const Vec3 d = c - tip;
          const double along = dot(d, axis_);
          if (head_.round) {
            const Vec3 e = d - axis_ * r;
            if (dot(e, e) > r2) continue;
          } else {
            if (along < 0 || along > head_.length_mm) continue;
            const Vec3 e = d - axis_ * along;
            if (dot(e, e) > r2) continue;
          }
          const Voxel vox = volume_.voxel(uint32_t(x), uint32_t(y), uint32_t(z));
          if (voxelFill(vox) == 0 || voxelMaterial(vox) == Material::Empty) continue;
          const size_t i = size_t((x - lo_[0]) + size_[0] * ((y - lo_[1]) + size_[1] * (z - lo_[2])));
          if (claimed_[i]) continue;
          claimed_[i] = true;
          const double amount = double(voxelFill(vox)) / DS_FILL_FULL * voxel_mm3;
          *mm3 += amount;
          const double hardness = params_.tissue(voxelMaterial(vox)).hardness;
          if (hardness > 0) seconds += amount / (rate_ * hardness);
        }
    return seconds;
  }

 private:
  static Vec3 min(const Vec3& a, const Vec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
  static Vec3 max(const Vec3& a, const Vec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
  // The voxel indices of a box [mm], clipped to the grid.
  void box(const Vec3& lo_mm, const Vec3& hi_mm, int64_t* lo, int64_t* hi) const {
    const auto last = int64_t(volume_.dim()) - 1;
    for (size_t a = 0; a < 3; ++a) {
      lo[a] = std::clamp<int64_t>(int64_t(std::floor((lo_mm[int(a)] - frame_.origin_mm[a]) / frame_.voxel_mm)), 0, last);
      hi[a] = std::clamp<int64_t>(int64_t(std::floor((hi_mm[int(a)] - frame_.origin_mm[a]) / frame_.voxel_mm)), 0, last);
    }
  }

  const BrickVolume& volume_;
  const VolumeFrame& frame_;
  const SimParams& params_;
  BurHead head_;
  Vec3 axis_;
  double rate_;                 // [mm^3/s] at hardness 1, full speed
  int64_t lo_[3]{}, hi_[3]{}, size_[3]{};
  std::vector<bool> claimed_;
};

using GridKey = std::pair<int64_t, int64_t>;

}  // namespace

Result<PocketPath> pocketPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                              const std::string& bur, const AxisFrame& axis, const std::vector<PocketColumn>& columns,
                              const PocketSettings& s) {
  const std::string where = "pocket path";
  if (columns.empty()) return makeError(where, "no columns to cut");
  if (!(s.grid_mm > 0) || !(s.layer_mm > 0) || s.press_mm < 0 || s.floor_overshoot_mm < 0 || !(s.margin > 0) ||
      !(s.speed_mm_s > 0) || !(s.hop_speed_mm_s > 0) || s.turn_s < 0 || s.approach_mm < 0 || !(s.hold_s > 0) ||
      !(s.lift_s > 0) || !(s.sample_s > 0))
    return makeError(where, "grid, layer, margin, speeds, hold, lift and sample period must be > 0; press, overshoot, "
                            "turn and approach >= 0");
  auto head = burHead(bur);
  if (!head) return makeError(where, head.message());
  const double rate = params.cutting.removal_rate_mm3_per_s * params.cuttingAbility(bur);  // at hardness 1
  if (!(rate > 0)) return makeError(where, "the parameter set gives " + bur + " no cutting ability");
  const TissueBox box = tissueBox(volume, frame);
  if (box.empty()) return makeError(where, "the volume holds no tissue");

  // Clear of the tooth: above the highest corner of its box along the axis.
  double clear_h = -HUGE_VAL;
  for (int corner = 0; corner < 8; ++corner)
    clear_h = std::max(clear_h, axis.height({corner & 1 ? box.hi.x : box.lo.x, corner & 2 ? box.hi.y : box.lo.y,
                                             corner & 4 ? box.hi.z : box.lo.z}));
  clear_h += s.approach_mm;

  // Each column's surface along the axis; the pocket's top is the highest.
  std::map<GridKey, size_t> index;
  std::vector<double> top(columns.size(), -HUGE_VAL);
  TissueRay ray(volume, frame);
  double top_h = -HUGE_VAL, lowest_floor = HUGE_VAL;
  for (size_t c = 0; c < columns.size(); ++c) {
    const PocketColumn& col = columns[c];
    index[{std::lround(col.u / s.grid_mm), std::lround(col.v / s.grid_mm)}] = c;
    lowest_floor = std::min(lowest_floor, col.floor_h);
    if (col.floor_h >= clear_h) continue;
    if (auto hit = ray.first(axis.at(col.u, col.v, clear_h), axis.axis * -1.0, clear_h - col.floor_h)) {
      top[c] = clear_h - hit->distance_mm;
      top_h = std::max(top_h, top[c]);
    }
  }
  if (top_h == -HUGE_VAL) return makeError(where, "no tissue above the floor under any column");

  // The ledger covers every head the plan may place.
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const PocketColumn& col : columns)
    for (double h : {col.floor_h, top_h + head->length_mm})
      for (int a = 0; a < 3; ++a) {
        const Vec3 p = axis.at(col.u, col.v, h);
        lo[a] = std::min(lo[a], p[a] - head->radius_mm - frame.voxel_mm);
        hi[a] = std::max(hi[a], p[a] + head->radius_mm + frame.voxel_mm);
      }
  TissueLedger ledger(volume, frame, params, *head, axis.axis, rate, lo, hi);

  // The positions, layer by layer from the top; in a layer, rows of equal v, every other row
  // backwards, and every other layer in the opposite order, so that each starts where the last ended.
  struct Position {
    size_t column = 0;
    double h = 0.0;        // the tip's height
    bool row_end = false;  // the last of its row: the bur turns here
  };
  std::vector<size_t> order(columns.size());
  for (size_t c = 0; c < order.size(); ++c) order[c] = c;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return columns[a].v != columns[b].v ? columns[a].v < columns[b].v : columns[a].u < columns[b].u;
  });
  const auto layers = int64_t(std::ceil((top_h - lowest_floor) / s.layer_mm - 1e-9));
  std::vector<std::vector<Position>> plan;
  for (int64_t k = 0; k <= layers; ++k) {
    const double h = top_h - double(k) * s.layer_mm;
    std::vector<Position> layer;
    size_t row_start = 0;
    int row = 0;
    for (size_t i = 0; i <= order.size(); ++i) {
      const bool row_ends = i == order.size() || (i > 0 && columns[order[i]].v != columns[order[i - 1]].v);
      if (row_ends && i > row_start) {
        std::vector<Position> cells;
        for (size_t j = row_start; j < i; ++j) {
          const PocketColumn& col = columns[order[j]];
          // The layer's positions over the column, and its floor once: the first layer at or below it.
          if (top[order[j]] == -HUGE_VAL || h <= col.floor_h - s.layer_mm + 1e-9) continue;
          cells.push_back({order[j], std::max(h, col.floor_h)});
        }
        if (row % 2 == 1) std::reverse(cells.begin(), cells.end());
        if (!cells.empty()) cells.back().row_end = true;
        layer.insert(layer.end(), cells.begin(), cells.end());
        ++row;
        row_start = i;
      }
    }
    if (k % 2 == 1) std::reverse(layer.begin(), layer.end());
    if (!layer.empty()) plan.push_back(std::move(layer));
  }

  PocketPath out;
  const Quat rotation = axis.rotation();
  auto add = [&](double t, const Vec3& tip, double pedal) {
    PenSample sample;
    sample.t_s = t;
    sample.pen = PenRole::Drill;
    sample.pose.position = tip + axis.axis * s.grip_mm;
    sample.pose.rotation = rotation;
    sample.pedal = pedal;
    out.path.samples.push_back(sample);
  };
  double t = 0.0;
  auto move = [&](const Vec3& a, const Vec3& b, double duration, double pedal) {
    const auto n = std::max<int64_t>(1, int64_t(std::floor(duration / s.sample_s + 1e-9)));
    for (int64_t k = 1; k <= n; ++k) add(t + duration * double(k) / double(n), a + (b - a) * (double(k) / double(n)), pedal);
    t += duration;
  };
  // Can the head go straight from tip a to tip b inside the pocket? Every half grid step on the way
  // must lie over a column, at or above its floor.
  auto straight = [&](const Vec3& a, const Vec3& b) {
    const auto n = int64_t(std::ceil(norm(b - a) / (0.5 * s.grid_mm)));
    for (int64_t k = 1; k < n; ++k) {
      const Vec3 p = a + (b - a) * (double(k) / double(n));
      const Vec3 q = p - axis.origin;
      auto it = index.find({std::lround(dot(q, axis.e_u) / s.grid_mm), std::lround(dot(q, axis.e_v) / s.grid_mm)});
      if (it == index.end() || axis.height(p) < columns[it->second].floor_h - 1e-9) return false;
    }
    return true;
  };
  auto tipOf = [&](const Position& p) { return axis.at(columns[p.column].u, columns[p.column].v, p.h); };

  // Clear over the first position; the turbine starts at the end of the hold.
  const Vec3 first = tipOf(plan.front().front());
  Vec3 at = first + axis.axis * (clear_h - axis.height(first));
  add(0.0, at, 0.0);
  move(at, at, s.hold_s, 0.0);
  out.path.samples.back().pedal = 1.0;
  out.cut_start_s = t;
  std::optional<Vec3> last_tip;
  for (const std::vector<Position>& layer : plan) {
    bool used = false;
    for (const Position& p : layer) {
      const Vec3 tip = tipOf(p);
      const double seconds = ledger.claim(tip, &out.planned_mm3);
      if (seconds <= 0) continue;  // nothing new here: earlier positions took it, or there is none
      const PocketColumn& col = columns[p.column];
      const Vec3 target = axis.at(col.u, col.v, std::max(p.h - s.press_mm, col.floor_h - s.floor_overshoot_mm));
      if (!last_tip || !straight(*last_tip, tip)) {
        // Out along the axis, across, and in again to a layer over the position (cut already).
        const Vec3 out_there = at + axis.axis * (clear_h - axis.height(at));
        const Vec3 over = tip + axis.axis * (clear_h - p.h);
        const Vec3 near = tip + axis.axis * std::min(s.layer_mm, clear_h - p.h);
        for (const Vec3& w : {out_there, over, near}) {
          if (norm(w - at) > 0) move(at, w, norm(w - at) / s.hop_speed_mm_s, 1.0);
          at = w;
        }
        if (last_tip) ++out.hops;
      }
      const double duration =
          std::max({norm(target - at) / s.speed_mm_s, s.margin * seconds, 1e-3}) + (p.row_end ? s.turn_s : 0.0);
      move(at, target, duration, 1.0);
      at = target;
      last_tip = tip;
      used = true;
      ++out.positions;
    }
    if (used) ++out.layers;
  }
  if (out.positions == 0) return makeError(where, "no position of the bur adds tissue to the cut");
  out.cut_end_s = t;
  // Pedal up, and out along the axis.
  move(at, at + axis.axis * (clear_h - axis.height(at)), s.lift_s, 0.0);
  out.duration_s = t;
  return out;
}

}  // namespace dentsim
