// The first camera view (app/first_view.h): which view a run opens on, and where the camera goes for a crown with and without the mirror beside it; camera math only, no window.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "app/first_view.h"
#include "app/tool_placement.h"
#include "sim/tool_library.h"

namespace dentsim::app {
namespace {

// A molar-sized crown: 10 x 10 x 8 mm of tissue about (1, 2, 3).
TissueBox crown() {
  TissueBox b;
  b.lo = {-4.0, -3.0, -1.0};
  b.hi = {6.0, 7.0, 7.0};
  return b;
}

// A point the camera shows lies in front of the eye and inside a 1280 x 800 frame.
bool inFrame(const render::OrbitCamera& camera, const Vec3& p) {
  if (camera.depthOf(render::toGlm(p)) <= camera.nearMm()) return false;
  const glm::vec3 px = camera.project(render::toGlm(p), 1280, 800);
  return px.x >= 0 && px.x <= 1280 && px.y >= 0 && px.y <= 800;
}

TEST(FirstView, NoneAskedIsBuccalFromTheChair) {
  auto v = chooseFirstView("", std::nullopt, false);
  ASSERT_TRUE(v) << v.message();
  EXPECT_EQ(v->preset, render::ViewPreset::Buccal);
  EXPECT_FLOAT_EQ(v->elevation_rad, kChairElevationRad);
  EXPECT_FALSE(v->fixed);
}

TEST(FirstView, TheTasksViewBringsItsElevationAndLock) {
  TaskView tv;
  tv.camera = "lingual";
  tv.elevation_deg = 45.0;
  tv.fixed = true;
  auto v = chooseFirstView("", tv, true);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->preset, render::ViewPreset::Lingual);
  EXPECT_FLOAT_EQ(v->elevation_rad, float(45.0 * std::numbers::pi / 180.0));
  EXPECT_TRUE(v->fixed);
  EXPECT_TRUE(v->mirror);
}

TEST(FirstView, ViewOptionOverridesTheTaskAndItsLock) {
  TaskView tv;
  tv.camera = "lingual";
  tv.elevation_deg = 45.0;
  tv.fixed = true;
  auto v = chooseFirstView("mesial", tv, false);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->preset, render::ViewPreset::Mesial);
  EXPECT_FLOAT_EQ(v->elevation_rad, kChairElevationRad);
  EXPECT_FALSE(v->fixed);
}

TEST(FirstView, AnUnknownViewIsAnError) { EXPECT_FALSE(chooseFirstView("palatal", std::nullopt, false)); }

TEST(FirstView, WithoutAMirrorTheCrownIsCentredAndRaised) {
  render::OrbitCamera camera;
  placeFirstView(camera, crown(), FirstView{});
  const glm::vec3 target = camera.target();
  EXPECT_FLOAT_EQ(target.x, 1.0f);
  EXPECT_FLOAT_EQ(target.y, 2.0f);
  EXPECT_FLOAT_EQ(target.z, 3.0f);
  EXPECT_NEAR(camera.pitch(), kChairElevationRad, 1e-6);
  // Buccal: the eye stands on the -y side of the crown, above it.
  EXPECT_LT(camera.eye().y, target.y);
  EXPECT_GT(camera.eye().z, target.z);
}

TEST(FirstView, TheOcclusalViewLooksStraightDownWhateverTheElevation) {
  render::OrbitCamera camera;
  FirstView v;
  v.preset = render::ViewPreset::Occlusal;
  v.elevation_rad = 0.1f;
  placeFirstView(camera, crown(), v);
  EXPECT_GT(camera.pitch(), 1.5f);  // at the pole, not raised 0.1 rad from the side
}

TEST(FirstView, AMirrorMovesTheTargetHalfwayToItsFaceAndKeepsBothInFrame) {
  const TissueBox box = crown();
  render::OrbitCamera plain;
  placeFirstView(plain, box, FirstView{});
  FirstView v;
  v.mirror = true;
  render::OrbitCamera camera;
  placeFirstView(camera, box, v);
  // The mirror's face as the mirror is placed from the unwidened eye.
  const Vec3 face = mirrorGrip(box, render::fromGlm(plain.eye())).apply(-kMirrorGripLocal);
  const Vec3 halfway = (box.centre() + face) * 0.5;
  EXPECT_NEAR(camera.target().x, halfway.x, 1e-4);
  EXPECT_NEAR(camera.target().y, halfway.y, 1e-4);
  EXPECT_NEAR(camera.target().z, halfway.z, 1e-4);
  // The widening is what makes room: every corner of the crown and the face stay in the frame.
  EXPECT_TRUE(inFrame(camera, face));
  for (int i = 0; i < 8; ++i) {
    const Vec3 p{(i & 1) ? box.hi.x : box.lo.x, (i & 2) ? box.hi.y : box.lo.y, (i & 4) ? box.hi.z : box.lo.z};
    EXPECT_TRUE(inFrame(camera, p)) << "corner " << i;
  }
}

}  // namespace
}  // namespace dentsim::app
