// Tests of src/ui/camera_control.cpp: a free view follows orbit, pan, zoom and the preset keys; a fixed one refuses them all and stays put.
#include "ui/camera_control.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

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

// The drill upright over a tooth of radius 10 at the origin, as the simulator starts it (tip 3 mm
// over the crown's top at z 5, grip 19 mm above the tip, the handpiece's head above that), and a
// mirror's face, a disc 22 mm across facing -x, beside the distal side: points as the window passes them.
std::vector<Vec3> startingTools() {
  std::vector<Vec3> points;
  for (int i = 0; i <= 10; ++i) points.push_back({0.0, 0.0, 8.0 + 2.5 * i});  // tip to 25 mm over it
  for (double r : {0.0, 5.5, 11.0})
    for (int k = 0; k < 12; ++k) points.push_back({13.0, 4.0 + r * std::cos(k * 0.5236), 4.0 + r * std::sin(k * 0.5236)});
  return points;
}

TEST(CameraControl, NoPresetLooksAtTheToothThroughATool) {
  const std::vector<Vec3> tools = startingTools();
  const Vec3 centre{0, 0, 0};
  // The plain top view looks straight down the drill, and the plain distal view through the
  // mirror's face: what the dodge is for.
  render::OrbitCamera plain;
  CameraControl plain_control(plain);
  ASSERT_TRUE(plain_control.showPreset(render::ViewPreset::Occlusal, centre, 10.0f));
  EXPECT_TRUE(plain_control.toolsHideTooth(centre, 10.0f, tools));
  ASSERT_TRUE(plain_control.showPreset(render::ViewPreset::Distal, centre, 10.0f));
  EXPECT_TRUE(plain_control.toolsHideTooth(centre, 10.0f, tools));
  for (render::ViewPreset p : {render::ViewPreset::Occlusal, render::ViewPreset::Buccal, render::ViewPreset::Lingual,
                               render::ViewPreset::Mesial, render::ViewPreset::Distal}) {
    render::OrbitCamera camera;
    CameraControl control(camera);
    ASSERT_TRUE(control.showPreset(p, centre, 10.0f, tools));
    EXPECT_FALSE(control.toolsHideTooth(centre, 10.0f, tools)) << render::viewPresetName(p);
    // Within the dodge's reach of the preset: the top view still looks down on the crown.
    render::OrbitCamera preset;
    preset.setView(p, glm::vec3(0.0f), 10.0f);
    const float turned = std::acos(std::clamp(glm::dot(glm::normalize(camera.eye()), glm::normalize(preset.eye())), -1.0f, 1.0f));
    EXPECT_LE(turned, float(CameraControl::kMaxDodgeRad) + 1e-3f) << render::viewPresetName(p);
  }
  render::OrbitCamera top;
  CameraControl top_control(top);
  top_control.showPreset(render::ViewPreset::Occlusal, centre, 10.0f, tools);
  EXPECT_GT(top.pitch(), 0.7f);  // still from above: at least 40 degrees up
  // Nothing in the way: the preset exactly.
  render::OrbitCamera clear;
  CameraControl clear_control(clear);
  clear_control.showPreset(render::ViewPreset::Occlusal, centre, 10.0f, std::vector<Vec3>{{40.0, 40.0, 0.0}});
  render::OrbitCamera exact;
  exact.setView(render::ViewPreset::Occlusal, glm::vec3(0.0f), 10.0f);
  EXPECT_EQ(clear.eye(), exact.eye());
}

}  // namespace
}  // namespace dentsim::ui
