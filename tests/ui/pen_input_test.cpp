// PenInput: drags, wheel and pedal against the camera's analytic pixel size.
#include "ui/pen_input.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "sim/tool_library.h"

namespace dentsim::ui {
namespace {

constexpr double kStep = 1e-3;     // the haptic loop's period [s]

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

TEST(PenInput, LiftAndLowerKeysMoveAlongTheToolsOwnAxisWhateverTheView) {
  const render::OrbitCamera cam = buccalCamera();  // looking along +y: the wheel would move along y
  const Vec3 grip{2.0, -1.0, 5.0};
  const Quat tilt = Quat::fromAxisAngle({1, 0, 0}, 0.5);
  VirtualPen drill(Pose{grip, tilt});
  PenInput input(cam, &drill, nullptr);
  const double step = input.params().key_lift_mm;
  EXPECT_DOUBLE_EQ(step, 0.1);
  for (int i = 0; i < 3; ++i) input.alongTool(-step);  // three presses of the lower key
  // Down the tool's own axis, (0, -sin 0.5, cos 0.5) for a turn of 0.5 rad about x, by 0.3 mm.
  expectNear(drill.target().position, grip - Vec3{0.0, -std::sin(0.5), std::cos(0.5)} * 0.3, 1e-12);
  const Quat& q = drill.target().rotation;  // unturned (the pen normalises it: an ulp or so)
  EXPECT_NEAR(q.w, tilt.w, 1e-12);
  EXPECT_NEAR(q.x, tilt.x, 1e-12);
  EXPECT_NEAR(q.y, tilt.y, 1e-12);
  EXPECT_NEAR(q.z, tilt.z, 1e-12);
  input.alongTool(step);  // and one lift
  expectNear(drill.target().position, grip - Vec3{0.0, -std::sin(0.5), std::cos(0.5)} * 0.2, 1e-12);
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

}  // namespace
}  // namespace dentsim::ui
