// The Falcon's delta kinematics: the per-arm closed-form inverse, Newton's forward solve and the analytic Jacobian.
//
// One arm, in its own frame (u radial, v tangential, w = z, origin at the thigh hinge). With the grip
// at (pu, pv, pw), the shin's lower joint sits at E = (pu + c, pv + f, pw), and the knee at
// K = a (cos theta, 0, sin theta). The parallelogram keeps its rungs (e at the knee, d at the lower
// joint) in the arm's plane, so it only tilts out of that plane by its v extent:
//   v:        pv + f = b cos(theta3)                   (theta3 in (0, pi): the shin's tilt)
//   in plane: |(E_u, E_w) - (K_u, K_w)| = L,  L = d + e + b sin(theta3) = d + e + sqrt(b^2 - (pv + f)^2)
// Each arm is therefore one scalar constraint g(p, theta) = 0 in its own angle, which is why the
// inverse is closed form per arm and the Jacobian follows from implicit differentiation.
//
// Contents: arm frames and the per-arm solve; the public conversions; the Jacobian; forward();
// torques and command words.
#include "devices/falcon_kinematics.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

namespace dentsim::devices::falcon {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One arm's view of a grip position, with what the constraint and its derivatives need.
struct ArmPoint {
  double U = 0;  // pu + c: the lower joint's radial coordinate from the hinge [mm]
  double W = 0;  // pw: its depth [mm]
  double q = 0;  // pv + f: the shin's extent along v [mm]
  double h = 0;  // b sin(theta3) = sqrt(b^2 - q^2) [mm]
  double L = 0;  // d + e + h: the in-plane reach the thigh must meet [mm]
};

// Row-major 3x3 inverse by cofactors. False when the matrix is singular relative to its size.
bool invert3(const Matrix3& m, Matrix3* out) {
  const double c00 = m[4] * m[8] - m[5] * m[7];
  const double c01 = m[5] * m[6] - m[3] * m[8];
  const double c02 = m[3] * m[7] - m[4] * m[6];
  const double det = m[0] * c00 + m[1] * c01 + m[2] * c02;
  double scale = 0;
  for (double v : m) scale = std::max(scale, std::fabs(v));
  // A determinant this small against the entries' cube means rows that are parallel to rounding.
  if (!std::isfinite(det) || std::fabs(det) <= 1e-12 * scale * scale * scale) return false;
  const double k = 1.0 / det;
  *out = {c00 * k, (m[2] * m[7] - m[1] * m[8]) * k, (m[1] * m[5] - m[2] * m[4]) * k,
          c01 * k, (m[0] * m[8] - m[2] * m[6]) * k, (m[2] * m[3] - m[0] * m[5]) * k,
          c02 * k, (m[1] * m[6] - m[0] * m[7]) * k, (m[0] * m[4] - m[1] * m[3]) * k};
  for (double v : *out)
    if (!std::isfinite(v)) return false;
  return true;
}

Vec3 multiply(const Matrix3& m, const Vec3& v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
          m[6] * v.x + m[7] * v.y + m[8] * v.z};
}

Matrix3 allNaN() {
  Matrix3 m;
  m.fill(kNaN);
  return m;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Arm frames and the per-arm solve

Kinematics::Kinematics() : Kinematics(Geometry{}) {}

Kinematics::Kinematics(const Geometry& geometry) : geometry_(geometry) {
  counts_per_radian_ =
      geometry_.encoder_counts_per_motor_turn * geometry_.capstan_ratio / (2.0 * std::numbers::pi);
  for (int i = 0; i < 3; ++i) {
    cos_azimuth_[i] = std::cos(geometry_.arm_azimuth_rad[i]);
    sin_azimuth_[i] = std::sin(geometry_.arm_azimuth_rad[i]);
  }
}

Vec3 Kinematics::workspaceCentre() const {
  return (geometry_.workspace_min_mm + geometry_.workspace_max_mm) * 0.5;
}

namespace {

// The grip as arm i sees it; false when the shin cannot span the tangential offset.
bool armPoint(const Geometry& g, double cos_az, double sin_az, const Vec3& p, ArmPoint* out) {
  const double pu = cos_az * p.x + sin_az * p.y - g.r;
  const double pv = -sin_az * p.x + cos_az * p.y - g.s;
  out->U = pu + g.c;
  out->W = p.z;
  out->q = pv + g.f;
  const double h2 = g.b * g.b - out->q * out->q;
  // At h = 0 the shin lies along v and the constraint's v derivative is infinite: out of reach.
  if (!(h2 > 0)) return false;
  out->h = std::sqrt(h2);
  out->L = g.d + g.e + out->h;
  return true;
}

// The thigh angle meeting the in-plane reach. With (U, W) = rho (cos psi, sin psi), the constraint
// |(U, W) - a (cos t, sin t)| = L reads rho cos(t - psi) = (rho^2 + a^2 - L^2) / (2 a), and the
// Falcon's thighs take the root below psi: the knee bends outward, away from the central axis.
bool armAngle(const Geometry& g, const ArmPoint& ap, double* theta) {
  // Behind the hinge plane only the mirror image of the mechanism reaches, through the housing.
  if (!(ap.W > 0)) return false;
  const double rho = std::hypot(ap.U, ap.W);
  if (!(rho > 0)) return false;
  const double cos_gap = (rho * rho + g.a * g.a - ap.L * ap.L) / (2.0 * g.a * rho);
  if (!(std::fabs(cos_gap) <= 1.0)) return false;  // too near or too far for thigh plus shin
  *theta = std::atan2(ap.W, ap.U) - std::acos(cos_gap);
  return std::isfinite(*theta);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Encoders and the inverse

Angles Kinematics::anglesFromEncoders(const Encoders& e) const {
  Angles a;
  for (int i = 0; i < 3; ++i)
    a[i] = geometry_.angle_at_zero_count_rad + static_cast<double>(e[i]) / counts_per_radian_;
  return a;
}

Encoders Kinematics::encodersFromAngles(const Angles& a) const {
  Encoders e;
  constexpr double lo = std::numeric_limits<int32_t>::min();
  constexpr double hi = std::numeric_limits<int32_t>::max();
  for (int i = 0; i < 3; ++i) {
    const double counts = std::round((a[i] - geometry_.angle_at_zero_count_rad) * counts_per_radian_);
    e[i] = std::isnan(counts) ? 0 : static_cast<int32_t>(std::clamp(counts, lo, hi));
  }
  return e;
}

bool Kinematics::inverse(const Vec3& position_mm, Angles* out) const {
  assert(out != nullptr);
  if (!finite(position_mm)) return false;
  Angles a;
  for (int i = 0; i < 3; ++i) {
    ArmPoint ap;
    if (!armPoint(geometry_, cos_azimuth_[i], sin_azimuth_[i], position_mm, &ap)) return false;
    if (!armAngle(geometry_, ap, &a[i])) return false;
  }
  *out = a;
  return true;
}

// ---------------------------------------------------------------------------------------------
// The Jacobian, by implicit differentiation of g = |(U, W) - a (cos t, sin t)|^2 - L^2 = 0:
//   dg/dU = 2 (U - a cos t),  dg/dW = 2 (W - a sin t),  dg/dq = 2 L q / h  (L shrinks as |q| grows),
//   dg/dt = 2 a (U sin t - W cos t),
// and U, q depend on x, y through the arm's rotation. Row i of A = d(theta)/dp is -grad_p g / dg/dt;
// J = A^-1. dg/dt = 0 is the thigh in line with the shin: the edge of the reach.

bool Kinematics::jacobianAt(const Vec3& position_mm, Matrix3* out) const {
  assert(out != nullptr);
  *out = allNaN();
  if (!finite(position_mm)) return false;
  Matrix3 angle_rate;  // A = d(theta)/dp [rad/mm]
  for (int i = 0; i < 3; ++i) {
    ArmPoint ap;
    double t = 0;
    if (!armPoint(geometry_, cos_azimuth_[i], sin_azimuth_[i], position_mm, &ap)) return false;
    if (!armAngle(geometry_, ap, &t)) return false;
    const double g_U = 2.0 * (ap.U - geometry_.a * std::cos(t));
    const double g_W = 2.0 * (ap.W - geometry_.a * std::sin(t));
    const double g_q = 2.0 * ap.L * ap.q / ap.h;
    const double g_t = 2.0 * geometry_.a * (ap.U * std::sin(t) - ap.W * std::cos(t));
    if (!(std::fabs(g_t) > 0)) return false;
    // U = cos x + sin y - r + c and q = -sin x + cos y - s + f, so d/dx and d/dy mix g_U and g_q.
    const double g_x = g_U * cos_azimuth_[i] - g_q * sin_azimuth_[i];
    const double g_y = g_U * sin_azimuth_[i] + g_q * cos_azimuth_[i];
    angle_rate[3 * i + 0] = -g_x / g_t;
    angle_rate[3 * i + 1] = -g_y / g_t;
    angle_rate[3 * i + 2] = -g_W / g_t;
  }
  Matrix3 j;
  if (!invert3(angle_rate, &j)) return false;
  *out = j;
  return true;
}

Matrix3 Kinematics::jacobian(const Angles& a) const {
  Vec3 p;
  Matrix3 j;
  if (!forward(a, &p) || !jacobianAt(p, &j)) return allNaN();
  return j;
}

// ---------------------------------------------------------------------------------------------
// forward(): Newton's method on theta(p) = a, each step dp = J (a - theta(p)). A step that leaves
// the reach or does not shrink the angle error is halved (a damped Newton), so a start far from the
// pose still walks in; both loops are bounded, so it ends within kForwardMaxSteps * 40 solves.

bool Kinematics::forward(const Angles& a, Vec3* position_mm, const Vec3* guess) const {
  assert(position_mm != nullptr);
  for (double v : a)
    if (!std::isfinite(v)) return false;

  const auto angleError = [&](const Vec3& p, Vec3* err) {
    Angles t;
    if (!inverse(p, &t)) return false;
    *err = {a[0] - t[0], a[1] - t[1], a[2] - t[2]};
    return true;
  };

  Vec3 p = workspaceCentre();
  Vec3 err;
  if (guess != nullptr && finite(*guess) && angleError(*guess, &err)) {
    p = *guess;
  } else if (!angleError(p, &err)) {
    return false;
  }

  constexpr int kMaxHalvings = 40;
  for (int step = 0; step < kForwardMaxSteps; ++step) {
    Matrix3 j;
    if (!jacobianAt(p, &j)) return false;
    const Vec3 full = multiply(j, err);
    const double err_norm = norm(err);
    double scale = 1.0;
    bool moved = false;
    for (int k = 0; k < kMaxHalvings; ++k, scale *= 0.5) {
      const Vec3 trial = p + full * scale;
      Vec3 trial_err;
      // Near the root rounding can stall the error, so a step already below the tolerance is kept.
      if (angleError(trial, &trial_err) &&
          (norm(trial_err) < err_norm || norm(full * scale) <= kForwardTolerance_mm)) {
        p = trial;
        err = trial_err;
        moved = true;
        break;
      }
    }
    if (!moved) return false;
    if (norm(full * scale) <= kForwardTolerance_mm && scale == 1.0) {
      *position_mm = p;
      return true;
    }
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// Torques and command words. Virtual work: F . dp = F . J da = (J^T F) . da, the thigh torques;
// a thigh turns 1 / capstan_ratio as fast as its motor, so the motor torque is that over the ratio.

Torques Kinematics::torquesForForce(const Angles& a, const Vec3& force_n) const {
  const Matrix3 j = jacobian(a);
  Torques t;
  for (int i = 0; i < 3; ++i) {
    const double thigh_n_mm = j[i] * force_n.x + j[3 + i] * force_n.y + j[6 + i] * force_n.z;
    t[i] = thigh_n_mm / geometry_.capstan_ratio;
  }
  return t;
}

std::array<int16_t, 3> Kinematics::motorWords(const Torques& t) const {
  std::array<int16_t, 3> words{};
  const double limit = std::fabs(static_cast<double>(geometry_.max_command_word));
  for (int i = 0; i < 3; ++i) {
    const double w = geometry_.command_sign * geometry_.command_words_per_n_mm * t[i];
    if (std::isnan(w)) continue;  // no pose, no force: the safe word is zero
    words[i] = static_cast<int16_t>(std::clamp(std::round(w), -limit, limit));
  }
  return words;
}

}  // namespace dentsim::devices::falcon
