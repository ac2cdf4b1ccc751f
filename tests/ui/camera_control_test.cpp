// Tests of src/ui/camera_control.cpp: a free view follows orbit, pan, zoom and the preset keys; a fixed one refuses them all and stays put.
#include "ui/camera_control.h"

#include <gtest/gtest.h>

namespace dentsim::ui {
namespace {

struct CameraPose {
  glm::vec3 target, eye;
  float distance;
};
CameraPose poseOf(const render::OrbitCamera& c) { return {c.target(), c.eye(), c.distance()}; }
bool same(const CameraPose& a, const CameraPose& b) {
  return a.target == b.target && a.eye == b.eye && a.distance == b.distance;
}

// The buccal view of a 10 mm tooth at the origin, raised 30 degrees.
render::OrbitCamera buccalCamera() {
  render::OrbitCamera camera;
  camera.setView(render::ViewPreset::Buccal, glm::vec3(0.0f), 10.0f);
  camera.orbit(0.0f, 0.52f);
  return camera;
}

TEST(CameraControl, AFreeViewTurnsPansZoomsAndJumpsToPresets) {
  render::OrbitCamera camera = buccalCamera();
  CameraControl control(camera);
  CameraPose before = poseOf(camera);
  EXPECT_TRUE(control.orbit(50.0, 0.0));
  // 50 px at 0.008 rad/px: the yaw turned by 0.4 rad the other way.
  EXPECT_NEAR(camera.yaw(), buccalCamera().yaw() - 0.4f, 1e-5);
  EXPECT_FALSE(same(before, poseOf(camera)));

  before = poseOf(camera);
  EXPECT_TRUE(control.pan(20.0, 10.0, 800));
  EXPECT_NE(camera.target(), before.target);

  before = poseOf(camera);
  EXPECT_TRUE(control.zoom(2.0));
  EXPECT_NEAR(camera.distance(), before.distance / 1.21f, 1e-3);

  EXPECT_TRUE(control.showPreset(render::ViewPreset::Occlusal, Vec3{0, 0, 0}, 10.0f));
  EXPECT_FLOAT_EQ(camera.pitch(), render::kMaxPitchRad);
}

TEST(CameraControl, AFixedViewRefusesEveryInputAndStaysPut) {
  render::OrbitCamera camera = buccalCamera();
  CameraControl control(camera);
  control.setFixed(true);
  EXPECT_TRUE(control.fixed());
  const CameraPose before = poseOf(camera);
  EXPECT_FALSE(control.orbit(50.0, -30.0));
  EXPECT_FALSE(control.pan(20.0, 10.0, 800));
  EXPECT_FALSE(control.zoom(3.0));
  EXPECT_FALSE(control.showPreset(render::ViewPreset::Occlusal, Vec3{0, 0, 0}, 10.0f));
  EXPECT_TRUE(same(before, poseOf(camera)));
  // Freed again, it moves.
  control.setFixed(false);
  EXPECT_TRUE(control.orbit(50.0, 0.0));
  EXPECT_FALSE(same(before, poseOf(camera)));
}

}  // namespace
}  // namespace dentsim::ui
