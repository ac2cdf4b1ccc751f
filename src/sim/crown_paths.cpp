// The crown preparation's path: the crown's outline and CEJ probed around the axis, the finish line placed clear of the neighbours, then the paced occlusal rasters and axial laps.
#include "sim/crown_paths.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "model/tool_generator.h"
#include "sim/pocket_planner.h"
#include "sim/scripted_paths.h"
#include "sim/surface_probe.h"

namespace dentsim {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The crown seen around the axis: for each direction, the surface's distance from the axis at each
// height (NaN where a ray from outside meets nothing) and the tissue there.
struct Outline {
  double h0 = 0.0, step = 0.1;               // heights h0 + j step [mm]
  std::vector<std::vector<double>> r;        // [sector][height] [mm]
  std::vector<std::vector<Material>> tissue;
  // The distance at height h in sector i, linear between samples; nullopt outside the samples or
  // where either neighbour sample is missing.
  std::optional<double> at(size_t i, double h) const {
    const double f = (h - h0) / step;
    if (!(f >= 0)) return std::nullopt;
    const auto j = size_t(f);
    if (j + 1 >= r[i].size()) return std::nullopt;
    const double a = r[i][j], b = r[i][j + 1];
    if (std::isnan(a) || std::isnan(b)) return std::nullopt;
    return a + (b - a) * (f - double(j));
  }
};

// A neighbour's surface voxel centres near the crown, for the bur's clearance.
std::vector<Vec3> neighbourSurface(const BrickVolume& volume, const VolumeFrame& frame, const Vec3& centre,
                                   const Vec3& axis, double reach_r, double h_lo, double h_hi) {
  std::vector<Vec3> out;
  const double v = frame.voxel_mm;
  const auto dim = int64_t(volume.dim());
  auto isNeighbour = [&](int64_t x, int64_t y, int64_t z) {
    if (x < 0 || y < 0 || z < 0 || x >= dim || y >= dim || z >= dim) return false;
    const Voxel vox = volume.voxel(uint32_t(x), uint32_t(y), uint32_t(z));
    return voxelMaterial(vox) == Material::Neighbour && voxelFill(vox) > 0;
  };
  volume.forEachBrick([&](const BrickView& b) {
    if (b.uniform && (voxelMaterial(b.value) != Material::Neighbour || voxelFill(b.value) == 0)) return;
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      const Voxel vox = b.at(i);
      if (voxelMaterial(vox) != Material::Neighbour || voxelFill(vox) == 0) continue;
      const int64_t x = b.coord.x * DS_BRICK_DIM + (i & 7u), y = b.coord.y * DS_BRICK_DIM + ((i >> 3) & 7u),
                    z = b.coord.z * DS_BRICK_DIM + (i >> 6);
      const Vec3 c{frame.origin_mm[0] + (double(x) + 0.5) * v, frame.origin_mm[1] + (double(y) + 0.5) * v,
                   frame.origin_mm[2] + (double(z) + 0.5) * v};
      const Vec3 d = c - centre;
      const double h = dot(d, axis);
      if (h < h_lo || h > h_hi || norm(d - axis * h) > reach_r) continue;
      if (isNeighbour(x - 1, y, z) && isNeighbour(x + 1, y, z) && isNeighbour(x, y - 1, z) && isNeighbour(x, y + 1, z) &&
          isNeighbour(x, y, z - 1) && isNeighbour(x, y, z + 1))
        continue;  // inside: a surface voxel is always nearer
      out.push_back(c);
    }
  });
  return out;
}

// The first surface of the treated tooth along a ray: past an adjacent tooth's surface, which the
// haptic field may show with the air's material where its fill is partial.
std::optional<TissueRay::Hit> toothHit(TissueRay& ray, const Vec3& from, const Vec3& dir, double max_mm, double voxel_mm) {
  double travelled = 0.0;
  for (int k = 0; k < 16 && travelled < max_mm; ++k) {
    auto hit = ray.first(from + dir * travelled, dir, max_mm - travelled);
    if (!hit) return std::nullopt;
    const Material m = hit->material;
    if (m == Material::Enamel || m == Material::Dentin || m == Material::Pulp || m == Material::Caries) {
      hit->distance_mm += travelled;
      return hit;
    }
    travelled += hit->distance_mm + 0.5 * voxel_mm;
  }
  return std::nullopt;
}

// The bur's profile: its radius t [mm] above its tip, from the catalog's revolution.
struct BurProfile {
  const ToolSpec* spec = nullptr;
  double length = 0.0;     // the cutting head [mm]
  double taper_deg = 0.0;  // the side's half-angle [deg]
  double end_r = 0.0;      // the end's radius: the foot of a wall it cuts lies this far up and across [mm]
  double at(double t) const { return burRadiusAt(*spec, std::clamp(t, 0.0, length)); }
};

// The least clearance [mm] between a bur with its tip at `tip` along unit `dir` and the points.
double clearance(const BurProfile& bur, const Vec3& tip, const Vec3& dir, const std::vector<Vec3>& points,
                 double voxel_mm) {
  double least = HUGE_VAL;
  for (const Vec3& q : points) {
    const Vec3 d = q - tip;
    const double t = std::clamp(dot(d, dir), 0.0, bur.length);
    least = std::min(least, norm(d - dir * t) - bur.at(t));
  }
  return least - 0.5 * voxel_mm;  // to the voxel's face, not its centre
}

// Circular moving average over 2 half + 1 sectors.
std::vector<double> smoothed(const std::vector<double>& x, int half) {
  const auto n = int64_t(x.size());
  std::vector<double> out(x.size());
  for (int64_t i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int64_t k = -half; k <= half; ++k) sum += x[size_t(((i + k) % n + n) % n)];
    out[size_t(i)] = sum / double(2 * half + 1);
  }
  return out;
}

}  // namespace

Result<CrownPrepPath> crownPrepPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                    const std::string& bur_name, const Vec3& insertion_axis, const CrownPrepSettings& s) {
  const std::string where = "crown preparation path";
  if (!(s.occlusal_reduction_mm > 0) || !(s.axial_reduction_mm > 0) || !(s.wall_convergence_deg > 0) ||
      s.wall_convergence_deg >= 30 || s.margin_above_cej_mm < 0 || !(s.margin_width_lo_mm > 0) ||
      s.margin_width_hi_mm < s.margin_width_lo_mm || s.neighbour_clearance_mm < 0 || s.sectors < 8 ||
      !(s.profile_step_mm > 0) || !(s.occlusal_layer_mm > 0) || !(s.raster_step_mm > 0) || !(s.lap_step_mm > 0) ||
      !(s.pace_margin > 0) || s.finish_laps < 1 || s.finish_laps > 8 || !(s.finish_area_mm2 >= 0) ||
      !(s.max_speed_mm_s > 0) || !(s.sample_mm > 0) || s.approach_mm < 0 || !finite(insertion_axis) ||
      !(norm(insertion_axis) > 0))
    return makeError(where, "reductions, convergence (under 30 degrees), widths, steps, pace and speed must be > 0, "
                            "1-8 finishing laps, 8 sectors at least, the axis not zero");
  BurProfile bur;
  bur.spec = findTool(bur_name);
  if (!bur.spec || !isBur(bur.spec->kind)) return makeError(where, bur_name + " is not a bur of the tool catalog");
  bur.length = bur.spec->cutting_length_mm;
  bur.taper_deg = std::atan(bur.at(bur.length) - bur.at(bur.length - 1.0)) / kDeg;
  bur.end_r = 0.5 * bur.spec->tip_diameter_mm;
  const double rate = params.cutting.removal_rate_mm3_per_s * params.cuttingAbility(bur_name) *
                      std::min(params.tissue(Material::Enamel).hardness, params.tissue(Material::Dentin).hardness);
  if (!(rate > 0)) return makeError(where, "the parameter set gives " + bur_name + " no cutting ability");
  const double lean_deg = s.wall_convergence_deg - bur.taper_deg;
  if (!(lean_deg >= 0)) return makeError(where, "the bur " + bur_name + " tapers more than the walls converge");

  const TissueBox box = toothBox(volume, frame);
  if (box.empty()) return makeError(where, "the volume holds no tissue");
  CrownPrepPath out;
  out.axis = normalized(insertion_axis);
  const Vec3 mesial{frame.tooth.mesial[0], frame.tooth.mesial[1], frame.tooth.mesial[2]};
  const Vec3 across = mesial - out.axis * dot(mesial, out.axis);
  out.e_u = norm(across) > 0.3 ? normalized(across) : normalized(cross(out.axis, Vec3{0, 1, 0}));
  out.e_v = cross(out.axis, out.e_u);
  out.centre_mm = box.centre();
  out.lean_deg = lean_deg;
  const Vec3 a = out.axis, c0 = out.centre_mm;
  double h_top = -HUGE_VAL, h_bottom = HUGE_VAL, reach = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{corner & 1 ? box.hi.x : box.lo.x, corner & 2 ? box.hi.y : box.lo.y, corner & 4 ? box.hi.z : box.lo.z};
    h_top = std::max(h_top, dot(p - c0, a));
    h_bottom = std::min(h_bottom, dot(p - c0, a));
    reach = std::max(reach, norm((p - c0) - a * dot(p - c0, a)));
  }
  reach += 1.0;

  // ---- 1. the outline, height by height, and the CEJ in each direction.
  const size_t n = size_t(s.sectors);
  auto direction = [&](double theta) { return out.e_u * std::cos(theta) + out.e_v * std::sin(theta); };
  Outline outline;
  outline.step = s.profile_step_mm;
  outline.h0 = std::max(h_bottom, h_top - 12.0);
  const auto heights = size_t(std::floor((h_top - outline.h0) / outline.step)) + 1;
  outline.r.assign(n, std::vector<double>(heights, NAN));
  outline.tissue.assign(n, std::vector<Material>(heights, Material::Empty));
  TissueRay ray(volume, frame);
  out.sector_deg.resize(n);
  out.cej_h.assign(n, NAN);
  for (size_t i = 0; i < n; ++i) {
    const double theta = 2.0 * std::numbers::pi * double(i) / double(n);
    out.sector_deg[i] = theta / kDeg;
    const Vec3 d = direction(theta);
    std::optional<double> last_enamel;
    for (size_t j = heights; j-- > 0;) {
      const double h = outline.h0 + double(j) * outline.step;
      const auto hit = toothHit(ray, c0 + a * h + d * reach, d * -1.0, reach, frame.voxel_mm);
      if (!hit) continue;
      outline.r[i][j] = reach - hit->distance_mm;
      outline.tissue[i][j] = hit->material;
      if (hit->material == Material::Enamel) last_enamel = h;
      else if (last_enamel && std::isnan(out.cej_h[i])) out.cej_h[i] = *last_enamel - 0.5 * outline.step;
    }
    if (std::isnan(out.cej_h[i])) return makeError(where, "no enamel ending in the direction " + std::to_string(int(theta / kDeg)) +
                                                              " degrees from the mesial: where is the CEJ?");
  }

  // ---- 2. the finish line: the wall's foot in each direction.
  const double tan_c = std::tan(s.wall_convergence_deg * kDeg);
  const std::vector<double> cej = smoothed(out.cej_h, 2);
  out.margin_h.resize(n);
  out.foot_r.resize(n);
  out.surface_r.resize(n);
  out.width_scale.resize(n);
  out.beside_neighbour.assign(n, false);
  for (size_t i = 0; i < n; ++i) {
    out.margin_h[i] = cej[i] + s.margin_above_cej_mm;
    const double h_f = out.margin_h[i] + bur.end_r;
    const std::optional<double> r_f = outline.at(i, h_f);
    if (!r_f)
      return makeError(where, "no crown surface at the finish line's height (" + std::to_string(h_f) + " mm along the axis, " +
                                  std::to_string(int(out.sector_deg[i])) + " degrees from the mesial)");
    // The wall: up from the foot while the surface stays a side (steeper than 45 degrees).
    double sum = 0.0;
    int count = 0;
    for (double h = h_f; h < h_top; h += outline.step) {
      const std::optional<double> r0 = outline.at(i, h), r1 = outline.at(i, h + outline.step);
      if (!r0 || !r1 || (*r0 - *r1) > outline.step) break;
      sum += *r0 + (h - h_f) * tan_c;
      ++count;
    }
    const double foot = count > 0 ? sum / count - s.axial_reduction_mm : *r_f - s.axial_reduction_mm;
    // The chamfer's width as an examiner (and eval/crown_prep_margin.h) reads it: from the original
    // surface at the finish line's own height, narrower than higher up on a crown that bulges.
    const double r_m = outline.at(i, out.margin_h[i]).value_or(*r_f);
    out.surface_r[i] = r_m;
    // The width is read square to the finish line; where the outline runs obliquely to this
    // direction (a line angle), a radial step of w is w cos(alpha) wide across the line.
    const double r_prev = outline.at((i + n - 1) % n, out.margin_h[i]).value_or(r_m);
    const double r_next = outline.at((i + 1) % n, out.margin_h[i]).value_or(r_m);
    const double slope = (r_next - r_prev) / (2.0 * 2.0 * std::numbers::pi / double(n)) / r_m;  // tan(alpha)
    const double obliquity = std::sqrt(1.0 + std::min(slope * slope, 1.0));                     // 1 / cos(alpha), alpha <= 45 deg
    out.width_scale[i] = obliquity;
    out.foot_r[i] = r_m - std::clamp(r_m - foot, s.margin_width_lo_mm * obliquity, s.margin_width_hi_mm * obliquity);
  }
  out.foot_r = smoothed(out.foot_r, 2);
  out.margin_h = smoothed(out.margin_h, 1);

  // The bur on the finish line in direction theta (continuous), stepped out by `offset` at the same
  // height: the outer laps cut the floor flat at the finish line's height out to the crown's
  // surface, so a finish line wider than the bur's end (a heavy chamfer, which all-ceramic crowns
  // ask) is a rounded inner angle and a floor, with no lip of uncut enamel left outside the groove
  // the last lap's round end makes.
  auto interp = [&](const std::vector<double>& x, double theta) {
    const double f = theta / (2.0 * std::numbers::pi) * double(n);
    const double fl = std::floor(f);
    const auto i0 = size_t(((int64_t(fl) % int64_t(n)) + int64_t(n)) % int64_t(n));
    const size_t i1 = (i0 + 1) % n;
    return x[i0] + (x[i1] - x[i0]) * (f - fl);
  };
  auto footPoint = [&](double theta) {
    return c0 + direction(theta) * interp(out.foot_r, theta) + a * (interp(out.margin_h, theta) + bur.end_r);
  };
  const double sin_l = std::sin(lean_deg * kDeg), cos_l = std::cos(lean_deg * kDeg);
  struct BurPose {
    Vec3 tip, dir;
  };
  auto lapPose = [&](double theta, double offset, double lift = 0.0) {
    const double dt = 0.5 * kDeg;
    const Vec3 tangent = footPoint(theta + dt) - footPoint(theta - dt);
    Vec3 normal = cross(tangent, a);  // outward for a counter-clockwise outline about +axis
    normal = normalized(normal - a * dot(normal, a));
    const Vec3 foot = footPoint(theta);
    BurPose p;
    p.dir = a * cos_l - normal * sin_l;
    p.tip = foot + normal * (bur.end_r * (1.0 + sin_l) + offset) + a * (-bur.end_r + lift);
    return p;
  };

  // Beside a neighbour: the foot moves in until the bur on the finish line keeps its clearance.
  const std::vector<Vec3> neighbour = neighbourSurface(volume, frame, c0, a, reach + 2.0,
                                                       *std::min_element(out.margin_h.begin(), out.margin_h.end()) - 1.0,
                                                       h_top + 1.0);
  std::vector<double> max_offset(n, HUGE_VAL);
  if (!neighbour.empty()) {
    std::vector<double> inward(n, 0.0);
    for (size_t i = 0; i < n; ++i) {
      const double theta = out.sector_deg[i] * kDeg;
      double in = 0.0;
      for (; in < 2.0; in += 0.05) {
        const double saved = out.foot_r[i];
        out.foot_r[i] = saved - in;
        const BurPose p = lapPose(theta, 0.0);
        const double cl = clearance(bur, p.tip, p.dir, neighbour, frame.voxel_mm);
        out.foot_r[i] = saved;
        if (cl >= s.neighbour_clearance_mm) break;
      }
      inward[i] = in;

    }
    // Keep the outline smooth: each sector moves in as far as its closest neighbours need.
    for (size_t i = 0; i < n; ++i) {
      double need = 0.0;
      for (int64_t k = -2; k <= 2; ++k) need = std::max(need, inward[size_t((int64_t(i) + k + int64_t(n)) % int64_t(n))]);
      if (need > 0) out.beside_neighbour[i] = true;
      out.foot_r[i] -= need;
    }
    // The outer laps step out only as far as the clearance allows.
    for (size_t i = 0; i < n; ++i) {
      const double theta = out.sector_deg[i] * kDeg;
      double o = 0.0;
      while (o < 3.0) {  // beyond the deepest reduction a lap is outside the tooth
        const BurPose p = lapPose(theta, o + 0.05);
        if (clearance(bur, p.tip, p.dir, neighbour, frame.voxel_mm) < s.neighbour_clearance_mm) break;
        o += 0.05;
      }
      max_offset[i] = o;
      if (o < 3.0) out.beside_neighbour[i] = true;
    }
  }

  // ---- 3. the occlusal rasters' plan, the bur along the axis (cut after the laps).
  const TissueBox tooth_box = box;
  SurfaceProbe probe(volume, frame, tooth_box);
  const double g = 0.1;  // the surface's grid [mm]
  const double half = reach;
  const auto cells = int64_t(std::ceil(half / g));
  const auto side = size_t(2 * cells + 1);
  // The surface along the axis over a (u, v) grid (the built-in axis is the probe's +z; another axis
  // is probed with rays along it).
  const bool along_z = std::abs(a.z) > 0.999;
  std::vector<double> surf(side * side, NAN);
  for (int64_t jv = -cells; jv <= cells; ++jv)
    for (int64_t ju = -cells; ju <= cells; ++ju) {
      const double u = double(ju) * g, v = double(jv) * g;
      const Vec3 p = c0 + out.e_u * u + out.e_v * v;
      std::optional<double> h;
      if (along_z) {
        if (const auto z = probe.surface(p.x, p.y)) h = dot(Vec3{p.x, p.y, *z} - c0, a);
      } else if (const auto hit = ray.first(p + a * (h_top + 1.0), a * -1.0, h_top + 1.0 - outline.h0)) {
        h = h_top + 1.0 - hit->distance_mm;
      }
      if (h) surf[size_t(ju + cells) + side * size_t(jv + cells)] = *h;
    }
  auto surfAt = [&](int64_t ju, int64_t jv) {
    if (ju < -cells || jv < -cells || ju > cells || jv > cells) return double(NAN);
    return surf[size_t(ju + cells) + side * size_t(jv + cells)];
  };
  // The tip's final height over (u, v): the ball end goes no lower than the reduction below any
  // point under it, so it rides high over a slope rather than gouge the cusp beside it.
  const double ball = bur.end_r;
  auto finalTip = [&](double u, double v) -> std::optional<double> {
    const auto cu = int64_t(std::lround(u / g)), cv = int64_t(std::lround(v / g));
    const auto k = int64_t(std::ceil(ball / g));
    double most = -HUGE_VAL;
    for (int64_t dv = -k; dv <= k; ++dv)
      for (int64_t du = -k; du <= k; ++du) {
        const double rho = std::hypot(double(du) * g, double(dv) * g);
        if (rho > ball) continue;
        const double sz = surfAt(cu + du, cv + dv);
        if (std::isnan(sz)) continue;
        most = std::max(most, sz - s.occlusal_reduction_mm - (ball - std::sqrt(ball * ball - rho * rho)));
      }
    if (most == -HUGE_VAL) return std::nullopt;
    return most;
  };
  // Inside the walls: the bur's side within the wall line from its tip up to reach_h, the highest
  // tissue it meets there. The walls converge upward and the bur widens, so the test is at the top:
  // a layer high on a cusp stays farther from the wall than the floor under it.
  auto insideWalls = [&](double u, double v, double tip_h, double reach_h) {
    const double rho = std::hypot(u, v);
    double theta = std::atan2(v, u);
    if (theta < 0) theta += 2.0 * std::numbers::pi;
    const double h_f = interp(out.margin_h, theta) + bur.end_r;
    const double top = std::max(tip_h, reach_h);
    const double wall = interp(out.foot_r, theta) - std::max(0.0, top - h_f) * tan_c;
    return rho + bur.at(std::max(bur.end_r, top - tip_h)) + 0.05 <= wall;
  };

  PenPath& path = out.path;
  double t = 0.0;
  Vec3 at_tip;
  Vec3 at_dir = a;
  auto add = [&](double time, const Vec3& tip, const Vec3& dir, double pedal) {
    PenSample sample;
    sample.t_s = time;
    sample.pen = PenRole::Drill;
    sample.pose.position = tip + dir * s.grip_mm;
    sample.pose.rotation = AxisFrame::along(tip, dir, out.e_u).rotation();
    sample.pedal = pedal;
    path.samples.push_back(sample);
  };
  // A straight move of the tip (the bur turning evenly to `dir`) lasting `duration`, sampled finely.
  auto move = [&](const Vec3& tip, const Vec3& dir, double duration, double pedal) {
    const double length = norm(tip - at_tip);
    const auto k = std::max<int64_t>(1, int64_t(std::ceil(std::max(length / s.sample_mm, duration / 0.05))));
    for (int64_t i = 1; i <= k; ++i) {
      const double f = double(i) / double(k);
      add(t + duration * f, at_tip + (tip - at_tip) * f, normalized(at_dir + (dir - at_dir) * f), pedal);
    }
    t += duration;
    at_tip = tip;
    at_dir = dir;
  };
  // How long a move of `length` that cuts `area` [mm^2] of cross-section takes.
  auto paced = [&](double length, double area, double margin) {
    return std::max(length / s.max_speed_mm_s, margin * length * area / rate) + 1e-3;
  };

  // Raster rows along e_u, every other backward; the layers from the top down.
  struct RasterPoint {
    double u, v, final_h, top_h;
  };
  std::vector<std::vector<RasterPoint>> rows;
  const double rs = s.raster_step_mm;
  const auto nr = int64_t(std::ceil(half / rs));
  for (int64_t jv = -nr; jv <= nr; ++jv) {
    std::vector<RasterPoint> row;
    for (int64_t ju = -nr; ju <= nr; ++ju) {
      const double u = double(ju) * rs, v = double(jv) * rs;
      const std::optional<double> f = finalTip(u, v);
      if (!f || !insideWalls(u, v, *f, *f)) continue;
      const double top = surfAt(std::lround(u / g), std::lround(v / g));
      row.push_back({u, v, *f, std::isnan(top) ? *f : top});
    }
    if (row.empty()) continue;
    if (rows.size() % 2 == 1) std::reverse(row.begin(), row.end());
    rows.push_back(std::move(row));
  }
  if (rows.empty()) return makeError(where, "no room for the bur over the occlusal surface inside the walls");
  const auto layers = int64_t(std::ceil(s.occlusal_reduction_mm / s.occlusal_layer_mm - 1e-9));
  auto tipAt = [&](const RasterPoint& p, double above) { return c0 + out.e_u * p.u + out.e_v * p.v + a * (p.final_h + above); };
  const double clear = h_top + s.approach_mm;

  // ---- 4. the axial laps first, outside in, starting on the buccal side (away from the neighbours): with
  // the crown whole above them, the wall bears on the bur's whole side and holds it upright; cut after
  // the occlusal table is lowered, the bur's top has nothing to lean on and the lap tips it inward.
  double max_reduction = 0.0;
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < heights; ++j) {
      const double h = outline.h0 + double(j) * outline.step;
      if (std::isnan(outline.r[i][j]) || h < out.margin_h[i]) continue;
      const double wall = out.foot_r[i] - std::max(0.0, h - out.margin_h[i] - bur.end_r) * tan_c;
      max_reduction = std::max(max_reduction, outline.r[i][j] - wall);
    }
  }
  const auto laps = int64_t(std::ceil(max_reduction / s.lap_step_mm));
  // The buccal direction: -e_v when e_u is mesial (buccal = axis x mesial, sim/ToothAxes).
  const Vec3 buccal{frame.tooth.buccal[0], frame.tooth.buccal[1], frame.tooth.buccal[2]};
  double theta0 = std::atan2(dot(buccal, out.e_v), dot(buccal, out.e_u));
  if (theta0 < 0) theta0 += 2.0 * std::numbers::pi;
  const double dtheta = 1.0 * kDeg;
  const auto steps = int64_t(std::lround(360.0 / 1.0));
  // The tissue a lap at `offset` takes in sector i inside where the laps before it cut (`before`):
  // along the wall from the tip up, out to that or the surface [mm^2].
  auto lapArea = [&](size_t i, double offset, double lift, double before, double before_low) {
    double area = 0.0;
    for (size_t j = 0; j < heights; ++j) {
      const double h = outline.h0 + double(j) * outline.step;
      if (std::isnan(outline.r[i][j]) || h < out.margin_h[i] + lift) continue;
      const double wall = out.foot_r[i] - std::max(0.0, h - out.margin_h[i] - bur.end_r) * tan_c;
      const double inner = wall + offset, outer = std::min(outline.r[i][j], h >= before_low ? wall + before : HUGE_VAL);
      area += std::max(0.0, outer - inner) * outline.step;
    }
    return area;
  };
  auto offsetFor = [&](double theta, double wanted) {
    const double f = theta / (2.0 * std::numbers::pi) * double(n);
    const auto i0 = size_t(((int64_t(std::floor(f)) % int64_t(n)) + int64_t(n)) % int64_t(n));
    return std::min({wanted, max_offset[i0], max_offset[(i0 + 1) % n]});
  };
  // Over the start, outside the tooth, the turbine starting, then down beside it.
  {
    const BurPose p = lapPose(theta0, offsetFor(theta0, double(laps) * s.lap_step_mm + 0.6));
    at_tip = p.tip + a * (clear - dot(p.tip - c0, a));
    at_dir = p.dir;
    add(0.0, at_tip, at_dir, 0.0);
    move(at_tip, at_dir, 0.2, 0.0);
    path.samples.back().pedal = 1.0;
    out.cut_start_s = t;
    move(p.tip, p.dir, norm(p.tip - at_tip) / s.max_speed_mm_s + 0.1, 1.0);
  }
  // Where the laps so far have cut to in each sector: out to an offset (far out: nowhere yet), down
  // to a height. Beside a neighbour the outer laps are held in; rather than take all of a proximal
  // wall's bulge in one lap, a bur held in is lifted by proximal_lift times what it is held in, so
  // the laps there go down the wall in steps.
  std::vector<double> cut_to(n, 10.0), cut_low(n, -HUGE_VAL);
  for (int64_t k = laps; k >= -int64_t(s.finish_laps); --k) {
    const bool finishing = k < 0;
    const double wanted = double(std::max<int64_t>(k, 0)) * s.lap_step_mm;
    auto liftFor = [&](double offset) { return s.proximal_lift * std::max(0.0, wanted - offset); };
    for (int64_t q = 0; q <= steps; ++q) {
      const double theta = theta0 + double(q) * dtheta;
      const double th = std::fmod(theta, 2.0 * std::numbers::pi);
      const double offset = offsetFor(th, wanted);
      const double lift = liftFor(offset);
      const BurPose p = lapPose(th, offset, lift);
      const auto i = size_t(std::lround(th / (2.0 * std::numbers::pi) * double(n))) % n;
      const double area = std::max(finishing ? s.finish_area_mm2 : 0.0, lapArea(i, offset, lift, cut_to[i], cut_low[i]));
      const double length = norm(p.tip - at_tip);
      move(p.tip, p.dir, paced(length, area, s.lap_pace_margin), 1.0);
      out.volume_planned_mm3 += length * area;
    }
    for (size_t i = 0; i < n; ++i) {
      const double th = out.sector_deg[i] * kDeg;
      const double offset = offsetFor(th, wanted), low = out.margin_h[i] + liftFor(offset);
      if (offset < cut_to[i] - 1e-9) {
        cut_to[i] = offset;
        cut_low[i] = low;
      } else {
        cut_low[i] = std::min(cut_low[i], low);
      }
    }
  }
  out.laps_end_s = t;
  // Out, away from the tooth, up along the axis and over the occlusal rasters' start, the bur
  // turning upright on the way.
  {
    const BurPose away = lapPose(theta0, offsetFor(theta0, 2.0));
    move(away.tip, away.dir, 0.5, 1.0);
    move(away.tip + a * (clear - dot(away.tip - c0, a)), a, 0.5, 1.0);
    const Vec3 over = c0 + out.e_u * rows.front().front().u + out.e_v * rows.front().front().v + a * clear;
    move(over, a, norm(over - at_tip) / s.max_speed_mm_s + 0.1, 1.0);
  }
  for (int64_t k = layers - 1; k >= 0; --k) {
    const double above = double(k) * s.occlusal_layer_mm;  // over the final surface
    const double layer_top = above + s.occlusal_layer_mm;
    const bool backward = (layers - 1 - k) % 2 == 1;
    for (size_t ri = 0; ri < rows.size(); ++ri) {
      const std::vector<RasterPoint>& row = rows[backward ? rows.size() - 1 - ri : ri];
      for (size_t pi = 0; pi < row.size(); ++pi) {
        const RasterPoint& p = row[backward ? row.size() - 1 - pi : pi];
        if (!insideWalls(p.u, p.v, p.final_h + above, std::min(p.top_h, p.final_h + layer_top))) continue;
        const Vec3 tip = tipAt(p, above);
        // What this layer takes under the point: the tissue between its top and its floor.
        const double thick = std::clamp(p.top_h - (p.final_h + above), 0.0, layer_top - above + s.occlusal_reduction_mm);
        const double length = norm(tip - at_tip);
        const double area = std::min(thick, s.occlusal_layer_mm + 0.3) * rs;
        // A plunge takes the ball's cross-section through the layer.
        const double plunge = std::abs(dot(tip - at_tip, a)) > 0.5 * length ? std::numbers::pi * ball * ball : 0.0;
        move(tip, a, paced(length, std::max(area, plunge), s.pace_margin), 1.0);
        out.volume_planned_mm3 += length * std::max(area, plunge);
      }
    }
  }
  out.cut_end_s = t;
  // Pedal up, and out along the axis.
  move(at_tip, a, 0.3, 0.0);
  move(at_tip + a * (clear - dot(at_tip - c0, a)), a, 0.5, 0.0);
  out.duration_s = t;
  return out;
}

}  // namespace dentsim
