// Scripted preparations: probing the volume for the surface, the class I cavity path and the caries removal path.
#include "sim/scripted_paths.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "sim/voxel_field.h"

namespace dentsim {

// ---- probing the volume -------------------------------------------------------------------------

TissueBox tissueBox(const BrickVolume& volume, const VolumeFrame& frame) {
  const BrickBox b = tissueBricks(volume);
  TissueBox box;
  if (b.empty()) return box;
  const double brick_mm = frame.voxel_mm * DS_BRICK_DIM;
  const uint32_t lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = frame.origin_mm[size_t(a)] + double(lo[a]) * brick_mm;
    box.hi[a] = frame.origin_mm[size_t(a)] + double(hi[a] + 1) * brick_mm;
  }
  return box;
}

namespace {

// Column probes of one volume: the topmost crossing of the haptic field's surface (phi = 0, what the
// student feels and sees), searched downward from above the tissue one voxel at a time.
class SurfaceProbe {
 public:
  SurfaceProbe(const BrickVolume& volume, const VolumeFrame& frame, const TissueBox& box)
      : field_(volume, frame), top_mm_(box.hi.z + frame.voxel_mm), bottom_mm_(box.lo.z - frame.voxel_mm) {}

  // Height [mm] of the surface in the column through (x, y); nullopt when the column holds no tissue.
  std::optional<double> surface(double x, double y) {
    const double step = field_.voxelMm();
    auto inside = [&](double z) { return field_.sample(field_.toVoxel({x, y, z})).phi > 0; };
    if (inside(top_mm_)) return top_mm_;
    const auto steps = int64_t(std::ceil((top_mm_ - bottom_mm_) / step));
    for (int64_t i = 1; i <= steps; ++i) {
      double below = top_mm_ - double(i) * step;
      if (!inside(below)) continue;
      double above = below + step;
      for (int k = 0; k < 12; ++k) {  // to 1/4096 voxel
        const double mid = 0.5 * (above + below);
        (inside(mid) ? below : above) = mid;
      }
      return 0.5 * (above + below);
    }
    return std::nullopt;
  }

  // The tip height of a ball of radius r [mm] coming down over (x, y): the highest of the columns
  // under it, each lowered by the ball's sag at its distance from the axis.
  std::optional<double> restingTip(double x, double y, double r) {
    constexpr double kRings[] = {0.0, 0.35, 0.7, 0.95};  // ring radius / r
    constexpr int kSpokes = 12;
    std::optional<double> best;
    for (double ring : kRings) {
      const double rho = ring * r;
      const int spokes = ring == 0.0 ? 1 : kSpokes;
      const double sag = r - std::sqrt(r * r - rho * rho);
      for (int k = 0; k < spokes; ++k) {
        const double angle = 2.0 * std::numbers::pi * double(k) / kSpokes;
        const std::optional<double> h = surface(x + rho * std::cos(angle), y + rho * std::sin(angle));
        if (h && (!best || *h - sag > *best)) best = *h - sag;
      }
    }
    return best;
  }

 private:
  VoxelField field_;
  double top_mm_;
  double bottom_mm_;
};

}  // namespace

std::optional<double> restingTipHeight(const BrickVolume& volume, const VolumeFrame& frame, double x_mm, double y_mm,
                                       double radius_mm) {
  const TissueBox box = tissueBox(volume, frame);
  if (box.empty()) return std::nullopt;
  SurfaceProbe probe(volume, frame, box);
  return probe.restingTip(x_mm, y_mm, radius_mm);
}

// ---- 1. the cavity preparation path ----------------------------------------------------------------

Result<CavityPath> cavityPreparationPath(const BrickVolume& volume, const VolumeFrame& frame,
                                         const CavityPathSettings& s) {
  const std::string where = "cavity path";
  if (!(s.bur_radius_mm > 0) || !(s.speed_mm_s > 0) || !(s.laps > 0) || !(s.sample_s > 0) ||
      !(s.oval_x_mm > 0) || !(s.oval_y_mm > 0) || !(s.fossa_grid_mm > 0) || s.fossa_search_mm < 0 ||
      !(s.hold_s > 0) || !(s.descent_s > 0) || s.dwell_s < 0 || !(s.lift_s > 0))
    return makeError(where, "radius, speed, laps, sample period, oval, grid, hold, descent and lift must be > 0; "
                            "search and dwell >= 0");
  const TissueBox box = tissueBox(volume, frame);
  if (box.empty()) return makeError(where, "the volume holds no tissue");
  SurfaceProbe probe(volume, frame, box);
  const double r = s.bur_radius_mm;

  // The fossa: where the bur comes to rest lowest near the centre of the crown.
  CavityPath out;
  out.crown_centre_mm = {0.5 * (box.lo.x + box.hi.x), 0.5 * (box.lo.y + box.hi.y), box.hi.z};
  const auto n = int(std::floor(s.fossa_search_mm / s.fossa_grid_mm));
  std::optional<Vec3> fossa;
  for (int j = -n; j <= n; ++j)
    for (int i = -n; i <= n; ++i) {
      if (i * i + j * j > n * n) continue;
      const double x = out.crown_centre_mm.x + s.fossa_grid_mm * i, y = out.crown_centre_mm.y + s.fossa_grid_mm * j;
      const std::optional<double> z = probe.restingTip(x, y, r);
      if (z && (!fossa || *z < fossa->z)) fossa = Vec3{x, y, *z};
    }
  if (!fossa) return makeError(where, "no tissue under the bur within " + std::to_string(s.fossa_search_mm) +
                                          " mm of the crown's centre");
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

namespace {

// The caries voxels' box (grid indices, inclusive) and their solid volume in fill units.
struct Lesion {
  uint32_t lo[3] = {UINT32_MAX, UINT32_MAX, UINT32_MAX};
  uint32_t hi[3] = {0, 0, 0};
  uint64_t fill = 0;
  void add(uint32_t x, uint32_t y, uint32_t z, uint64_t f) {
    const uint32_t c[3] = {x, y, z};
    for (size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
    fill += f;
  }
};

Lesion findLesion(const BrickVolume& volume) {
  Lesion lesion;
  volume.forEachBrick([&](const BrickView& b) {
    const uint32_t bx = b.coord.x * DS_BRICK_DIM, by = b.coord.y * DS_BRICK_DIM, bz = b.coord.z * DS_BRICK_DIM;
    if (b.uniform) {
      if (voxelMaterial(b.value) != Material::Caries || voxelFill(b.value) == 0) return;
      lesion.add(bx, by, bz, 0);
      lesion.add(bx + DS_BRICK_DIM - 1, by + DS_BRICK_DIM - 1, bz + DS_BRICK_DIM - 1,
                 uint64_t(voxelFill(b.value)) * DS_BRICK_VOXELS);
      return;
    }
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      const Voxel v = b.voxels[i];
      if (voxelMaterial(v) != Material::Caries || voxelFill(v) == 0) continue;
      lesion.add(bx + (i & 7u), by + ((i >> 3) & 7u), bz + (i >> 6), voxelFill(v));
    }
  });
  return lesion;
}

// Evenly spaced positions from a to b at most `spacing` apart; the middle alone when a > b.
std::vector<double> spread(double a, double b, double spacing) {
  if (a >= b) return {0.5 * (a + b)};
  const auto gaps = std::max<int64_t>(1, int64_t(std::ceil((b - a) / spacing - 1e-9)));
  std::vector<double> out;
  for (int64_t k = 0; k <= gaps; ++k) out.push_back(a + (b - a) * double(k) / double(gaps));
  return out;
}

}  // namespace

Result<CariesPath> cariesRemovalPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                     const std::string& bur, const CariesPathSettings& s) {
  const std::string where = "caries path";
  if (!(s.bur_radius_mm > 0) || !(s.layer_mm > 0) || !(s.line_spacing > 0) || s.overreach < 0 ||
      !(s.speed_mm_s > 0) || !(s.margin > 0) || !(s.hold_s > 0) || !(s.descent_s > 0) || !(s.lift_s > 0) ||
      !(s.sample_s > 0) || s.approach_mm < 0)
    return makeError(where, "radius, layer, spacing, speed, margin, hold, descent, lift and sample period must be > 0; "
                            "overreach and approach >= 0");
  const double ability = params.cuttingAbility(bur);
  if (!(ability > 0)) return makeError(where, "the parameter set gives " + bur + " no cutting ability");
  const double rate = params.cutting.removal_rate_mm3_per_s * ability;  // [mm^3/s] at hardness 1, full speed
  if (!(rate > 0)) return makeError(where, "the parameter set's removal rate is 0");
  const Lesion lesion = findLesion(volume);
  if (lesion.lo[0] > lesion.hi[0]) return makeError(where, "the volume holds no caries");

  CariesPath out;
  const double v = frame.voxel_mm;
  for (int a = 0; a < 3; ++a) {
    out.lesion_lo_mm[a] = frame.origin_mm[size_t(a)] + double(lesion.lo[a]) * v;
    out.lesion_hi_mm[a] = frame.origin_mm[size_t(a)] + double(lesion.hi[a] + 1) * v;
  }
  out.lesion_mm3 = double(lesion.fill) / DS_FILL_FULL * frame.voxelVolumeMm3();
  const double r = s.bur_radius_mm;

  // The raster: lines along x at these y, from x0 to x1.
  const std::vector<double> ys =
      spread(out.lesion_lo_mm.y + s.overreach * r, out.lesion_hi_mm.y - s.overreach * r, s.line_spacing * r);
  std::vector<double> xs = spread(out.lesion_lo_mm.x + s.overreach * r, out.lesion_hi_mm.x - s.overreach * r, HUGE_VAL);
  const double x0 = xs.front(), x1 = xs.back();

  // The top: the highest the bur rests anywhere on the raster.
  const TissueBox box = tissueBox(volume, frame);
  SurfaceProbe probe(volume, frame, box);
  std::optional<double> top;
  for (double y : ys)
    for (double x : spread(x0, x1, 0.5 * r)) {
      const std::optional<double> z = probe.restingTip(x, y, r);
      if (z && (!top || *z > *top)) top = z;
    }
  if (!top) return makeError(where, "no tissue over the lesion");
  const double floor_z = out.lesion_lo_mm.z;
  out.layers = std::max(1, int(std::ceil((*top - floor_z) / s.layer_mm - 1e-9)));

  // Seconds each layer's tissue takes to cut: voxels under the raster's reach between the layer's
  // tip height and the one above, each at its own hardness.
  auto voxelRange = [&](double lo_mm, double hi_mm, int axis) {
    const double o = frame.origin_mm[size_t(axis)];
    const auto dim = double(volume.dim());
    const double a = std::clamp(std::floor((lo_mm - o) / v), 0.0, dim - 1), b = std::clamp(std::floor((hi_mm - o) / v), 0.0, dim - 1);
    return std::pair<uint32_t, uint32_t>{uint32_t(a), uint32_t(b)};
  };
  auto layerSeconds = [&](double z_lo, double z_hi) {
    const auto [ix0, ix1] = voxelRange(x0 - r, x1 + r, 0);
    const auto [iy0, iy1] = voxelRange(ys.front() - r, ys.back() + r, 1);
    const auto [iz0, iz1] = voxelRange(z_lo, z_hi, 2);
    double seconds = 0.0;
    for (uint32_t z = iz0; z <= iz1; ++z)
      for (uint32_t y = iy0; y <= iy1; ++y)
        for (uint32_t x = ix0; x <= ix1; ++x) {
          const Voxel vox = volume.voxel(x, y, z);
          const double h = params.tissue(voxelMaterial(vox)).hardness;
          if (voxelFill(vox) == 0 || !(h > 0)) continue;
          seconds += double(voxelFill(vox)) / DS_FILL_FULL * frame.voxelVolumeMm3() / (rate * h);
        }
    return seconds;
  };

  const Vec3 grip{0.0, 0.0, s.grip_z_mm};
  auto add = [&](double t, const Vec3& tip, double pedal) {
    PenSample sample;
    sample.t_s = t;
    sample.pen = PenRole::Drill;
    sample.pose.position = tip + grip;  // vertical bur: the grip straight above the tip
    sample.pedal = pedal;
    out.path.samples.push_back(sample);
  };
  auto samplesOver = [&](double span) { return std::max<int64_t>(1, int64_t(std::ceil(span / s.sample_s - 1e-9))); };

  // Above the first line's start; the turbine starts at the end of the hold.
  const Vec3 first{x0, ys.front(), floor_z};
  const Vec3 above{first.x, first.y, *top + s.approach_mm};
  add(0.0, above, 0.0);
  double t = 0.0;
  for (int64_t k = 1, n = samplesOver(s.hold_s); k <= n; ++k) add(t + s.hold_s * double(k) / double(n), above, k < n ? 0.0 : 1.0);
  t += s.hold_s;
  out.cut_start_s = t;

  // Layer by layer, the raster run forward, then backward, and so on.
  Vec3 at = above;
  double z_above = *top;
  for (int layer = 0; layer < out.layers; ++layer) {
    const double z = *top - (*top - floor_z) * double(layer + 1) / double(out.layers);
    std::vector<Vec3> corners;
    for (size_t i = 0; i < ys.size(); ++i) {
      const bool forward = i % 2 == 0;
      corners.push_back({forward ? x0 : x1, ys[i], z});
      corners.push_back({forward ? x1 : x0, ys[i], z});
    }
    if (layer % 2 == 1) std::reverse(corners.begin(), corners.end());
    // The first layer is reached by the descent; later ones drop where the last ended.
    if (layer == 0) {
      const Vec3 from = at, to = corners.front();
      for (int64_t k = 1, n = samplesOver(s.descent_s); k <= n; ++k)
        add(t + s.descent_s * double(k) / double(n), from + (to - from) * (double(k) / double(n)), 1.0);
      t += s.descent_s;
    }
    double length = 0.0;
    for (size_t i = 1; i < corners.size(); ++i) length += norm(corners[i] - corners[i - 1]);
    const double duration = std::max({length / s.speed_mm_s, s.margin * layerSeconds(z, z_above), s.sample_s});
    // Uniform speed along the corners' polyline.
    const int64_t n = samplesOver(duration);
    size_t seg = 0;
    double seg_start = 0.0;
    for (int64_t k = 0; k <= n; ++k) {
      const double along = length * double(k) / double(n);
      while (seg + 2 < corners.size() && seg_start + norm(corners[seg + 1] - corners[seg]) < along) {
        seg_start += norm(corners[seg + 1] - corners[seg]);
        ++seg;
      }
      Vec3 p = corners.front();
      if (corners.size() > 1) {
        const double span = norm(corners[seg + 1] - corners[seg]);
        const double u = span > 0 ? std::clamp((along - seg_start) / span, 0.0, 1.0) : 0.0;
        p = corners[seg] + (corners[seg + 1] - corners[seg]) * u;
      }
      // k == 0 drops the target to this layer where the last one ended.
      add(t + s.sample_s + duration * double(k) / double(n), p, 1.0);
    }
    t += duration + s.sample_s;
    at = corners.back();
    z_above = z;
  }
  out.cut_end_s = t;

  // Pedal up, lift.
  const Vec3 up{at.x, at.y, *top + s.approach_mm};
  for (int64_t k = 1, n = samplesOver(s.lift_s); k <= n; ++k)
    add(t + s.lift_s * double(k) / double(n), at + (up - at) * (double(k) / double(n)), 0.0);
  t += s.lift_s;
  out.duration_s = t;
  return out;
}

}  // namespace dentsim
