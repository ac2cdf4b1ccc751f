// Faulty attempts: the names, the over-cutting raster, the trench, and the edits that make the other faults out of the expert's path.
//
// Contents
//   1. Names
//   2. Path edits
//   3. Over-cutting a lesion: a raster over its whole box and beyond
//   4. The attempts
#include "sim/novice_paths.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "io/pen_playback.h"
#include "sim/tool_library.h"

namespace dentsim {

// ---- 1. names -------------------------------------------------------------------------------------

const char* attemptName(Attempt a) {
  switch (a) {
    case Attempt::Expert: return "expert";
    case Attempt::Overcut: return "overcut";
    case Attempt::Undercut: return "undercut";
    case Attempt::Heavy: return "heavy";
    case Attempt::Slow: return "slow";
    case Attempt::Trench: return "trench";
    case Attempt::Tilted: return "tilted";
    case Attempt::Token: return "token";
    case Attempt::Overtaper: return "overtaper";
    case Attempt::Shallow: return "shallow";
    case Attempt::WallUndercut: return "wall_undercut";
    case Attempt::ThinMargin: return "thin_margin";
    case Attempt::Nick: return "nick";
  }
  return "unknown";
}

const char* attemptFault(Attempt a) {
  switch (a) {
    case Attempt::Expert: return "none: the careful path";
    case Attempt::Overcut: return "over-cutting: a wide box";
    case Attempt::Undercut: return "under-cutting: stops early";
    case Attempt::Heavy: return "heavy-handed: pressed 3x harder";
    case Attempt::Slow: return "slow: a third of the speed";
    case Attempt::Trench: return "wrong place: a trench";
    case Attempt::Tilted: return "tilted: 15 degrees off the axis";
    case Attempt::Token: return "a token cut: touches and stops";
    case Attempt::Overtaper: return "over-tapered: walls 9 degrees steeper";
    case Attempt::Shallow: return "under-reduced occlusally by 1.3 mm";
    case Attempt::WallUndercut: return "an undercut left on the buccal wall";
    case Attempt::ThinMargin: return "a thin margin on the lingual";
    case Attempt::Nick: return "the mesial neighbour nicked";
  }
  return "unknown";
}

std::optional<Attempt> parseAttempt(const std::string& name) {
  for (Attempt a : kAttempts)
    if (name == attemptName(a)) return a;
  for (Attempt a : kCrownAttempts)
    if (name == attemptName(a)) return a;
  return std::nullopt;
}

Result<std::vector<Attempt>> parseAttemptList(const std::vector<std::string>& names, const std::string& option) {
  std::vector<Attempt> out;
  for (const std::string& name : names) {
    const std::optional<Attempt> a = parseAttempt(name);
    if (!a)
      return makeError(option, "\"" + name + "\" is not one of " + attemptNames() + " (a crown: " + crownAttemptNames() + ")");
    out.push_back(*a);
  }
  return out;
}

std::vector<std::string> attemptNameList() {
  std::vector<std::string> out;
  for (Attempt a : kAttempts) out.push_back(attemptName(a));
  return out;
}

std::string attemptNames() {
  std::string out;
  for (Attempt a : kAttempts) out += (out.empty() ? "" : ", ") + std::string(attemptName(a));
  return out;
}

std::string crownAttemptNames() {
  std::string out;
  for (Attempt a : kCrownAttempts) out += (out.empty() ? "" : ", ") + std::string(attemptName(a));
  return out;
}

// ---- 2. path edits --------------------------------------------------------------------------------

PenPath slowedPath(const PenPath& path, double factor) {
  PenPath out = path;
  for (PenSample& s : out.samples) {
    s.t_s *= factor;
    s.pedal /= factor;
  }
  return out;
}

PenPath wanderingPath(const PenPath& path, double amplitude_mm, double period_s) {
  constexpr double kEveryS = 0.02;  // dense enough that the wander is not lost between the path's samples
  PenPath out = path;
  out.samples.clear();
  ScriptedPen drill(path, PenRole::Drill);
  const double end = drill.endTime();
  bool any = false;
  for (const PenSample& s : path.samples) {
    if (s.pen == PenRole::Drill) any = true;
    else out.samples.push_back(s);
  }
  if (!any) return path;
  const double w = 2.0 * std::numbers::pi / period_s;
  for (int k = 0;; ++k) {
    const double t = std::min(end, double(k) * kEveryS);
    PenReading r;
    drill.read(t, &r);
    PenSample s;
    s.t_s = t;
    s.pen = PenRole::Drill;
    s.pose = r.grip;
    s.pose.position += Vec3{std::sin(w * t), std::sin(w * t / 1.37), 0.0} * amplitude_mm;
    s.buttons = r.buttons;
    s.pedal = r.pedal;
    out.samples.push_back(s);
    if (t >= end) break;
  }
  // Per pen the samples stay in time order; the file's order is by time across pens.
  std::stable_sort(out.samples.begin(), out.samples.end(), [](const PenSample& a, const PenSample& b) { return a.t_s < b.t_s; });
  return out;
}

PenPath stoppedPath(const PenPath& path, double stop_s, double lift_mm, double lift_s, const Vec3& lift_dir) {
  PenPath out;
  for (const PenSample& s : path.samples)
    if (s.t_s <= stop_s) out.samples.push_back(s);
  if (out.samples.empty()) return out;
  // Pedal up where it stopped, then straight up.
  PenSample last = out.samples.back();
  last.pedal = 0.0;
  out.samples.push_back(last);
  last.t_s += lift_s;
  last.pose.position += lift_dir * lift_mm;
  out.samples.push_back(last);
  return out;
}

PenPath tiltedPath(const PenPath& path, const Vec3& axis, const Vec3& toward, double degrees) {
  // Leaning from axis toward `toward` is a turn about axis x toward. The pen holds the bur at its
  // grip, kBurGripLocal above the tip: the grip swings round the tip, which stays where it was.
  const Vec3 about = normalized(cross(normalized(axis), toward));
  const Quat lean = Quat::fromAxisAngle(about, degrees * std::numbers::pi / 180.0);
  PenPath out = path;
  for (PenSample& s : out.samples) {
    if (s.pen != PenRole::Drill) continue;
    const Vec3 tip = s.pose.position - s.pose.rotation.rotate(kBurGripLocal);
    s.pose.rotation = lean * s.pose.rotation;
    s.pose.position = tip + s.pose.rotation.rotate(kBurGripLocal);
  }
  return out;
}

PenPath joinedPaths(const PenPath& a, const PenPath& b, double gap_s) {
  PenPath out = a;
  const double offset = (a.samples.empty() ? 0.0 : a.samples.back().t_s + gap_s) - (b.samples.empty() ? 0.0 : b.samples.front().t_s);
  for (PenSample s : b.samples) {
    s.t_s += offset;
    out.samples.push_back(s);
  }
  return out;
}

// ---- 3. over-cutting a lesion -------------------------------------------------------------------------

namespace {

// Evenly spaced positions from a to b at most `spacing` apart; the middle alone when a > b.
std::vector<double> spread(double a, double b, double spacing) {
  if (a >= b) return {0.5 * (a + b)};
  const auto gaps = std::max<int64_t>(1, int64_t(std::ceil((b - a) / spacing - 1e-9)));
  std::vector<double> out;
  for (int64_t k = 0; k <= gaps; ++k) out.push_back(a + (b - a) * double(k) / double(gaps));
  return out;
}

// What a student who opens the whole box of the lesion does: layers of a back-and-forth raster over
// the caries voxels' box widened by `margin_mm`, from the top down to the lesion's floor, each paced
// so that the bur keeps up with its target (1.6 times the time its tissue takes).
Result<PenPath> boxRasterPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                              const std::string& bur, double margin_mm) {
  const std::string where = "over-cutting path";
  const std::optional<double> radius = burHeadRadiusMm(bur);
  if (!radius) return makeError(where, bur + " is not a bur of the tool catalog");
  const double r = *radius, layer_mm = 0.25, approach_mm = 1.0, speed_mm_s = 3.0, margin = 1.6, sample_s = 0.01;
  const double ability = params.cuttingAbility(bur);
  const double rate = params.cutting.removal_rate_mm3_per_s * ability;
  if (!(rate > 0)) return makeError(where, "the parameter set gives " + bur + " no cutting ability");
  const LesionBox lesion = findLesion(volume);
  if (lesion.empty()) return makeError(where, "the volume holds no caries");
  const double v = frame.voxel_mm;
  Vec3 lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = frame.origin_mm[size_t(a)] + double(lesion.lo[a]) * v;
    hi[a] = frame.origin_mm[size_t(a)] + double(lesion.hi[a] + 1) * v;
  }
  const std::vector<double> ys = spread(lo.y - margin_mm + 0.4 * r, hi.y + margin_mm - 0.4 * r, r);
  const double x0 = lo.x - margin_mm + 0.4 * r, x1 = hi.x + margin_mm - 0.4 * r;

  const TissueBox box = tissueBox(volume, frame);
  SurfaceProbe probe(volume, frame, box);
  std::optional<double> top;
  for (double y : ys)
    for (double x : spread(x0, x1, 0.5 * r)) {
      const std::optional<double> z = probe.restingTip(x, y, r);
      if (z && (!top || *z > *top)) top = z;
    }
  if (!top) return makeError(where, "no tissue over the lesion");
  const double floor_z = lo.z;
  const int layers = std::max(1, int(std::ceil((*top - floor_z) / layer_mm - 1e-9)));

  // Seconds a layer's tissue takes to cut: the voxels under the raster's reach between two heights.
  auto layerSeconds = [&](double z_lo, double z_hi) {
    auto range = [&](double a_mm, double b_mm, int axis) {
      const double o = frame.origin_mm[size_t(axis)], dim = double(volume.dim());
      return std::pair<uint32_t, uint32_t>{uint32_t(std::clamp(std::floor((a_mm - o) / v), 0.0, dim - 1)),
                                           uint32_t(std::clamp(std::floor((b_mm - o) / v), 0.0, dim - 1))};
    };
    const auto [ix0, ix1] = range(x0 - r, x1 + r, 0);
    const auto [iy0, iy1] = range(ys.front() - r, ys.back() + r, 1);
    const auto [iz0, iz1] = range(z_lo, z_hi, 2);
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

  PenPath path;
  const Vec3 grip{0.0, 0.0, 19.0};
  auto add = [&](double t, const Vec3& tip, double pedal) {
    PenSample sample;
    sample.t_s = t;
    sample.pose.position = tip + grip;
    sample.pedal = pedal;
    path.samples.push_back(sample);
  };
  double t = 0.0;
  auto move = [&](const Vec3& a, const Vec3& b, double duration, double pedal) {
    const auto n = std::max<int64_t>(1, int64_t(std::ceil(duration / sample_s - 1e-9)));
    for (int64_t k = 1; k <= n; ++k) add(t + duration * double(k) / double(n), a + (b - a) * (double(k) / double(n)), pedal);
    t += duration;
  };
  Vec3 at{x0, ys.front(), *top + approach_mm};
  add(0.0, at, 0.0);
  move(at, at, 0.1, 0.0);
  path.samples.back().pedal = 1.0;
  double z_above = *top;
  for (int layer = 0; layer < layers; ++layer) {
    const double z = *top - (*top - floor_z) * double(layer + 1) / double(layers);
    std::vector<Vec3> corners;
    for (size_t i = 0; i < ys.size(); ++i) {
      const bool forward = i % 2 == 0;
      corners.push_back({forward ? x0 : x1, ys[i], z});
      corners.push_back({forward ? x1 : x0, ys[i], z});
    }
    if (layer % 2 == 1) std::reverse(corners.begin(), corners.end());
    double length = norm(corners.front() - at);
    for (size_t i = 1; i < corners.size(); ++i) length += norm(corners[i] - corners[i - 1]);
    const double duration = std::max({length / speed_mm_s, margin * layerSeconds(z, z_above), sample_s});
    // Each leg gets its share of the layer's time, by length.
    for (const Vec3& c : corners) {
      move(at, c, std::max(sample_s, duration * norm(c - at) / std::max(length, 1e-9)), 1.0);
      at = c;
    }
    z_above = z;
  }
  move(at, {at.x, at.y, *top + approach_mm}, 0.3, 0.0);
  return path;
}

}  // namespace

// ---- 4. the attempts ------------------------------------------------------------------------------

namespace {

// The trench: the class I groove's machinery, as a narrow loop along x across the buccal cusps.
CavityPathSettings trenchSettings(CavityPathSettings s, const AttemptFaults& faults) {
  s.search_offset_mm = {0.0, -faults.trench_offset_mm, 0.0};
  s.fossa_search_mm = 0.3;
  s.oval_x_mm = faults.trench_length_mm;
  s.oval_y_mm = 0.3;
  s.speed_mm_s = faults.trench_speed_mm_s;
  s.laps = 1.0;
  return s;
}

// The path stopped once the share of its cutting time (from pedal down to pedal up) has passed.
PenPath stoppedEarly(const PenPath& path, double cut_start_s, double cut_end_s, const AttemptFaults& faults) {
  return stoppedPath(path, cut_start_s + faults.undercut_share * (cut_end_s - cut_start_s));
}

// The built-in paths stand the bur along +z (the crown up): the tilted one leans it mesially (-x),
// and the token one stops token_s after the pedal first goes down.
PenPath tiltedOrToken(const PenPath& path, Attempt attempt, double cut_start_s, const AttemptFaults& faults) {
  if (attempt == Attempt::Tilted) return tiltedPath(path, {0, 0, 1}, {-1, 0, 0}, faults.tilt_deg);
  return stoppedPath(path, cut_start_s + faults.token_s);
}

}  // namespace

Result<PenPath> cariesAttemptPath(Attempt attempt, const BrickVolume& volume, const VolumeFrame& frame,
                                  const SimParams& params, const std::string& bur, const CariesPathSettings& base,
                                  const AttemptFaults& faults) {
  if (attempt == Attempt::Overcut) return boxRasterPath(volume, frame, params, bur, faults.overcut_margin_mm);
  if (attempt == Attempt::Trench) {
    const std::optional<double> radius = burHeadRadiusMm(bur);
    if (!radius) return makeError("trench path", bur + " is not a bur of the tool catalog");
    CavityPathSettings round;
    round.bur_radius_mm = *radius;
    auto path = cavityPreparationPath(volume, frame, trenchSettings(round, faults));
    if (!path) return path.error();
    return path->path;
  }
  CariesPathSettings s = base;
  if (attempt == Attempt::Heavy) {
    // The hand that presses harder does not stop at the floor the expert holds.
    s.press_mm *= faults.heavy_press;
    s.floor_overshoot_mm = s.press_mm;
  }
  auto expert = cariesRemovalPath(volume, frame, params, bur, s);
  if (!expert) return expert.error();
  if (attempt == Attempt::Undercut) return stoppedEarly(expert->path, expert->cut_start_s, expert->cut_end_s, faults);
  if (attempt == Attempt::Slow) return slowedPath(expert->path, faults.slow_factor);
  if (attempt == Attempt::Tilted || attempt == Attempt::Token)
    return tiltedOrToken(expert->path, attempt, expert->cut_start_s, faults);
  return expert->path;
}

Result<PenPath> cavityAttemptPath(Attempt attempt, const BrickVolume& volume, const VolumeFrame& frame,
                                  const CavityPathSettings& base, const AttemptFaults& faults) {
  CavityPathSettings s = attempt == Attempt::Trench ? trenchSettings(base, faults) : base;
  if (attempt == Attempt::Heavy) s.press_mm *= faults.heavy_press;
  auto expert = cavityPreparationPath(volume, frame, s);
  if (!expert) return expert.error();
  switch (attempt) {
    case Attempt::Overcut: {
      CavityPathSettings wide = base;
      wide.oval_x_mm *= faults.overcut_widen;
      wide.oval_y_mm *= faults.overcut_widen;
      wide.laps = 1.0;
      auto second = cavityPreparationPath(volume, frame, wide);
      if (!second) return second.error();
      return joinedPaths(expert->path, second->path);
    }
    case Attempt::Undercut:
      return stoppedEarly(expert->path, expert->cut_start_s, expert->cut_end_s, faults);
    case Attempt::Slow:
      return slowedPath(expert->path, faults.slow_factor);
    case Attempt::Tilted:
    case Attempt::Token:
      return tiltedOrToken(expert->path, attempt, expert->cut_start_s, faults);
    default:
      return expert->path;
  }
}

}  // namespace dentsim
