// Tests for src/sim/pen_script.cpp: a tooth-frame script lands where the tooth frame says, on a turned tooth as on the built-in one, and a start inside the tooth is named.
#include "sim/pen_script.h"

#include <gtest/gtest.h>

#include "sim/builtin_tooth.h"
#include "sim/tool_library.h"
#include "volume/tooth_frame.h"

namespace dentsim {
namespace {

PenPath toothFramePath(const Vec3& grip, const Quat& rotation = {}) {
  PenPath p;
  p.frame = PenFrame::Tooth;
  PenSample s;
  s.pose = Pose{grip, rotation};
  p.samples.push_back(s);
  return p;
}

TEST(PenScript, OnTheBuiltInMolarTheToothFrameIsTheOcclusalCentreWithTheSameAxes) {
  auto molar = builtinMolarTooth(6);
  ASSERT_TRUE(molar.ok()) << molar.message();
  const Vec3 centre = toothOcclusalCentreMm(*molar);
  const PenPath sim = penPathInSimulationFrame(toothFramePath({1, 2, 21}), *molar);
  EXPECT_EQ(sim.frame, PenFrame::Simulation);
  const Pose& p = sim.samples[0].pose;
  EXPECT_NEAR(norm(p.position - (centre + Vec3{1, 2, 21})), 0.0, 1e-12);
  EXPECT_NEAR(norm(p.rotation.rotate({0, 0, 1}) - Vec3{0, 0, 1}), 0.0, 1e-12);
  // A simulation-frame path is played as written.
  PenPath plain = toothFramePath({1, 2, 3});
  plain.frame = PenFrame::Simulation;
  EXPECT_EQ(penPathInSimulationFrame(plain, *molar), plain);
}

TEST(PenScript, OnATurnedToothTheScriptFollowsTheAxes) {
  // A tooth whose frame says: crown +y, mesial +z (so distal -z), centre at (1, 2, 3).
  ToothVolume t{VolumeFrame::axisAligned(4, 1.0, {0, 0, 0}), BrickVolume(4)};
  t.frame.tooth.crown = {0, 1, 0};
  t.frame.tooth.mesial = {0, 0, 1};
  t.frame.tooth.buccal = {1, 0, 0};
  t.frame.tooth.has_occlusal_centre = true;
  t.frame.tooth.occlusal_centre_mm = {1, 2, 3};
  const PenPath sim = penPathInSimulationFrame(toothFramePath({0.5, 0, 19}), t);
  const Pose& p = sim.samples[0].pose;
  // x (distal) = -z, z (crown) = +y, y = z x x = (+y) x (-z) = -x.
  EXPECT_NEAR(norm(p.position - Vec3{1, 2 + 19, 3 - 0.5}), 0.0, 1e-12);
  // The bur upright in the tooth frame points its tip against the crown axis.
  EXPECT_NEAR(norm(p.rotation.rotate({0, 0, -1}) - Vec3{0, -1, 0}), 0.0, 1e-12);
  EXPECT_NEAR(norm(p.rotation.rotate({0, 1, 0}) - Vec3{-1, 0, 0}), 0.0, 1e-12);
}

TEST(PenScript, AStartInsideTheToothIsNamedAndAStartAboveItIsNot) {
  auto molar = builtinMolarTooth(6);
  ASSERT_TRUE(molar.ok()) << molar.message();
  const PenPath inside = penPathInSimulationFrame(toothFramePath({0, 0, 19 - 3.0}), *molar);  // tip 3 mm down
  const auto warnings = penPathStartWarnings(inside, *molar, "s.csv");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("s.csv: the bur starts inside the tooth (", 0), 0u) << warnings[0];
  EXPECT_NE(warnings[0].find("19 mm above the bur's tip"), std::string::npos) << warnings[0];
  const PenPath above = penPathInSimulationFrame(toothFramePath({0, 0, 19 + 2.0}), *molar);
  EXPECT_TRUE(penPathStartWarnings(above, *molar, "s.csv").empty());
  // The mirror's face inside the crown.
  PenPath mirror;
  PenSample s;
  s.pen = PenRole::Mirror;
  s.pose = Pose{toothOcclusalCentreMm(*molar) + Vec3{0, 0, -2} + kMirrorGripLocal, Quat{}};
  mirror.samples.push_back(s);
  const auto m = penPathStartWarnings(mirror, *molar, "m.csv");
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].rfind("m.csv: the mirror starts inside the tooth (", 0), 0u) << m[0];
}

}  // namespace
}  // namespace dentsim
