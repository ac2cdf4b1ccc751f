// The window's view keys with the tools where the simulator starts them on the built-in molar: no preset looks at the tooth through the handpiece or the mirror.
#include <gtest/gtest.h>

#include <cmath>

#include "app/tool_placement.h"
#include "model/tool_generator.h"
#include "render/camera.h"
#include "sim/surface_probe.h"
#include "ui/camera_control.h"

namespace dentsim::app {
namespace {

TEST(ViewPresets, NoPresetHidesTheMolarBehindTheDrillOrTheMirrorWhereTheyStart) {
  // The built-in molar's tissue box, crown up (its size at any level, to a voxel) [mm].
  TissueBox box;
  box.lo = {-5.6, -5.0, -13.5};
  box.hi = {5.6, 5.0, 7.5};
  const Vec3 c = box.centre();
  const float radius = float(0.5 * norm(box.hi - box.lo) * 1.25);  // as the window's keys pass it
  const double mirror_mm = findTool("mirror_size4")->head_diameter_mm;
  for (render::ViewPreset p : {render::ViewPreset::Occlusal, render::ViewPreset::Buccal, render::ViewPreset::Lingual,
                               render::ViewPreset::Mesial, render::ViewPreset::Distal}) {
    render::OrbitCamera camera;
    ui::CameraControl control(camera);
    camera.setView(p, render::toGlm(c), radius);
    // The mirror is placed for the eye the preset gives, as R puts it back.
    const Pose mirror = mirrorGrip(box, render::fromGlm(camera.eye()));
    const std::vector<Vec3> tools = toolSightPoints(drillStartGrip(box, 3.0), &mirror, mirror_mm);
    const bool plain_hidden = control.toolsHideTooth(c, radius, tools);
    ASSERT_TRUE(control.showPreset(p, c, radius, tools));
    EXPECT_FALSE(control.toolsHideTooth(c, radius, tools)) << render::viewPresetName(p);
    if (p == render::ViewPreset::Occlusal) {
      EXPECT_TRUE(plain_hidden) << "the plain top view looks down the handpiece: what the dodge is for";
      EXPECT_GT(camera.pitch(), 0.7f) << "still a view from above";
    }
  }
}

}  // namespace
}  // namespace dentsim::app
