// The Falcon's kinematics against hand-derived poses, an independent per-arm solve, finite differences and virtual work.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "devices/falcon_kinematics.h"

namespace dentsim::devices::falcon {
namespace {

// The published numbers (libnifalcon's measurements, Stamper's names), written out again here so
// that the references below never read them back from the code under test.
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kA = 60.0, kB = 102.5, kC = 14.0, kD = 11.25, kE = 11.25, kF = -25.0;
constexpr double kR = 37.233758, kS = -27.330909;
constexpr double kAzimuth[3] = {105.0 * kDeg, -15.0 * kDeg, -135.0 * kDeg};
constexpr double kCountsPerRadian = 320.0 * 4.0 * (110.0 / 14.25) / (2.0 * kPi);
constexpr double kZeroCountAngle = 35.0 * kDeg;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------------
// Reference 1: one arm on the central axis, where every arm sees the grip at the same spot. In the
// arm's plane the lower joint is at (c - r, z) from the hinge and the knee at a (cos t, sin t); the
// shin's tangential extent is f - s, so its in-plane reach is L = d + e + sqrt(b^2 - (f - s)^2).

double axisReach() { return kD + kE + std::sqrt(kB * kB - (kF - kS) * (kF - kS)); }

// |joint - knee|^2 - L^2 on the axis: the planar arm equation.
double axisArmEquation(double z, double t) {
  const double du = kC - kR - kA * std::cos(t);
  const double dw = z - kA * std::sin(t);
  return du * du + dw * dw - axisReach() * axisReach();
}

// The thigh angle on the axis by bisection. The equation is largest with the knee pointing away
// from the joint (t = psi - pi) and smallest pointing at it (t = psi), and monotone in between; the
// Falcon's knee bends outward, which is the root in that half turn.
double axisAngleByBisection(double z) {
  const double psi = std::atan2(z, kC - kR);
  double lo = psi - kPi, hi = psi;
  EXPECT_GT(axisArmEquation(z, lo), 0.0);
  EXPECT_LT(axisArmEquation(z, hi), 0.0);
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (axisArmEquation(z, mid) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// With all three thighs at t, the grip on the axis at the depth solving the planar equation for z
// (the + root: the grip is in front of the knees).
double axisDepthForAngle(double t) {
  const double du = kC - kR - kA * std::cos(t);
  return kA * std::sin(t) + std::sqrt(axisReach() * axisReach() - du * du);
}

// ---------------------------------------------------------------------------------------------
// Reference 2: one arm anywhere, written with 3D vectors in the device frame. The thigh hinge is at
// r u + s v, the knee at hinge + a (cos t u + sin t z), the shin's lower joint at p + c u + f v; the
// parallelogram spans sqrt(b^2 - (span . v)^2) in the arm's plane, plus the two rungs.

double armResidual3d(int arm, const Vec3& p, double t) {
  const Vec3 u{std::cos(kAzimuth[arm]), std::sin(kAzimuth[arm]), 0.0};
  const Vec3 v{-std::sin(kAzimuth[arm]), std::cos(kAzimuth[arm]), 0.0};
  const Vec3 w{0.0, 0.0, 1.0};
  const Vec3 knee = kR * u + kS * v + kA * (std::cos(t) * u + std::sin(t) * w);
  const Vec3 span = (p + kC * u + kF * v) - knee;
  const double along_v = dot(span, v);
  return std::hypot(dot(span, u), dot(span, w)) - (kD + kE + std::sqrt(kB * kB - along_v * along_v));
}

// Every root over a full turn (scan, then bisect), keeping the one whose knee sits farthest out
// along u: the Falcon's thighs bend outward. NaN when there is none.
double armAngleBySearch(int arm, const Vec3& p) {
  double best = kNaN;
  const int steps = 1440;
  for (int i = 0; i < steps; ++i) {
    double lo = -kPi + 2.0 * kPi * i / steps, hi = -kPi + 2.0 * kPi * (i + 1) / steps;
    const double flo = armResidual3d(arm, p, lo), fhi = armResidual3d(arm, p, hi);
    if (!(flo * fhi <= 0)) continue;
    for (int k = 0; k < 100; ++k) {
      const double mid = 0.5 * (lo + hi);
      ((armResidual3d(arm, p, mid) > 0) == (flo > 0) ? lo : hi) = mid;
    }
    const double root = 0.5 * (lo + hi);
    if (std::isnan(best) || std::cos(root) > std::cos(best)) best = root;
  }
  return best;
}

int32_t countsByHand(double t) { return static_cast<int32_t>(std::lround((t - kZeroCountAngle) * kCountsPerRadian)); }

double relativeError(const Matrix3& got, const Matrix3& want) {
  double diff = 0, size = 0;
  for (int i = 0; i < 9; ++i) {
    diff += (got[i] - want[i]) * (got[i] - want[i]);
    size += want[i] * want[i];
  }
  return std::sqrt(diff / size);
}

// Points spread through the workspace box, corners and faces included.
std::vector<Vec3> workspaceGrid(const Kinematics& k, int n) {
  const Vec3 lo = k.geometry().workspace_min_mm, hi = k.geometry().workspace_max_mm;
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int l = 0; l < n; ++l)
        points.push_back({lo.x + (hi.x - lo.x) * i / (n - 1), lo.y + (hi.y - lo.y) * j / (n - 1),
                          lo.z + (hi.z - lo.z) * l / (n - 1)});
  return points;
}

std::vector<Vec3> randomPoses(const Kinematics& k, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  const Vec3 lo = k.geometry().workspace_min_mm, hi = k.geometry().workspace_max_mm;
  std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y), uz(lo.z, hi.z);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) points.push_back({ux(rng), uy(rng), uz(rng)});
  return points;
}

// ---------------------------------------------------------------------------------------------
// Encoders

TEST(FalconKinematics, CountsPerRadianIsTheCodeWheelThroughTheCapstan) {
  const Kinematics k;
  EXPECT_NEAR(k.countsPerRadian(), kCountsPerRadian, 1e-9);
  EXPECT_NEAR(k.countsPerRadian(), 1572.5625, 1e-3);  // 1280 * 7.7193 / 2 pi, by calculator
  const Angles a = k.anglesFromEncoders({0, 1000, -1000});
  EXPECT_DOUBLE_EQ(a[0], kZeroCountAngle);
  EXPECT_NEAR(a[1] - a[0], 1000.0 / kCountsPerRadian, 1e-15);
  EXPECT_NEAR(a[2] - a[0], -1000.0 / kCountsPerRadian, 1e-15);
  // Half a count either way rounds back to the count.
  const double half = 0.49 / kCountsPerRadian;
  EXPECT_EQ(k.encodersFromAngles({a[0] + half, a[1] - half, a[2] + half}), (Encoders{0, 1000, -1000}));
  EXPECT_EQ(k.encodersFromAngles({kNaN, a[1], a[2]})[0], 0);
}

// ---------------------------------------------------------------------------------------------
// Known poses

TEST(FalconKinematics, CentreOfTheWorkspaceHasThreeEqualAnglesSolvedByHand) {
  const Kinematics k;
  for (double z : {80.0, 110.0, 140.0}) {
    Angles a;
    ASSERT_TRUE(k.inverse({0, 0, z}, &a)) << z;
    const double want = axisAngleByBisection(z);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], want, 1e-12) << "arm " << i << " at z " << z;
  }
  // Encoders all zero: every thigh at 35 degrees, the grip on the axis at the planar equation's depth.
  Vec3 p;
  ASSERT_TRUE(k.forward(k.anglesFromEncoders({0, 0, 0}), &p));
  EXPECT_NEAR(p.x, 0.0, 1e-9);
  EXPECT_NEAR(p.y, 0.0, 1e-9);
  EXPECT_NEAR(p.z, axisDepthForAngle(kZeroCountAngle), 1e-9);
  EXPECT_NEAR(p.z, 136.29, 0.01);  // the same number, evaluated once by hand
}

TEST(FalconKinematics, EncoderCountsMatchAnIndependentPerArmSolve) {
  const Kinematics k;
  const Vec3 points[] = {{0, 0, 110}, {25, -10, 100}, {-30, 20, 130}, {35, 35, 80}, {-38, -5, 145}, {10, -38, 72}};
  for (const Vec3& p : points) {
    Angles a;
    ASSERT_TRUE(k.inverse(p, &a)) << p.x << " " << p.y << " " << p.z;
    const Encoders got = k.encodersFromAngles(a);
    for (int i = 0; i < 3; ++i) {
      const double want = armAngleBySearch(i, p);
      ASSERT_FALSE(std::isnan(want));
      EXPECT_NEAR(a[i], want, 1e-9) << "arm " << i;
      EXPECT_EQ(got[i], countsByHand(want)) << "arm " << i;
    }
  }
}

TEST(FalconKinematics, EncodersToPositionAndBackIsExactToTheCountOverTheWorkspace) {
  const Kinematics k;
  int checked = 0;
  for (const Vec3& target : workspaceGrid(k, 9)) {
    Angles a;
    ASSERT_TRUE(k.inverse(target, &a)) << target.x << " " << target.y << " " << target.z;
    const Encoders counts = k.encodersFromAngles(a);
    Vec3 p;
    ASSERT_TRUE(k.forward(k.anglesFromEncoders(counts), &p));  // from the centre, no guess
    Angles back;
    ASSERT_TRUE(k.inverse(p, &back));
    EXPECT_EQ(k.encodersFromAngles(back), counts);
    // Rounding to a count moves the grip by at most |J| * half a count.
    EXPECT_LT(norm(p - target), 0.1);
    ++checked;
  }
  EXPECT_EQ(checked, 729);
}

TEST(FalconKinematics, WholeCountTriplesRoundTripWithAGuessToo) {
  const Kinematics k;
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> jitter(-40, 40);
  int checked = 0;
  Vec3 previous = k.workspaceCentre();
  for (const Vec3& target : randomPoses(k, 300, 4)) {
    Angles a;
    ASSERT_TRUE(k.inverse(target, &a));
    Encoders counts = k.encodersFromAngles(a);
    for (int32_t& c : counts) c += jitter(rng);
    Vec3 p;
    ASSERT_TRUE(k.forward(k.anglesFromEncoders(counts), &p, &previous));
    Angles back;
    ASSERT_TRUE(k.inverse(p, &back));
    EXPECT_EQ(k.encodersFromAngles(back), counts);
    previous = p;
    ++checked;
  }
  EXPECT_EQ(checked, 300);
}

TEST(FalconKinematics, ForwardConvergesToTheSamePoseFromAnyStart) {
  const Kinematics k;
  const Vec3 target{20, -15, 120};
  Angles a;
  ASSERT_TRUE(k.inverse(target, &a));
  const Vec3 far_guess{0, 0, 1000};  // out of reach: forward falls back to the centre
  for (const Vec3* guess : {static_cast<const Vec3*>(nullptr), &target, &far_guess}) {
    Vec3 p;
    ASSERT_TRUE(k.forward(a, &p, guess));
    EXPECT_LT(norm(p - target), 1e-9);
  }
}

// ---------------------------------------------------------------------------------------------
// The Jacobian

TEST(FalconKinematics, JacobianMatchesCentralDifferencesOfForward) {
  const Kinematics k;
  const double h = 1e-5;  // [rad]
  for (const Vec3& pose : randomPoses(k, 200, 1)) {
    Angles a;
    ASSERT_TRUE(k.inverse(pose, &a));
    const Matrix3 j = k.jacobian(a);
    Matrix3 fd;
    for (int col = 0; col < 3; ++col) {
      Angles plus = a, minus = a;
      plus[col] += h;
      minus[col] -= h;
      Vec3 pp, pm;
      ASSERT_TRUE(k.forward(plus, &pp, &pose));
      ASSERT_TRUE(k.forward(minus, &pm, &pose));
      const Vec3 column = (pp - pm) / (2.0 * h);
      fd[col] = column.x;
      fd[3 + col] = column.y;
      fd[6 + col] = column.z;
    }
    EXPECT_LT(relativeError(j, fd), 1e-5) << pose.x << " " << pose.y << " " << pose.z;
    Matrix3 at;
    ASSERT_TRUE(k.jacobianAt(pose, &at));
    EXPECT_LT(relativeError(at, j), 1e-9);
  }
}

TEST(FalconKinematics, JacobianStaysWellScaledOverTheWholeBox) {
  // The box is the promise made in the spec: every grid point must reach with a usable Jacobian.
  const Kinematics k;
  for (const Vec3& p : workspaceGrid(k, 13)) {
    Matrix3 j;
    ASSERT_TRUE(k.jacobianAt(p, &j)) << p.x << " " << p.y << " " << p.z;
    for (double v : j) EXPECT_LT(std::fabs(v), 200.0) << p.x << " " << p.y << " " << p.z;
  }
}

TEST(FalconKinematics, VirtualWorkBalances) {
  const Kinematics k;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> force(-9.0, 9.0), move(-1e-6, 1e-6);
  for (const Vec3& pose : randomPoses(k, 200, 2)) {
    Angles a;
    ASSERT_TRUE(k.inverse(pose, &a));
    const Vec3 f{force(rng), force(rng), force(rng)};
    const Torques tau = k.torquesForForce(a, f);
    Angles moved = a;
    double motor_work = 0;  // [N mm]: motor torque times motor angle, which is the capstan times the thigh's
    for (int i = 0; i < 3; ++i) {
      const double d_theta = move(rng);
      moved[i] += d_theta;
      motor_work += tau[i] * d_theta * (110.0 / 14.25);
    }
    Vec3 p0, p1;
    ASSERT_TRUE(k.forward(a, &p0, &pose));
    ASSERT_TRUE(k.forward(moved, &p1, &pose));
    const double grip_work = dot(f, p1 - p0);
    EXPECT_NEAR(motor_work, grip_work, 1e-4 * norm(f) * norm(p1 - p0) + 1e-15);
  }
}

TEST(FalconKinematics, PushingAlongTheAxisTurnsEveryMotorEquallyByHand) {
  // On the axis all thighs move together: z(t) is the planar equation's depth, and virtual work
  // gives 3 * thigh torque * dt = Fz * dz, so the thigh torque is Fz (dz/dt) / 3.
  const Kinematics k;
  const double t = 20.0 * kDeg;
  const double du = kC - kR - kA * std::cos(t);
  const double dz_dt = kA * std::cos(t) - du * kA * std::sin(t) / std::sqrt(axisReach() * axisReach() - du * du);
  const double want = 5.0 * dz_dt / 3.0 / (110.0 / 14.25);
  const Torques tau = k.torquesForForce({t, t, t}, {0, 0, 5.0});
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(tau[i], want, 1e-9 * std::fabs(want)) << i;
  EXPECT_GT(want, 0.0);  // a push toward the user needs the thighs to turn up
}

// ---------------------------------------------------------------------------------------------
// Bad input

TEST(FalconKinematics, OutOfReachIsFalse) {
  const Kinematics k;
  Angles a{};
  EXPECT_FALSE(k.inverse({0, 0, 300}, &a));     // beyond thigh plus shin
  EXPECT_FALSE(k.inverse({0, 0, 40}, &a));      // folded into the base
  EXPECT_FALSE(k.inverse({250, 0, 110}, &a));   // far to the side
  EXPECT_FALSE(k.inverse({0, 0, -110}, &a));    // behind the hinges: the mirror pose, not the Falcon
  EXPECT_FALSE(k.inverse({0, 0, 0}, &a));
  Matrix3 j;
  EXPECT_FALSE(k.jacobianAt({0, 0, 300}, &j));
  EXPECT_TRUE(std::isnan(j[0]));
}

TEST(FalconKinematics, NaNIsFalseAndGivesNoForce) {
  const Kinematics k;
  const double inf = std::numeric_limits<double>::infinity();
  Angles a{};
  Vec3 p;
  EXPECT_FALSE(k.inverse({kNaN, 0, 110}, &a));
  EXPECT_FALSE(k.inverse({0, inf, 110}, &a));
  EXPECT_FALSE(k.forward({kNaN, 0.3, 0.3}, &p));
  EXPECT_FALSE(k.forward({0.3, inf, 0.3}, &p));
  const Vec3 bad_guess{kNaN, 0, 0};
  EXPECT_TRUE(k.forward({0.3, 0.3, 0.3}, &p, &bad_guess));  // a bad guess falls back to the centre
  for (double v : k.jacobian({kNaN, 0.3, 0.3})) EXPECT_TRUE(std::isnan(v));
  const Torques tau = k.torquesForForce({kNaN, 0.3, 0.3}, {0, 0, 5});
  EXPECT_EQ(k.motorWords(tau), (std::array<int16_t, 3>{0, 0, 0}));
}

TEST(FalconKinematics, ForwardEndsOnAnglesNoPoseHas) {
  const Kinematics k;
  Vec3 p;
  const auto start = std::chrono::steady_clock::now();
  // The outward knee puts every thigh at psi - acos(..) with psi = atan2(z, U) in (0, pi) for a grip
  // in front of the hinges, so no pose has an angle outside (-pi, pi).
  EXPECT_FALSE(k.forward({3.2, 0.3, 0.3}, &p));
  EXPECT_FALSE(k.forward({0.3, -3.2, 0.3}, &p));
  EXPECT_FALSE(k.forward({1e6, -1e6, 0.0}, &p));
  // Random triples, most without a pose: each call ends, and a "true" is a real solution.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> angle(-2.0, 2.0);
  int solved = 0;
  for (int n = 0; n < 2000; ++n) {
    const Angles a{angle(rng), angle(rng), angle(rng)};
    if (!k.forward(a, &p)) continue;
    ++solved;
    Angles back;
    ASSERT_TRUE(k.inverse(p, &back));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[i], a[i], 1e-9);
  }
  EXPECT_GT(solved, 0);
  // Bounded: kForwardMaxSteps Newton steps of at most 40 halvings each; in practice far below.
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 10.0);
}

// ---------------------------------------------------------------------------------------------
// Command words

TEST(FalconKinematics, MotorWordsScaleSaturateSymmetricallyAndKeepSign) {
  const Kinematics k;
  // 1 N mm of motor torque is 10 000 words per N m of thigh torque times the capstan: 77.19 words,
  // sent negative (libnifalcon's sign).
  EXPECT_EQ(k.motorWords({1.0, -1.0, 0.0}), (std::array<int16_t, 3>{-77, 77, 0}));
  EXPECT_EQ(k.motorWords({100.0, -100.0, 0.006}), (std::array<int16_t, 3>{-7719, 7719, 0}));
  EXPECT_EQ(k.motorWords({1e6, -1e6, 1e300}), (std::array<int16_t, 3>{-32767, 32767, -32767}));
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(k.motorWords({inf, -inf, kNaN}), (std::array<int16_t, 3>{-32767, 32767, 0}));
  // Saturation keeps the sign of each motor independently.
  for (double t : {-1e5, -424.6, -3.0, 3.0, 424.6, 1e5}) {
    const int16_t w = k.motorWords({t, 0, 0})[0];
    EXPECT_EQ(w < 0, t > 0) << t;
    EXPECT_LE(std::abs(static_cast<int>(w)), 32767);
  }
  Geometry flipped;
  flipped.command_sign = +1;
  EXPECT_EQ(Kinematics(flipped).motorWords({1.0, -1e6, 0}), (std::array<int16_t, 3>{77, -32767, 0}));
}

TEST(FalconKinematics, AGeometryOverrideMovesTheEncoderZero) {
  Geometry g;
  g.angle_at_zero_count_rad = 30.0 * kDeg;
  const Kinematics shifted(g), published;
  Angles a;
  ASSERT_TRUE(published.inverse({0, 0, 110}, &a));
  const Encoders e0 = published.encodersFromAngles(a), e1 = shifted.encodersFromAngles(a);
  EXPECT_DOUBLE_EQ(shifted.anglesFromEncoders({0, 0, 0})[0], 30.0 * kDeg);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(e0[i], std::lround((a[i] - 35.0 * kDeg) * kCountsPerRadian));
    EXPECT_EQ(e1[i], std::lround((a[i] - 30.0 * kDeg) * kCountsPerRadian));
  }
}

}  // namespace
}  // namespace dentsim::devices::falcon
