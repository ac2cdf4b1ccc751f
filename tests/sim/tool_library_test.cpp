// Tests of the built-in tool models: the tapered crown burs load, their cutting shells follow the catalog's taper, and the pocket planner reads their heads.
#include "sim/tool_library.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "model/tool_generator.h"
#include "sim/pocket_planner.h"

namespace dentsim {
namespace {

const char* const kTaperedBurs[] = {"chamfer_bur_016", "chamfer_bur_018", "shoulder_bur_014", "shoulder_bur_016"};

TEST(ToolLibrary, TaperedBurShellsCutOverTheirEightMillimetreHeads) {
  PointShellParams spacing;
  spacing.head_spacing_mm = 0.05;  // coarser than the default: this checks shape, not density
  spacing.shank_spacing_mm = 0.2;
  const double s = spacing.head_spacing_mm;
  for (const char* name : kTaperedBurs) {
    const ToolSpec* spec = findTool(name);
    ASSERT_NE(spec, nullptr) << name;
    auto bur = loadToolModel(name, spacing);
    ASSERT_TRUE(bur.ok()) << bur.message();
    EXPECT_TRUE(bur->cuts) << name;
    const PointShell& shell = bur->shell;
    ASSERT_GT(shell.cuttingCount(), 0u) << name;
    double lo = 1e9, hi = -1e9, worst = 0.0;
    size_t checked = 0;
    for (size_t i = 0; i < shell.size(); ++i) {
      const Vec3& p = shell.positions[i];
      if (!shell.cutting[i]) {
        EXPECT_GT(p.z, 8.0) << name << ": the shank side never cuts";
        continue;
      }
      lo = std::min(lo, p.z);
      hi = std::max(hi, p.z);
      // On the taper (away from the end's arc and the head's top face), each cutting point lies on
      // the profile within a point spacing.
      if (p.z < 0.5 || p.z > 8.0 - s) continue;
      worst = std::max(worst, std::abs(std::hypot(p.x, p.y) - burRadiusAt(*spec, p.z)));
      ++checked;
    }
    EXPECT_NEAR(lo, 0.0, s) << name << ": the cutting points start at the tip";
    EXPECT_NEAR(hi, 8.0, s) << name << ": and reach 8 mm up";
    EXPECT_LT(worst, s) << name;
    // About one point per spacing^2 on the 7 mm of cone checked (area 2 pi r_mean 7 mm).
    const double cone_area = 2.0 * std::numbers::pi * burRadiusAt(*spec, 4.25) * (8.0 - s - 0.5);
    EXPECT_GT(double(checked), 0.5 * cone_area / (s * s)) << name;
    // And the widths at a few heights: the widest point within a spacing of each.
    for (double h : {1.0, 4.0, 7.5}) {
      double widest = 0.0;
      for (size_t i = 0; i < shell.size(); ++i)
        if (shell.cutting[i] && std::abs(shell.positions[i].z - h) < 0.5 * s)
          widest = std::max(widest, std::hypot(shell.positions[i].x, shell.positions[i].y));
      EXPECT_NEAR(widest, burRadiusAt(*spec, h), s) << name << " at " << h << " mm";
    }
  }
}

TEST(ToolLibrary, PocketPlannerTakesATaperedBurByItsTip) {
  auto chamfer = burHead("chamfer_bur_016");
  ASSERT_TRUE(chamfer.ok()) << chamfer.message();
  EXPECT_TRUE(chamfer->round);
  EXPECT_NEAR(chamfer->radius_mm, 0.5 * (1.6 - 16.0 * std::tan(2.0 * std::numbers::pi / 180.0)), 1e-12);
  auto shoulder = burHead("shoulder_bur_014");
  ASSERT_TRUE(shoulder.ok()) << shoulder.message();
  EXPECT_FALSE(shoulder->round);
  EXPECT_NEAR(shoulder->radius_mm, 0.5 * (1.4 - 16.0 * std::tan(2.0 * std::numbers::pi / 180.0)), 1e-12);
  EXPECT_EQ(shoulder->length_mm, 8.0);
  auto mirror = burHead("mirror_size4");
  ASSERT_FALSE(mirror.ok());
  EXPECT_NE(mirror.message().find("mirror_size4"), std::string::npos) << mirror.message();
}

}  // namespace
}  // namespace dentsim
