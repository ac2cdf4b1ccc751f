// The virtual pen: drags, wheel and pedal against the camera's analytic pixel size, the follower against its closed form, and the UI/haptic hand-off under contention.
#include "ui/virtual_pen.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "sim/tool_library.h"

namespace dentsim::ui {
namespace {

constexpr double kStep = 1e-3;     // the haptic loop's period [s]
constexpr double kFollow = 0.004;  // the default follow time [s]: w = 250 /s

void expectNear(const Vec3& got, const Vec3& want, double tol) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

// A buccal camera on the origin: right +x, up +z, forward +y.
render::OrbitCamera buccalCamera() {
  render::OrbitCamera cam;
  cam.setView(render::ViewPreset::Buccal, {0, 0, 0}, 10.0f);
  return cam;
}

// The angle of the rotation from a to b [rad].
double angleBetween(const Quat& a, const Quat& b) { return norm((b * a.conjugate()).rotationVector()); }

// Reads the pen every millisecond from t0 for `seconds`; returns the last reading.
PenReading settle(VirtualPen& pen, double t0, double seconds) {
  PenReading r;
  for (double t = t0; t <= t0 + seconds; t += kStep) pen.read(t, &r);
  return r;
}

// A drag of (25, -10) px moves the pen by 2 D tan(fov/2) / h per pixel at its own depth D: right
// (+x) 25 of them, and up (+z) 10, since screen y grows downward.
TEST(PenInput, DragMovesThePenByTheAnalyticAmount) {
  const render::OrbitCamera cam = buccalCamera();
  const Vec3 start{1.0, 4.0, 2.0};  // depth = distance + 4
  VirtualPen drill(Pose{start, Quat{}}), mirror;
  PenInput input(cam, &drill, &mirror);
  input.drag(25.0f, -10.0f);  // before the window's size is known a pixel means nothing
  EXPECT_EQ(drill.target().position, start);
  input.setViewport(800, 600);
  input.drag(25.0f, -10.0f);
  const double depth = double(cam.distance()) + 4.0;
  const double s = 2.0 * depth * std::tan(0.5 * double(cam.fovY())) / 600.0;
  const Vec3 want = start + Vec3{25.0 * s, 0.0, 10.0 * s};
  expectNear(input.target(PenRole::Drill).position, want, 1e-5);
  expectNear(drill.target().position, want, 1e-5);
  PenReading r;
  drill.read(0.0, &r);
  expectNear(settle(drill, 0.0, 0.3).grip.position, want, 1e-5);
}

TEST(PenInput, WheelMovesAlongTheViewDirection) {
  render::OrbitCamera cam = buccalCamera();
  VirtualPen drill(Pose{{0, 0, 0}, Quat{}});
  PenInput input(cam, &drill, nullptr, PenInputParams{.wheel_mm_per_step = 0.5});
  input.wheel(3.0f);  // away from the viewer: +y
  expectNear(drill.target().position, {0.0, 1.5, 0.0}, 1e-6);
  cam.setView(render::ViewPreset::Occlusal, {0, 0, 0}, 10.0f);
  input.wheel(-2.0f);  // toward an occlusal viewer: +z
  expectNear(drill.target().position, {0.0, 1.5, 1.0}, 1e-6);
}

TEST(PenInput, PedalIsClampedAndReachesOnlyTheDrill) {
  const render::OrbitCamera cam = buccalCamera();
  VirtualPen drill, mirror;
  PenInput input(cam, &drill, &mirror, PenInputParams{.pedal_per_step = 0.05});
  input.setActive(PenRole::Mirror);  // the pedal is the drill's whichever pen is active
  input.wheelPedal(3.0f);
  EXPECT_NEAR(input.pedal(), 0.15, 1e-12);
  input.wheelPedal(100.0f);
  EXPECT_EQ(input.pedal(), 1.0);
  PenReading d, m;
  drill.read(0.0, &d);
  mirror.read(0.0, &m);
  EXPECT_EQ(d.pedal, 1.0);
  EXPECT_EQ(m.pedal, 0.0);
  input.setPedal(-2.0);
  EXPECT_EQ(input.pedal(), 0.0);
  drill.read(kStep, &d);
  EXPECT_EQ(d.pedal, 0.0);
  input.wheelPedal(-4.0f);
  EXPECT_EQ(input.pedal(), 0.0);
  input.setPedal(0.4);
  EXPECT_EQ(drill.pedal(), 0.4);
}

// Tilting about the camera's right (+x here) by a turns the bur's tip, 19 mm below the grip, to
// (0, 19 sin a, -19 cos a) from the grip, which stays put; turning that about +z by b gives
// (-19 sin a sin b, 19 sin a cos b, -19 cos a).
TEST(PenInput, RotateTiltsTheToolAboutItsGrip) {
  const render::OrbitCamera cam = buccalCamera();
  const Vec3 grip{2.0, -1.0, 5.0};
  VirtualPen drill(Pose{grip, Quat{}});
  PenInput input(cam, &drill, nullptr);
  input.rotate(0.0, 0.3);
  const Pose& p = drill.target();
  expectNear(p.position, grip, 0.0);
  const Vec3 tip = p.apply(Vec3{0, 0, 0} - kBurGripLocal);
  expectNear(tip - grip, {0.0, 19.0 * std::sin(0.3), -19.0 * std::cos(0.3)}, 1e-6);
  // Then about the camera's up (+z) by b: the tip swings about the vertical through the grip.
  input.rotate(0.5, 0.0);
  const Vec3 swung{-19.0 * std::sin(0.3) * std::sin(0.5), 19.0 * std::sin(0.3) * std::cos(0.5), -19.0 * std::cos(0.3)};
  expectNear(drill.target().apply(Vec3{0, 0, 0} - kBurGripLocal) - grip, swung, 1e-6);
  expectNear(drill.target().position, grip, 0.0);
}

TEST(PenInput, SwitchingPensLeavesTheOtherWhereItWas) {
  const render::OrbitCamera cam = buccalCamera();
  const Pose drill_start{{1, 2, 3}, Quat{}}, mirror_start{{-4, -2, 6}, Quat::fromAxisAngle({0, 1, 0}, 1.0)};
  VirtualPen drill(drill_start), mirror(mirror_start);
  PenInput input(cam, &drill, &mirror);
  input.setViewport(640, 480);
  input.drag(10.0f, 0.0f);
  const Pose drill_moved = drill.target();
  EXPECT_NE(drill_moved, drill_start);

  input.setActive(PenRole::Mirror);
  input.drag(-30.0f, 12.0f);
  input.wheel(2.0f);
  input.rotate(0.2, -0.1);
  EXPECT_EQ(drill.target(), drill_moved);
  EXPECT_EQ(input.target(PenRole::Drill), drill_moved);
  EXPECT_NE(mirror.target().position, mirror_start.position);
  EXPECT_EQ(input.target(PenRole::Mirror), mirror.target());

  PenReading r;
  drill.read(0.0, &r);
  EXPECT_EQ(r.grip, drill_moved);

  input.reset(PenRole::Drill, drill_start);
  EXPECT_EQ(input.active(), PenRole::Mirror);
  drill.read(kStep, &r);
  EXPECT_EQ(r.grip, drill_start);  // reset jumps, no glide
  EXPECT_EQ(r.velocity, Vec3{});
}

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
}  // namespace dentsim::ui
