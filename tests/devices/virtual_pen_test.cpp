// The virtual pen: the follower against its closed form, and the UI/haptic hand-off under contention.
#include "devices/virtual_pen.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "sim/tool_library.h"

namespace dentsim::devices {
namespace {

constexpr double kStep = 1e-3;     // the haptic loop's period [s]
constexpr double kFollow = 0.004;  // the default follow time [s]: w = 250 /s

void expectNear(const Vec3& got, const Vec3& want, double tol) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

// The angle of the rotation from a to b [rad].
double angleBetween(const Quat& a, const Quat& b) { return norm((b * a.conjugate()).rotationVector()); }

// A jump of D: the follower closes in without overshoot, never faster than the free critically
// damped bound D w / e, and sits on the target, at rest, once settled.
TEST(VirtualPen, FollowerConvergesWithoutAnImpulse) {
  VirtualPen pen(Pose{{0, 0, 0}, Quat{}}, VirtualPenParams{.follow_time_s = kFollow});
  PenReading r;
  pen.read(0.0, &r);
  const double jump = 5.0;
  const Pose goal{{jump, 0, 0}, Quat::fromAxisAngle({0, 0, 1}, 0.5)};
  pen.setTarget(goal);
  const double bound = jump / kFollow / std::exp(1.0);
  double peak = 0.0, last_x = 0.0;
  for (int k = 1; k <= 300; ++k) {
    pen.read(k * kStep, &r);
    peak = std::max(peak, r.velocity.x);
    EXPECT_GE(r.grip.position.x, last_x - 1e-12);
    EXPECT_LE(r.grip.position.x, jump + 1e-12);
    last_x = r.grip.position.x;
  }
  EXPECT_LE(peak, bound);
  EXPECT_GT(peak, 0.8 * bound);  // yet it does move briskly
  expectNear(r.grip.position, goal.position, 1e-9);
  EXPECT_LT(angleBetween(r.grip.rotation, goal.rotation), 1e-9);
  expectNear(r.velocity, {}, 1e-9);
  expectNear(r.angular_velocity, {}, 1e-9);
}

// A target moving at constant speed c (and spinning at s about z): once settled the follower moves
// at exactly c (spins at s) and trails by 2 c / w (2 s / w radians).
TEST(VirtualPen, FollowerMatchesAConstantSpeedTarget) {
  VirtualPen pen(Pose{}, VirtualPenParams{.follow_time_s = kFollow});
  const Vec3 c = Vec3{1, 2, -2} * (80.0 / 3.0);  // 80 mm/s
  const double spin = 3.0;                      // [rad/s]
  PenReading r;
  for (int k = 0; k <= 300; ++k) {
    const double t = k * kStep;
    pen.setTarget(Pose{c * t, Quat::fromAxisAngle({0, 0, 1}, spin * t)});
    pen.read(t, &r);
  }
  const double t_end = 300 * kStep;
  expectNear(r.velocity, c, 1e-9);
  expectNear(r.grip.position, c * t_end - c * (2.0 * kFollow), 1e-9);
  expectNear(r.angular_velocity, {0, 0, spin}, 1e-9);
  const Vec3 behind = (r.grip.rotation * Quat::fromAxisAngle({0, 0, 1}, spin * t_end).conjugate()).rotationVector();
  expectNear(behind, {0, 0, -2.0 * spin * kFollow}, 1e-9);
}

// The UI thread writes poses with x == y == z as fast as it can while the haptic thread reads. A
// torn hand-off would mix two poses. Through reset() the reading is the command itself (an integer
// x with its own rotation, never going back); through setTarget() the follower treats the three
// axes identically, so its x, y and z stay bit-equal too.
TEST(VirtualPen, ReadsNeverSeeATornPose) {
  // Normalized as the pen stores it, so that a reading can be compared bit for bit.
  auto pose_of = [](double k) { return Pose{{k, k, k}, Quat::fromAxisAngle({1, 1, 0}, 1e-3 * k).normalized()}; };
  for (const bool jump : {true, false}) {
    SCOPED_TRACE(jump ? "reset" : "setTarget");
    VirtualPen pen(pose_of(0.0));
    std::atomic<bool> done{false};
    constexpr int kWrites = 200000;
    std::thread writer([&] {
      for (int k = 1; k <= kWrites; ++k) jump ? pen.reset(pose_of(k)) : pen.setTarget(pose_of(k));
      done.store(true, std::memory_order_release);
    });
    int reads = 0, bad = 0;
    double last = 0.0;
    PenReading r;
    for (int n = 0; !done.load(std::memory_order_acquire) || n < 10; ++n) {
      pen.read(n * kStep, &r);
      ++reads;
      const Vec3& p = r.grip.position;
      if (p.x != p.y || p.y != p.z) ++bad;
      // A reading between two writes restarts the follower from rest on the target: the position is
      // then exact, the rotation within the rounding of one normalization (a tear is off by 1e-3 rad).
      if (jump && (p.x < last || std::floor(p.x) != p.x ||
                   angleBetween(r.grip.rotation, pose_of(p.x).rotation) > 1e-12))
        ++bad;
      last = p.x;
    }
    writer.join();
    EXPECT_EQ(bad, 0) << "of " << reads << " reads";
    EXPECT_GT(reads, 10);
    if (jump) {  // the last write is what a read after it sees
      pen.read(1e6, &r);
      EXPECT_EQ(r.grip.position, pose_of(kWrites).position);
      EXPECT_LT(angleBetween(r.grip.rotation, pose_of(kWrites).rotation), 1e-12);
    }
  }
}

}  // namespace
}  // namespace dentsim::devices
