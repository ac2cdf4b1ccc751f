// Derived attempts: the professional's session sampled into a pen path, and each attempt made from it by one edit.
#include "sim/session_attempts.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "io/pen_playback.h"
#include "sim/tool_library.h"
#include "sim/sim_params.h"

namespace dentsim {

namespace {

// A unit vector across `axis`, toward the tooth's mesial where that is not along the axis (a class
// V's axis is level, an occlusal one upright: the mesial is across both), else toward the buccal.
Vec3 acrossTowardMesial(const Vec3& axis, const ToothAxes& axes) {
  for (const std::array<double, 3>& d : {axes.mesial, axes.buccal}) {
    const Vec3 v{d[0], d[1], d[2]};
    const Vec3 across = v - axis * dot(v, axis);
    if (norm(across) > 0.3) return normalized(across);
  }
  return normalized(cross(axis, std::abs(axis.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
}

// Applies `edit(sample, drill_index)` to every drill sample.
template <typename Edit>
PenPath editDrill(const ProfessionalPath& pro, Edit edit) {
  PenPath out = pro.path;
  size_t i = 0;
  for (PenSample& s : out.samples)
    if (s.pen == PenRole::Drill) edit(s, i++);
  return out;
}

// The second careful hand: slower by `pace`, swaying across the axis.
PenPath secondHand(const ProfessionalPath& pro, const Vec3& axis, const ToothAxes& axes, const DerivedAttemptSettings& s) {
  const Vec3 u = acrossTowardMesial(axis, axes);
  const Vec3 v = cross(axis, u);
  const double w = 2.0 * std::numbers::pi / s.tremor_period_s;
  PenPath out = editDrill(pro, [&](PenSample& p, size_t) {
    p.pose.position += (u * std::sin(w * p.t_s) + v * std::sin(w * p.t_s / 1.37)) * s.tremor_mm;
  });
  // The pedal stays as the professional held it: a hand that moves a little slower cuts a little
  // closer to its path, as a second careful hand does.
  for (PenSample& p : out.samples) p.t_s *= s.pace_factor;
  return out;
}

// The slow hand: the professional's motion in pieces of about work_s, each followed by a pause
// with the hand held still and the turbine stopped, (factor - 1) times the piece's length, so it
// takes factor times as long and cuts what was cut.
PenPath hesitantPath(const PenPath& path, double factor, double work_s) {
  double end = 0.0;
  for (const PenSample& s : path.samples) end = std::max(end, s.t_s);
  const double pieces = std::max(1.0, std::floor(end / work_s));
  const double piece = end / pieces, pause = (factor - 1.0) * piece;
  // The k-th pause follows the k-th piece; a sample on a boundary belongs to the piece it ends.
  const auto pausesBefore = [&](double t) { return std::min(pieces - 1.0, std::max(0.0, std::ceil(t / piece - 1e-9) - 1.0)); };
  PenPath out;
  for (const PenRole role : {PenRole::Drill, PenRole::Mirror}) {
    ScriptedPen pen(path, role);
    bool any = false;
    for (const PenSample& s : path.samples)
      if (s.pen == role) {
        PenSample moved = s;
        moved.t_s = s.t_s + pausesBefore(s.t_s) * pause;
        out.samples.push_back(moved);
        any = true;
      }
    if (!any) continue;
    for (double k = 1.0; k <= pieces; k += 1.0) {
      PenReading r;
      pen.read(k * piece, &r);
      PenSample hold;
      hold.pen = role;
      hold.pose = r.grip;
      hold.buttons = r.buttons;
      hold.pedal = 0.0;
      hold.t_s = k * piece + (k - 1.0) * pause + 1e-4;  // just after the piece it follows
      out.samples.push_back(hold);
      hold.t_s = k * (piece + pause) - 1e-4;  // just before the next piece
      out.samples.push_back(hold);
    }
  }
  std::stable_sort(out.samples.begin(), out.samples.end(), [](const PenSample& a, const PenSample& b) { return a.t_s < b.t_s; });
  return out;
}

// ---- a crown preparation's faults

// A drill sample as a crown's edits see it: the bur's tip, its axis, whether it laps a wall, and the
// wall's outward direction across the insertion axis (the side the bur's top leans away from).
struct CrownSample {
  Vec3 tip, bur;
  bool lapping = false;
  Vec3 side;
};

CrownSample crownSample(const PenSample& p, const Vec3& axis, const DerivedAttemptSettings& s) {
  CrownSample c;
  c.bur = p.pose.rotation.rotate({0, 0, 1});
  c.tip = p.pose.position - p.pose.rotation.rotate(kBurGripLocal);
  const Vec3 across = c.bur - axis * dot(c.bur, axis);
  const double lean = std::atan2(norm(across), dot(c.bur, axis)) * 180.0 / std::numbers::pi;
  c.lapping = lean > s.crown_lap_lean_deg;
  if (c.lapping) c.side = normalized(across) * -1.0;
  return c;
}

// How much of an edit a lapping sample on `side` gets for the wall facing `wall` (unit, across the
// axis): all within crown_side_deg, none past crown_fade_deg more, linear between.
double wallWeight(const Vec3& side, const Vec3& wall, const DerivedAttemptSettings& s) {
  const double angle = std::acos(std::clamp(dot(side, wall), -1.0, 1.0)) * 180.0 / std::numbers::pi;
  if (angle <= s.crown_side_deg) return 1.0;
  if (s.crown_fade_deg <= 0 || angle >= s.crown_side_deg + s.crown_fade_deg) return 0.0;
  return 1.0 - (angle - s.crown_side_deg) / s.crown_fade_deg;
}

// The sample turned about its tip by `degrees` in the plane of the axis and its side: positive
// leans the bur's top further toward the axis.
void turnAboutTip(PenSample& p, const CrownSample& c, const Vec3& axis, double degrees) {
  const Vec3 about = normalized(cross(c.side, axis));  // a positive turn about it takes the top toward -side
  const Quat turn = Quat::fromAxisAngle(about, degrees * std::numbers::pi / 180.0);
  p.pose.rotation = turn * p.pose.rotation;
  p.pose.position = c.tip + p.pose.rotation.rotate(kBurGripLocal);
}

// The tooth's direction `d` across the axis (unit).
Vec3 acrossAxis(const std::array<double, 3>& d, const Vec3& axis) {
  const Vec3 v{d[0], d[1], d[2]};
  return normalized(v - axis * dot(v, axis));
}

// The nick: the lap stops at its last sample facing the mesial, swings out and back, and goes on.
PenPath nickedPath(const ProfessionalPath& pro, const Vec3& axis, const ToothAxes& axes, const DerivedAttemptSettings& s) {
  const Vec3 mesial = acrossTowardMesial(axis, axes);
  std::optional<size_t> at;
  for (size_t k = 0; k < pro.path.samples.size(); ++k) {
    const PenSample& p = pro.path.samples[k];
    if (p.pen != PenRole::Drill || p.pedal <= 0) continue;
    const CrownSample c = crownSample(p, axis, s);
    if (c.lapping && dot(c.side, mesial) > std::cos(3.0 * std::numbers::pi / 180.0)) at = k;
  }
  if (!at) return pro.path;
  const PenSample& from = pro.path.samples[*at];
  const CrownSample c = crownSample(from, axis, s);
  PenPath out;
  for (size_t k = 0; k <= *at; ++k) out.samples.push_back(pro.path.samples[k]);
  // Out over the first 30 %, held, back over the last 30 %, every 10 ms.
  const auto steps = std::max<int64_t>(2, int64_t(std::ceil(s.nick_s / 0.01)));
  for (int64_t i = 1; i <= steps; ++i) {
    const double f = double(i) / double(steps);
    const double reach = std::clamp(std::min(f, 1.0 - f) / 0.3, 0.0, 1.0);
    PenSample p = from;
    p.t_s = from.t_s + f * s.nick_s;
    p.pose.position += c.side * (s.nick_mm * reach);
    out.samples.push_back(p);
  }
  for (size_t k = *at + 1; k < pro.path.samples.size(); ++k) {
    PenSample p = pro.path.samples[k];
    p.t_s += s.nick_s;
    out.samples.push_back(p);
  }
  // The other pen's samples before the nick but listed after it keep their order by time.
  std::stable_sort(out.samples.begin(), out.samples.end(), [](const PenSample& a, const PenSample& b) { return a.t_s < b.t_s; });
  return out;
}

PenPath crownFault(const ProfessionalPath& pro, Attempt attempt, const Vec3& axis, const ToothAxes& axes,
                   const DerivedAttemptSettings& s) {
  const Vec3 buccal = acrossAxis(axes.buccal, axis);
  switch (attempt) {
    case Attempt::Overtaper:
      return editDrill(pro, [&](PenSample& p, size_t) {
        const CrownSample c = crownSample(p, axis, s);
        if (c.lapping) turnAboutTip(p, c, axis, s.overtaper_deg);
      });
    case Attempt::Shallow:
      return editDrill(pro, [&](PenSample& p, size_t) {
        if (!crownSample(p, axis, s).lapping) p.pose.position += axis * s.shallow_mm;
      });
    case Attempt::WallUndercut:
      return editDrill(pro, [&](PenSample& p, size_t) {
        const CrownSample c = crownSample(p, axis, s);
        if (c.lapping) turnAboutTip(p, c, axis, -s.undercut_turn_deg * wallWeight(c.side, buccal, s));
      });
    case Attempt::ThinMargin:
      return editDrill(pro, [&](PenSample& p, size_t) {
        const CrownSample c = crownSample(p, axis, s);
        if (c.lapping) p.pose.position += c.side * (s.thin_margin_mm * wallWeight(c.side, buccal * -1.0, s));
      });
    case Attempt::Nick: return nickedPath(pro, axis, axes, s);
    default: return pro.path;
  }
}

}  // namespace

Result<ProfessionalPath> professionalPath(const SessionRecording& session, const std::string& where,
                                          const DerivedAttemptSettings& settings) {
  auto params = parseSimParams(session.info.params_json, where + ": parameters");
  if (!params) return params.error();
  ProfessionalPath pro;
  pro.coupling_n_per_mm = params->coupling.stiffness_n_per_mm;
  pro.drill_tool = session.info.drill_tool;
  const double rate = session.info.rate_hz > 0 ? session.info.rate_hz : 1000.0;
  const auto stride = std::max<uint64_t>(1, uint64_t(std::llround(settings.sample_every_s * rate)));
  // Past a recorder's gap the readings are unknown: the path ends there.
  const uint64_t first_gap = session.gaps.empty() ? UINT64_MAX : session.gaps.front().first_step;
  Vec3 centre_sum;
  uint64_t cutting_steps = 0;
  bool any_drill = false;
  for (size_t k = 0; k < session.steps.size(); ++k) {
    const SessionStep& st = session.steps[k];
    if (st.step >= first_gap) break;
    const double t = double(st.step) / rate;
    pro.elapsed_s = t;
    const bool cutting = st.hasReading(0) && st.contacts[0] > 0 && st.reading[0].pedal > 0.0;
    if (cutting) {
      if (cutting_steps == 0) pro.cut_start_s = t;
      pro.cut_end_s = t;
      centre_sum += st.reading[0].grip.position;
      ++cutting_steps;
    }
    const bool last = k + 1 == session.steps.size();
    if (st.step % stride != 0 && !last) continue;
    for (size_t pen = 0; pen < 2; ++pen) {
      if (!st.hasReading(pen)) continue;
      PenSample s;
      s.t_s = t;
      s.pen = PenRole(pen);
      s.pose = st.reading[pen].grip;
      s.buttons = st.reading[pen].buttons;
      s.pedal = st.reading[pen].pedal;
      pro.path.samples.push_back(s);
      if (pen == 0) {
        any_drill = true;
        pro.drill_press.push_back(pro.coupling_n_per_mm > 0 ? st.force_n[0] * (-1.0 / pro.coupling_n_per_mm) : Vec3{});
        pro.drill_cutting.push_back(cutting);
      }
    }
  }
  if (!any_drill) return makeError(where, "the session has no drill reading to derive attempts from");
  if (cutting_steps == 0) return makeError(where, "the bur never cut in this session (no step in contact with the pedal down)");
  pro.cut_centre = centre_sum * (1.0 / double(cutting_steps));
  return pro;
}

PenPath derivedAttemptPath(const ProfessionalPath& pro, Attempt attempt, const Vec3& insertion_axis, const ToothAxes& axes,
                           const DerivedAttemptSettings& s) {
  const Vec3 axis = normalized(insertion_axis);
  switch (attempt) {
    case Attempt::Expert: return secondHand(pro, axis, axes, s);
    case Attempt::Undercut: {
      const double stop = pro.half_removed_s > 0 ? pro.half_removed_s
                                                 : pro.cut_start_s + s.undercut_share * (pro.cut_end_s - pro.cut_start_s);
      return stoppedPath(pro.path, stop, s.lift_mm, 0.3, axis);
    }
    case Attempt::Token: return stoppedPath(pro.path, pro.cut_start_s + s.token_s, s.lift_mm, 0.3, axis);
    case Attempt::Slow: return hesitantPath(pro.path, s.slow_factor, s.slow_work_s);
    case Attempt::Tilted: return tiltedPath(pro.path, axis, acrossTowardMesial(axis, axes), s.tilt_deg);
    case Attempt::Trench: {
      const Vec3 shift = acrossTowardMesial(axis, axes) * s.trench_offset_mm;
      return editDrill(pro, [&](PenSample& p, size_t) { p.pose.position += shift; });
    }
    case Attempt::Overcut: {
      // r -> r + d min(1, r / d) across the axis: continuous, so the second pass stays one stroke.
      const PenPath wider = editDrill(pro, [&](PenSample& p, size_t) {
        const Vec3 from = p.pose.position - pro.cut_centre;
        const Vec3 across = from - axis * dot(from, axis);
        const double r = norm(across);
        if (r < 1e-9) return;
        p.pose.position += across * (s.overcut_offset_mm * std::min(1.0, r / s.overcut_offset_mm) / r);
      });
      return joinedPaths(pro.path, wider, 0.3);
    }
    case Attempt::Heavy:
      // The grip goes heavy_press times as far past the bur as the professional's did, in the
      // direction the professional pressed, and while cutting at least as far as heavy_min_force_n
      // needs: a hand that presses harder where it pressed.
      return editDrill(pro, [&](PenSample& p, size_t i) {
        const Vec3 press = i < pro.drill_press.size() ? pro.drill_press[i] : Vec3{};
        Vec3 heavy = press * s.heavy_press;
        const double length = norm(heavy);
        if (i < pro.drill_cutting.size() && pro.drill_cutting[i] && pro.coupling_n_per_mm > 0 && length > 1e-6) {
          const double need = s.heavy_min_force_n / pro.coupling_n_per_mm;
          if (length < need) heavy *= need / length;
        }
        p.pose.position += heavy - press;
      });
    case Attempt::Overtaper:
    case Attempt::Shallow:
    case Attempt::WallUndercut:
    case Attempt::ThinMargin:
    case Attempt::Nick: return crownFault(pro, attempt, axis, axes, s);
  }
  return pro.path;
}

}  // namespace dentsim
