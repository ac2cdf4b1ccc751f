// Tests of the crown preparation's scripted path: deterministic, within the bur's reach, clear of the neighbours, and reducing the crown as planned.
#include <gtest/gtest.h>

#include <numbers>

#include "model/tool_generator.h"
#include "sim/builtin_tooth.h"
#include "sim/crown_paths.h"
#include "sim/pocket_planner.h"
#include "sim/session_attempts.h"
#include "sim/tool_library.h"
#include "sim/sim_params.h"

namespace dentsim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const ToothAxes kAxes;  // crown +z, mesial -x, buccal -y

// A drill sample with the tip at `tip` and the bur along `bur` (unit), as the pen holds it.
PenSample drillSample(double t, const Vec3& tip, const Vec3& bur) {
  PenSample s;
  s.t_s = t;
  s.pen = PenRole::Drill;
  s.pose.rotation = AxisFrame::along(tip, bur, std::abs(bur.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}).rotation();
  s.pose.position = tip + s.pose.rotation.rotate(kBurGripLocal);
  s.pedal = 1.0;
  return s;
}
Vec3 tipOf(const PenSample& s) { return s.pose.position - s.pose.rotation.rotate(kBurGripLocal); }
Vec3 burOf(const PenSample& s) { return s.pose.rotation.rotate({0, 0, 1}); }

// A professional's crown in miniature: 10 occlusal samples with the bur upright over the crown's
// centre, then a lap of 72 samples (one every 5 degrees, from the buccal round) with the tip on a
// circle of radius 5 mm at height 1 and the bur's top leaning 4 degrees toward the axis.
ProfessionalPath miniatureCrown() {
  ProfessionalPath pro;
  double t = 0.0;
  for (int k = 0; k < 10; ++k) pro.path.samples.push_back(drillSample(t += 0.1, {0.2 * k - 1.0, 0, 5.5}, {0, 0, 1}));
  for (int k = 0; k < 72; ++k) {
    const double theta = (-90.0 + 5.0 * k) * kDeg;  // -90: buccal (-y)
    const Vec3 out{std::cos(theta), std::sin(theta), 0};
    pro.path.samples.push_back(drillSample(t += 0.1, out * 5.0 + Vec3{0, 0, 1}, Vec3{0, 0, std::cos(4 * kDeg)} - out * std::sin(4 * kDeg)));
  }
  pro.cut_start_s = 0.1;
  pro.cut_end_s = t;
  pro.elapsed_s = t;
  return pro;
}

// The bur's lean toward the axis [deg]: positive when its top leans in from the tip's side.
double leanIn(const PenSample& s) {
  const Vec3 tip = tipOf(s), bur = burOf(s);
  const Vec3 side = normalized(Vec3{tip.x, tip.y, 0});
  return std::atan2(-dot(bur, side), bur.z) / kDeg;
}

TEST(CrownPaths, TheOvertaperedHandLeansEveryLapNineDegreesFurtherAboutItsTip) {
  const ProfessionalPath pro = miniatureCrown();
  const PenPath over = derivedAttemptPath(pro, Attempt::Overtaper, {0, 0, 1}, kAxes);
  ASSERT_EQ(over.samples.size(), pro.path.samples.size());
  for (size_t k = 0; k < over.samples.size(); ++k) {
    const PenSample &a = pro.path.samples[k], &b = over.samples[k];
    EXPECT_NEAR(norm(tipOf(a) - tipOf(b)), 0.0, 1e-9) << k;  // the tip stays
    if (k < 10) {
      EXPECT_EQ(a.pose, b.pose) << k;  // the occlusal samples are not lapping
    } else {
      EXPECT_NEAR(leanIn(b), 4.0 + 9.0, 1e-6) << k;  // each wall 13 + 2 (the bur's taper) = 15 degrees
    }
  }
}

TEST(CrownPaths, TheShallowHandLiftsOnlyTheOcclusalSamples) {
  const ProfessionalPath pro = miniatureCrown();
  const DerivedAttemptSettings s;
  ASSERT_DOUBLE_EQ(s.shallow_mm, 1.3);
  const PenPath shallow = derivedAttemptPath(pro, Attempt::Shallow, {0, 0, 1}, kAxes, s);
  for (size_t k = 0; k < shallow.samples.size(); ++k) {
    const Vec3 moved = shallow.samples[k].pose.position - pro.path.samples[k].pose.position;
    EXPECT_NEAR(norm(moved - (k < 10 ? Vec3{0, 0, 1.3} : Vec3{})), 0.0, 1e-12) << k;
    EXPECT_EQ(shallow.samples[k].pose.rotation, pro.path.samples[k].pose.rotation);
  }
}

TEST(CrownPaths, TheUndercutLeansTheBuccalWallsBurOutward) {
  const ProfessionalPath pro = miniatureCrown();
  const PenPath under = derivedAttemptPath(pro, Attempt::WallUndercut, {0, 0, 1}, kAxes);
  for (size_t k = 10; k < under.samples.size(); ++k) {
    // The lap's sample k faces -90 + 5 (k - 10) degrees; buccal is -90: within 45 all of the turn,
    // fading to none at 60, untouched beyond.
    double off = std::abs(-90.0 + 5.0 * double(k - 10) + 90.0);
    off = std::min(off, 360.0 - off);
    const double weight = off <= 45.0 ? 1.0 : off >= 60.0 ? 0.0 : 1.0 - (off - 45.0) / 15.0;
    EXPECT_NEAR(leanIn(under.samples[k]), 4.0 - 12.0 * weight, 1e-6) << k;
    EXPECT_NEAR(norm(tipOf(under.samples[k]) - tipOf(pro.path.samples[k])), 0.0, 1e-9) << k;
  }
}

TEST(CrownPaths, TheThinMarginHoldsTheLingualLapOut) {
  const ProfessionalPath pro = miniatureCrown();
  const PenPath thin = derivedAttemptPath(pro, Attempt::ThinMargin, {0, 0, 1}, kAxes);
  for (size_t k = 0; k < thin.samples.size(); ++k) {
    const Vec3 moved = thin.samples[k].pose.position - pro.path.samples[k].pose.position;
    if (k < 10) {
      EXPECT_NEAR(norm(moved), 0.0, 1e-12);
      continue;
    }
    double off = std::abs(-90.0 + 5.0 * double(k - 10) - 90.0);  // lingual: +90
    off = std::min(off, 360.0 - off);
    const double weight = off <= 45.0 ? 1.0 : off >= 60.0 ? 0.0 : 1.0 - (off - 45.0) / 15.0;
    const Vec3 side = normalized(Vec3{tipOf(pro.path.samples[k]).x, tipOf(pro.path.samples[k]).y, 0});
    EXPECT_NEAR(norm(moved - side * (0.6 * weight)), 0.0, 1e-9) << k;
  }
}

TEST(CrownPaths, TheNickSwingsOnceTowardTheMesialAndTheRestFollowsLater) {
  const ProfessionalPath pro = miniatureCrown();
  DerivedAttemptSettings s;
  const PenPath nick = derivedAttemptPath(pro, Attempt::Nick, {0, 0, 1}, kAxes, s);
  // The lap faces the mesial (-x) at its sample 54 (-90 + 270 = 180 degrees): path sample 64.
  const auto steps = size_t(std::ceil(s.nick_s / 0.01));
  ASSERT_EQ(nick.samples.size(), pro.path.samples.size() + steps);
  for (size_t k = 0; k <= 64; ++k) EXPECT_EQ(nick.samples[k], pro.path.samples[k]) << k;
  double reach = 0.0;
  for (size_t k = 65; k < 65 + steps; ++k) {
    const Vec3 d = nick.samples[k].pose.position - pro.path.samples[64].pose.position;
    EXPECT_NEAR(d.y, 0.0, 1e-9);
    EXPECT_NEAR(d.z, 0.0, 1e-9);
    EXPECT_LE(d.x, 1e-12);  // toward the mesial only
    reach = std::max(reach, -d.x);
  }
  EXPECT_NEAR(reach, s.nick_mm, 1e-9);
  for (size_t k = 65; k < pro.path.samples.size(); ++k) {
    PenSample later = pro.path.samples[k];
    later.t_s += s.nick_s;
    EXPECT_EQ(nick.samples[k + steps], later) << k;
  }
}

// The built-in molar between its neighbours at level 7 (a 0.23 mm grid: the plan, not the cut).
const ToothVolume& molarBetweenNeighbours() {
  static const ToothVolume tooth = [] {
    auto t = builtinMolarNeighboursTooth(7);
    EXPECT_TRUE(t) << t.message();
    return std::move(*t);
  }();
  return tooth;
}

TEST(CrownPaths, ThePreparationIsPlannedTheSameEveryTime) {
  const ToothVolume& tooth = molarBetweenNeighbours();
  auto a = crownPrepPath(tooth.voxels, tooth.frame, defaultSimParams(), "chamfer_bur_016", {0, 0, 1});
  auto b = crownPrepPath(tooth.voxels, tooth.frame, defaultSimParams(), "chamfer_bur_016", {0, 0, 1});
  ASSERT_TRUE(a) << a.message();
  ASSERT_TRUE(b) << b.message();
  ASSERT_EQ(a->path.samples.size(), b->path.samples.size());
  for (size_t k = 0; k < a->path.samples.size(); ++k) ASSERT_EQ(a->path.samples[k], b->path.samples[k]) << k;
  EXPECT_GT(a->laps_end_s, a->cut_start_s);
  EXPECT_GT(a->cut_end_s, a->laps_end_s);
  EXPECT_NEAR(a->lean_deg, 5.0, 0.05);  // 7 degrees of wall less the bur's 2 of taper
}

// The finished wall is gone round finish_laps times after the last lap that steps in: every lap
// starts and ends where the laps begin (on the buccal), so the final lap's start, at the wall's
// foot, is visited once on arriving and once at the end of each of the 1 + finish_laps laps there.
TEST(CrownPaths, TheLastLapIsGoneRoundAgainToFinishTheWall) {
  const ToothVolume& tooth = molarBetweenNeighbours();
  for (int finish : {1, 3}) {
    CrownPrepSettings settings;
    settings.finish_laps = finish;
    auto made = crownPrepPath(tooth.voxels, tooth.frame, defaultSimParams(), "chamfer_bur_016", {0, 0, 1}, settings);
    ASSERT_TRUE(made) << made.message();
    const auto end = std::find_if(made->path.samples.begin(), made->path.samples.end(),
                                  [&](const PenSample& p) { return p.t_s >= made->laps_end_s - 1e-9; });
    ASSERT_NE(end, made->path.samples.end());
    const Vec3 foot = tipOf(*end);
    int visits = 0;
    bool at = false;
    for (auto p = made->path.samples.begin(); p <= end; ++p) {
      const bool here = norm(tipOf(*p) - foot) < 1e-6;
      if (here && !at) ++visits;
      at = here;
    }
    EXPECT_EQ(visits, 2 + finish) << finish;
  }
}

// The chamfer's width is planned from the original surface at the finish line's own height, as the
// margin measure reads it: away from the neighbours (where the foot moves in further for the bur's
// clearance) every sector's width lies in the settings' band, less what smoothing the foot over five
// sectors moves it, and the mean in the band.
TEST(CrownPaths, TheFinishLineIsPlannedWideFromTheSurfaceAtItsOwnHeight) {
  const ToothVolume& tooth = molarBetweenNeighbours();
  const CrownPrepSettings settings;
  auto made = crownPrepPath(tooth.voxels, tooth.frame, defaultSimParams(), "chamfer_bur_016", {0, 0, 1}, settings);
  ASSERT_TRUE(made) << made.message();
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < made->sector_deg.size(); ++i) {
    if (made->beside_neighbour[i]) continue;
    // Square to the line: the radial step times the cosine of the outline's obliquity.
    EXPECT_GE(made->width_scale[i], 1.0);
    EXPECT_LE(made->width_scale[i], std::sqrt(2.0) + 1e-12);
    const double width = (made->surface_r[i] - made->foot_r[i]) / made->width_scale[i];
    EXPECT_GE(width, settings.margin_width_lo_mm - 0.1) << made->sector_deg[i];
    EXPECT_LE(width, settings.margin_width_hi_mm + 0.1) << made->sector_deg[i];
    sum += width;
    ++n;
  }
  ASSERT_GT(n, 20);
  EXPECT_GE(sum / n, settings.margin_width_lo_mm - 0.02);
  EXPECT_LE(sum / n, settings.margin_width_hi_mm + 0.02);
  // The finish line over the CEJ by the settings' height, every sector (smoothed over three).
  for (size_t i = 0; i < made->sector_deg.size(); ++i)
    EXPECT_NEAR(made->margin_h[i] - made->cej_h[i], settings.margin_above_cej_mm, 0.3) << made->sector_deg[i];
}

TEST(CrownPaths, TheBurStaysOverTheToothAndClearOfTheNeighbours) {
  const ToothVolume& tooth = molarBetweenNeighbours();
  const CrownPrepSettings settings;
  auto made = crownPrepPath(tooth.voxels, tooth.frame, defaultSimParams(), "chamfer_bur_016", {0, 0, 1}, settings);
  ASSERT_TRUE(made) << made.message();
  // The neighbours' voxels, counted here from the grid.
  std::vector<Vec3> neighbour;
  const double v = tooth.frame.voxel_mm;
  tooth.voxels.forEachBrick([&](const BrickView& b) {
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      const Voxel x = b.at(i);
      if (voxelMaterial(x) != Material::Neighbour || voxelFill(x) == 0) continue;
      const Vec3 c{tooth.frame.origin_mm[0] + (b.coord.x * DS_BRICK_DIM + (i & 7u) + 0.5) * v,
                   tooth.frame.origin_mm[1] + (b.coord.y * DS_BRICK_DIM + ((i >> 3) & 7u) + 0.5) * v,
                   tooth.frame.origin_mm[2] + (b.coord.z * DS_BRICK_DIM + (i >> 6) + 0.5) * v};
      if (std::abs(c.y) < 6 && c.z > -1 && c.z < 9 && std::abs(c.x) < 8) neighbour.push_back(c);
    }
  });
  ASSERT_FALSE(neighbour.empty());
  const ToolSpec* bur = findTool("chamfer_bur_016");
  ASSERT_NE(bur, nullptr);
  double least = HUGE_VAL;
  bool any_beside = false;
  for (size_t k = 0; k < made->path.samples.size(); k += 7) {
    const PenSample& p = made->path.samples[k];
    const Vec3 tip = tipOf(p), dir = burOf(p);
    // Over the tooth's grid and never below the CEJ's lowest, less a millimetre.
    EXPECT_GT(tip.z, *std::min_element(made->cej_h.begin(), made->cej_h.end()) + made->centre_mm.z - 1.0) << k;
    if (p.pedal <= 0) continue;
    for (const Vec3& q : neighbour) {
      const double t = std::clamp(dot(q - tip, dir), 0.0, bur->cutting_length_mm);
      least = std::min(least, norm(q - tip - dir * t) - burRadiusAt(*bur, t) - 0.5 * v);
    }
  }
  for (bool beside : made->beside_neighbour) any_beside = any_beside || beside;
  EXPECT_TRUE(any_beside);  // the contacts hold the laps in
  // The plan's clearance, within the 1-degree steps' chord between samples checked every 7th.
  EXPECT_GE(least, settings.neighbour_clearance_mm - 0.1);
}

}  // namespace
}  // namespace dentsim
