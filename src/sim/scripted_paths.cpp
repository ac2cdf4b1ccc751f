// Scripted preparations: probing the volume for the surface, the class I cavity path and the caries removal path.
#include "sim/scripted_paths.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <vector>

#include "model/tool_generator.h"
#include "volume/cut_zone.h"
#include "volume/tooth_frame.h"

namespace dentsim {

TissueBox toothBox(const BrickVolume& volume, const VolumeFrame& frame) { return brickBoxMm(toothBricks(volume), frame); }

// ---- 1. the cavity preparation path ----------------------------------------------------------------

Result<CavityPath> cavityPreparationPath(const BrickVolume& volume, const VolumeFrame& frame,
                                         const CavityPathSettings& s) {
  const std::string where = "cavity path";
  if (!(s.bur_radius_mm > 0) || !(s.speed_mm_s > 0) || !(s.laps > 0) || !(s.sample_s > 0) ||
      !(s.oval_x_mm > 0) || !(s.oval_y_mm > 0) || !(s.fossa_grid_mm > 0) || s.fossa_search_mm < 0 ||
      !(s.hold_s > 0) || !(s.descent_s > 0) || s.dwell_s < 0 || !(s.lift_s > 0))
    return makeError(where, "radius, speed, laps, sample period, oval, grid, hold, descent and lift must be > 0; "
                            "search and dwell >= 0");
  const TissueBox box = toothBox(volume, frame);
  if (box.empty()) return makeError(where, "the volume holds no tissue");
  SurfaceProbe probe(volume, frame, box);
  const double r = s.bur_radius_mm;

  // The fossa: where the bur comes to rest lowest near the centre of the crown.
  CavityPath out;
  out.crown_centre_mm = {0.5 * (box.lo.x + box.hi.x), 0.5 * (box.lo.y + box.hi.y), box.hi.z};
  const std::optional<Vec3> fossa =
      lowestRestingTip(probe, out.crown_centre_mm.x + s.search_offset_mm.x, out.crown_centre_mm.y + s.search_offset_mm.y, r,
                       s.fossa_search_mm, s.fossa_grid_mm);
  if (!fossa) return makeError(where, "no tissue under the bur within " + std::to_string(s.fossa_search_mm) +
                                          " mm of the search's centre");
  out.fossa_mm = *fossa;

  const Vec3 grip{0.0, 0.0, s.grip_z_mm};
  auto add = [&](double t, const Vec3& tip, double pedal) {
    PenSample sample;
    sample.t_s = t;
    sample.pen = PenRole::Drill;
    sample.pose.position = tip + grip;  // the bur is vertical: the grip is straight above the tip
    sample.pedal = pedal;
    out.path.samples.push_back(sample);
  };
  // Samples every sample_s over (t0, t0 + span], the last exactly at the end; f(t, u) with u in (0, 1].
  auto segment = [&](double t0, double span, const auto& f) {
    const auto count = std::max<int64_t>(1, int64_t(std::ceil(span / s.sample_s - 1e-9)));
    for (int64_t k = 1; k <= count; ++k) {
      const double u = double(k) / double(count);
      f(t0 + u * span, u);
    }
    return t0 + span;
  };

  // The bur cuts at a rate that does not depend on the force, so a bur held still sinks until it
  // meets the pen's target: a plunge at the fossa would bore a hole as deep as the press. So the bur
  // comes down on the outline itself and keeps moving; the target follows the untouched surface
  // press_mm below the bur's resting height, and a lap's groove is shallow beside the press.
  const double a = 0.5 * s.oval_x_mm, b = 0.5 * s.oval_y_mm;
  std::optional<double> start_z = probe.restingTip(fossa->x + a, fossa->y, r);
  if (!start_z) return makeError(where, "no tissue under the outline's start");
  const Vec3 start_tip{fossa->x + a, fossa->y, *start_z};
  auto rest = [&](double x, double y) { return probe.restingTip(x, y, r).value_or(start_tip.z); };

  // Above the outline's distal end (+x); the turbine starts at the end of the hold, then the pen
  // comes down to press and stays a moment.
  const Vec3 above = start_tip + Vec3{0, 0, s.approach_mm};
  const Vec3 pressed = start_tip - Vec3{0, 0, s.press_mm};
  add(0.0, above, 0.0);
  double t = segment(0.0, s.hold_s, [&](double ts, double u) { add(ts, above, u < 1.0 ? 0.0 : 1.0); });
  out.cut_start_s = t;
  t = segment(t, s.descent_s, [&](double ts, double u) { add(ts, above + (pressed - above) * u, 1.0); });
  if (s.dwell_s > 0) t = segment(t, s.dwell_s, [&](double ts, double) { add(ts, pressed, 1.0); });

  // The laps: arc length against angle, so the bur keeps its speed along the oval.
  constexpr int kArcSteps = 2048;
  std::vector<double> arc(kArcSteps + 1, 0.0);
  auto oval = [&](double theta) { return Vec3{fossa->x + a * std::cos(theta), fossa->y + b * std::sin(theta), 0.0}; };
  for (int k = 1; k <= kArcSteps; ++k) {
    const Vec3 p0 = oval(2.0 * std::numbers::pi * (k - 1) / kArcSteps), p1 = oval(2.0 * std::numbers::pi * k / kArcSteps);
    arc[size_t(k)] = arc[size_t(k - 1)] + norm(p1 - p0);
  }
  out.outline_mm = arc.back();
  const double total = s.laps * out.outline_mm;
  t = segment(t, total / s.speed_mm_s, [&](double ts, double u) {
    const double along = u * total;
    const double in_lap = std::fmod(along, out.outline_mm);
    const auto k = size_t(std::upper_bound(arc.begin(), arc.end(), in_lap) - arc.begin());
    const size_t k1 = std::clamp<size_t>(k, 1, kArcSteps);
    const double span = arc[k1] - arc[k1 - 1];
    const double frac = span > 0 ? (in_lap - arc[k1 - 1]) / span : 0.0;
    const Vec3 p = oval(2.0 * std::numbers::pi * (double(k1 - 1) + frac) / kArcSteps);
    const double deeper = s.step_down_mm * along / out.outline_mm;
    // The last sample lets go of the pedal: the bur stops as it lifts.
    add(ts, {p.x, p.y, rest(p.x, p.y) - s.press_mm - deeper}, u < 1.0 ? 1.0 : 0.0);
  });
  out.cut_end_s = t;

  // Lift off.
  const Vec3 last = out.path.samples.back().pose.position - grip;
  const Vec3 up{last.x, last.y, rest(last.x, last.y) + s.approach_mm};
  t = segment(t, s.lift_s, [&](double ts, double u) { add(ts, last + (up - last) * u, 0.0); });
  out.duration_s = t;
  return out;
}


// ---- 2. the caries removal path ------------------------------------------------------------------

std::optional<double> burHeadRadiusMm(const std::string& bur) {
  for (const ToolSpec& t : toolCatalog())
    if (t.name == bur && isBur(t.kind)) return 0.5 * t.head_diameter_mm;
  return std::nullopt;
}

LesionBox findLesion(const BrickVolume& volume) {
  LesionBox lesion;
  auto add = [&](uint32_t x, uint32_t y, uint32_t z, uint64_t f) {
    const uint32_t c[3] = {x, y, z};
    for (size_t a = 0; a < 3; ++a) {
      lesion.lo[a] = std::min(lesion.lo[a], c[a]);
      lesion.hi[a] = std::max(lesion.hi[a], c[a]);
    }
    lesion.fill += f;
  };
  volume.forEachBrick([&](const BrickView& b) {
    const uint32_t bx = b.coord.x * DS_BRICK_DIM, by = b.coord.y * DS_BRICK_DIM, bz = b.coord.z * DS_BRICK_DIM;
    if (b.uniform) {
      if (voxelMaterial(b.value) != Material::Caries || voxelFill(b.value) == 0) return;
      add(bx, by, bz, 0);
      add(bx + DS_BRICK_DIM - 1, by + DS_BRICK_DIM - 1, bz + DS_BRICK_DIM - 1, uint64_t(voxelFill(b.value)) * DS_BRICK_VOXELS);
      return;
    }
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      const Voxel v = b.voxels[i];
      if (voxelMaterial(v) != Material::Caries || voxelFill(v) == 0) continue;
      add(bx + (i & 7u), by + ((i >> 3) & 7u), bz + (i >> 6), voxelFill(v));
    }
  });
  return lesion;
}

namespace {

// The planner's view of the tooth around the lesion: the allowed zone, and which voxels earlier
// positions have already claimed for removal, both dense over one box.
class CariesPlanner {
 public:
  CariesPlanner(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params, double rate,
                const LesionBox& lesion, const CariesPathSettings& s)
      : volume_(volume), frame_(frame), params_(params), rate_(rate), r_(s.bur_radius_mm),
        pulp_margin_(s.pulp_margin_mm), masks_(volume.brickDim()) {
    const double v = frame.voxel_mm;
    markCariesAccess(volume, {0, 0, 1}, uint32_t(std::ceil(s.leeway_mm / v / DS_BRICK_DIM)) + 1, &masks_);
    leeway_.emplace(masks_, s.leeway_mm / v);
    // The box: the lesion widened by a ball and the leeway across the axis, from a ball below its
    // floor to the top of the tissue.
    const auto pad = int64_t(std::ceil((r_ + s.leeway_mm) / v)) + 2;
    const BrickBox tissue = tissueBricks(volume);
    lo_ = {int64_t(lesion.lo[0]) - pad, int64_t(lesion.lo[1]) - pad, int64_t(lesion.lo[2]) - pad};
    hi_ = {int64_t(lesion.hi[0]) + 1 + pad, int64_t(lesion.hi[1]) + 1 + pad,
           int64_t(tissue.hi.z + 1) * DS_BRICK_DIM + int64_t(std::ceil(2 * r_ / v)) + 1};
    zone_.emplace(volume, masks_, *leeway_, lo_, hi_);
    for (size_t a = 0; a < 3; ++a) size_[a] = std::max<int64_t>(0, std::min<int64_t>(hi_[a], volume.dim()) - std::max<int64_t>(lo_[a], 0));
    claimed_.assign(size_t(size_[0] * size_[1] * size_[2]), 0);
  }

  // The ball of the bur with its tip at `tip` [mm]: does it fit the allowed zone, and how much
  // target tissue does it hold [fill units]?
  struct Fit {
    bool fits = false;
    uint64_t target = 0;
  };
  Fit fit(const Vec3& tip) const {
    Fit out{true, 0};
    // Near the pulp a careful dentist leaves a layer of dentin over it rather than expose it.
    if (pulp_margin_ > 0)
      forBall(tip, [&](int64_t, int64_t, int64_t, Voxel vox) {
        return voxelFill(vox) == 0 || voxelMaterial(vox) != Material::Pulp || (out.fits = false);
      }, pulp_margin_);
    if (!out.fits) return out;
    forBall(tip, [&](int64_t x, int64_t y, int64_t z, Voxel vox) {
      if (voxelFill(vox) == 0 || voxelMaterial(vox) == Material::Empty) return true;
      if (!zone_->allowed(x, y, z)) return out.fits = false;
      if (zone_->target(x, y, z)) out.target += voxelFill(vox);
      return true;
    });
    return out;
  }

  // Claims the ball's tissue that no earlier position claimed: the seconds it takes to cut at full
  // speed, and its volume into the plan's totals [mm^3].
  double claim(const Vec3& tip, double* caries_mm3, double* healthy_mm3) {
    double seconds = 0.0;
    const double voxel_mm3 = frame_.voxelVolumeMm3();
    forBall(tip, [&](int64_t x, int64_t y, int64_t z, Voxel vox) {
      // Positions that fit hold tissue only inside the box; the test keeps the index in range anyway.
      if (voxelFill(vox) == 0 || voxelMaterial(vox) == Material::Empty || !inBox(x, y, z)) return true;
      uint8_t& c = claimed_[index(x, y, z)];
      if (c) return true;
      c = 1;
      const double mm3 = double(voxelFill(vox)) / DS_FILL_FULL * voxel_mm3;
      const double hardness = params_.tissue(voxelMaterial(vox)).hardness;
      if (hardness > 0) seconds += mm3 / (rate_ * hardness);
      (voxelMaterial(vox) == Material::Caries ? *caries_mm3 : *healthy_mm3) += mm3;
      return true;
    });
    return seconds;
  }

  // The voxel centre (x, y, z) in mm.
  Vec3 centre(int64_t x, int64_t y, int64_t z) const {
    const double v = frame_.voxel_mm;
    return {frame_.origin_mm[0] + (double(x) + 0.5) * v, frame_.origin_mm[1] + (double(y) + 0.5) * v,
            frame_.origin_mm[2] + (double(z) + 0.5) * v};
  }

 private:
  // Calls f(x, y, z, voxel) for the grid's voxels whose centres lie in the ball (grown by `extra`
  // [mm]), until f returns false. (The zone answers "not allowed" for tissue beyond its box.)
  template <typename F>
  void forBall(const Vec3& tip, F&& f, double extra = 0.0) const {
    const double v = frame_.voxel_mm;
    const Vec3 c = tip + Vec3{0, 0, r_};
    const double r = r_ + extra;
    const int64_t dim = volume_.dim();
    int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max<int64_t>(0, int64_t(std::floor((c[a] - r - frame_.origin_mm[size_t(a)]) / v)));
      hi[a] = std::min<int64_t>(dim - 1, int64_t(std::ceil((c[a] + r - frame_.origin_mm[size_t(a)]) / v)));
    }
    const double r2 = r * r;
    for (int64_t z = lo[2]; z <= hi[2]; ++z)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t x = lo[0]; x <= hi[0]; ++x) {
          const Vec3 d = centre(x, y, z) - c;
          if (dot(d, d) > r2) continue;
          if (!f(x, y, z, volume_.voxel(uint32_t(x), uint32_t(y), uint32_t(z)))) return;
        }
  }
  bool inBox(int64_t x, int64_t y, int64_t z) const {
    return x >= lo_[0] && y >= lo_[1] && z >= lo_[2] && x < hi_[0] && y < hi_[1] && z < hi_[2];
  }
  size_t index(int64_t x, int64_t y, int64_t z) const {
    const int64_t bx = std::max<int64_t>(lo_[0], 0), by = std::max<int64_t>(lo_[1], 0), bz = std::max<int64_t>(lo_[2], 0);
    return size_t((x - bx) + size_[0] * ((y - by) + size_[1] * (z - bz)));
  }

  const BrickVolume& volume_;
  const VolumeFrame& frame_;
  const SimParams& params_;
  double rate_;                 // [mm^3/s] at hardness 1, full speed
  double r_;                    // the ball's radius [mm]
  double pulp_margin_;          // no position's ball comes nearer the pulp than this [mm]
  TargetMasks masks_;
  std::optional<LeewayField> leeway_;
  std::optional<ZoneGrid> zone_;
  std::array<int64_t, 3> lo_{}, hi_{}, size_{};
  std::vector<uint8_t> claimed_;
};

}  // namespace

Result<CariesPath> cariesRemovalPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                     const std::string& bur, const CariesPathSettings& settings) {
  const std::string where = "caries path";
  CariesPathSettings s = settings;
  if (s.bur_radius_mm == 0) {
    const std::optional<double> r = burHeadRadiusMm(bur);
    if (!r) return makeError(where, bur + " is not a bur of the tool catalog: give the head's radius");
    s.bur_radius_mm = *r;
  }
  if (!(s.bur_radius_mm > 0) || !(s.grid_mm > 0) || !(s.layer_mm > 0) || s.press_mm < 0 || !(s.margin > 0) ||
      !(s.speed_mm_s > 0) || !(s.hop_speed_mm_s > 0) || !(s.hold_s > 0) || !(s.descent_s > 0) || !(s.lift_s > 0) ||
      !(s.sample_s > 0) || s.approach_mm < 0 || s.leeway_mm < 0)
    return makeError(where, "radius, grid, layer, margin, speeds, hold, descent, lift and sample period must be > 0; "
                            "press, approach and leeway >= 0");
  const double ability = params.cuttingAbility(bur);
  if (!(ability > 0)) return makeError(where, "the parameter set gives " + bur + " no cutting ability");
  const double rate = params.cutting.removal_rate_mm3_per_s * ability;  // [mm^3/s] at hardness 1, full speed
  if (!(rate > 0)) return makeError(where, "the parameter set's removal rate is 0");
  const LesionBox lesion = findLesion(volume);
  if (lesion.empty()) return makeError(where, "the volume holds no caries");

  CariesPath out;
  const double v = frame.voxel_mm;
  for (int a = 0; a < 3; ++a) {
    out.lesion_lo_mm[a] = frame.origin_mm[size_t(a)] + double(lesion.lo[a]) * v;
    out.lesion_hi_mm[a] = frame.origin_mm[size_t(a)] + double(lesion.hi[a] + 1) * v;
  }
  out.lesion_mm3 = double(lesion.fill) / DS_FILL_FULL * frame.voxelVolumeMm3();
  CariesPlanner planner(volume, frame, params, rate, lesion, s);
  const TissueBox box = tissueBox(volume, frame);
  const double top = box.hi.z + s.approach_mm;  // clear of the tooth

  // The positions, layer by layer from the top; rows along x, every other row backwards.
  const auto columns = int64_t(std::floor((out.lesion_hi_mm.x - out.lesion_lo_mm.x) / s.grid_mm)) + 1;
  const auto rows = int64_t(std::floor((out.lesion_hi_mm.y - out.lesion_lo_mm.y) / s.grid_mm)) + 1;
  const double x0 = 0.5 * (out.lesion_lo_mm.x + out.lesion_hi_mm.x) - 0.5 * double(columns - 1) * s.grid_mm;
  const double y0 = 0.5 * (out.lesion_lo_mm.y + out.lesion_hi_mm.y) - 0.5 * double(rows - 1) * s.grid_mm;
  const double floor_z = out.lesion_lo_mm.z;
  const auto layers = int64_t(std::ceil((box.hi.z - floor_z) / s.layer_mm));
  // A lesion far larger than the bur (a tooth in the wrong units, say) would take hours to plan.
  constexpr double kMaxCandidates = 4e6;
  if (double(columns) * double(rows) * double(layers + 1) > kMaxCandidates) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "the lesion spans %.1f x %.1f mm under %.1f mm of tooth: too large for a scripted removal with a "
                  "%.2f mm bur (are the tooth's units right?)",
                  out.lesion_hi_mm.x - out.lesion_lo_mm.x, out.lesion_hi_mm.y - out.lesion_lo_mm.y, box.hi.z - floor_z,
                  2 * s.bur_radius_mm);
    return makeError(where, text);
  }
  // A column's floor: the lowest tip that fits there. The pen never presses below it.
  struct Position {
    Vec3 tip;
    size_t column = 0;
    bool row_end = false;  // the last of its row: the bur turns here
  };
  std::vector<double> floor_of(size_t(columns * rows), HUGE_VAL);
  std::vector<std::vector<Position>> plan;
  for (int64_t k = layers; k >= 0; --k) {
    const double z = floor_z + double(k) * s.layer_mm;
    std::vector<Position> layer;
    for (int64_t j = 0; j < rows; ++j) {
      std::vector<Position> row;
      for (int64_t i = 0; i < columns; ++i) {
        const Vec3 tip{x0 + double(i) * s.grid_mm, y0 + double(j) * s.grid_mm, z};
        const CariesPlanner::Fit f = planner.fit(tip);
        if (!f.fits) continue;
        const auto column = size_t(i + columns * j);
        floor_of[column] = std::min(floor_of[column], z);
        if (f.target > 0) row.push_back({tip, column});
      }
      if (j % 2 == 1) std::reverse(row.begin(), row.end());
      if (!row.empty()) row.back().row_end = true;
      layer.insert(layer.end(), row.begin(), row.end());
    }
    if (!layer.empty()) plan.push_back(std::move(layer));
  }
  if (plan.empty()) return makeError(where, "no position of the bur fits the allowed zone around the lesion");
  out.layers = int(plan.size());

  const Vec3 grip{0.0, 0.0, s.grip_z_mm};
  auto add = [&](double t, const Vec3& tip, double pedal) {
    PenSample sample;
    sample.t_s = t;
    sample.pen = PenRole::Drill;
    sample.pose.position = tip + grip;  // vertical bur: the grip straight above the tip
    sample.pedal = pedal;
    out.path.samples.push_back(sample);
  };
  // A straight move from a to b [mm, targets], sampled every sample_s.
  double t = 0.0;
  auto move = [&](const Vec3& a, const Vec3& b, double duration, double pedal) {
    const auto n = std::max<int64_t>(1, int64_t(std::floor(duration / s.sample_s + 1e-9)));
    for (int64_t k = 1; k <= n; ++k) add(t + duration * double(k) / double(n), a + (b - a) * (double(k) / double(n)), pedal);
    t += duration;
  };
  // Can the ball travel straight from a to b without leaving the zone? Checked every half grid step.
  auto straight = [&](const Vec3& a, const Vec3& b) {
    const auto n = int64_t(std::ceil(norm(b - a) / (0.5 * s.grid_mm)));
    for (int64_t k = 1; k < n; ++k)
      if (!planner.fit(a + (b - a) * (double(k) / double(n))).fits) return false;
    return true;
  };

  // Above the first position; the turbine starts at the end of the hold, then the pen comes down.
  const Vec3 first = plan.front().front().tip;
  Vec3 above{first.x, first.y, top};
  add(0.0, above, 0.0);
  move(above, above, s.hold_s, 0.0);
  out.path.samples.back().pedal = 1.0;
  out.cut_start_s = t;
  double caries_mm3 = 0.0, healthy_mm3 = 0.0;
  Vec3 at = above;  // the last target
  std::optional<Vec3> last_tip;
  for (const std::vector<Position>& layer : plan)
    for (const Position& p : layer) {
      const Vec3& tip = p.tip;
      const Vec3 target{tip.x, tip.y, std::max(tip.z - s.press_mm, floor_of[p.column] - s.floor_overshoot_mm)};
      if (!last_tip || !straight(*last_tip, tip)) {
        // Over the position, then down to it: the column above a position that fits fits too.
        const Vec3 up{at.x, at.y, top}, over{tip.x, tip.y, top};
        if (norm(up - at) > 0) move(at, up, norm(up - at) / s.hop_speed_mm_s, 1.0);
        if (norm(over - up) > 0) move(up, over, norm(over - up) / s.hop_speed_mm_s, 1.0);
        at = over;
        if (last_tip) ++out.hops;
      }
      const double seconds = planner.claim(tip, &caries_mm3, &healthy_mm3);
      // At a row's end the bur, which trails its target sideways, is given time to reach it.
      const double duration =
          std::max({norm(target - at) / s.speed_mm_s, s.margin * seconds, 1e-3}) + (p.row_end ? s.turn_s : 0.0);
      move(at, target, duration, 1.0);
      at = target;
      last_tip = tip;
      ++out.positions;
    }
  out.cut_end_s = t;
  out.planned_caries_mm3 = caries_mm3;
  out.planned_healthy_mm3 = healthy_mm3;

  // Pedal up, lift.
  move(at, {at.x, at.y, top}, s.lift_s, 0.0);
  out.duration_s = t;
  return out;
}

}  // namespace dentsim
