// Tests of the crown preparation's score: a round tooth prepared well, untouched, short occlusally, with parallel or over-tapered walls and with a ledge, each criterion's verdict and points against the rules counted by hand.
#include "eval/crown_score.h"
#include "io/input_budget.h"

#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <numbers>
#include <string>

#include "eval/cut_score.h"
#include "eval/score_image.h"
#include "eval/score_summary.h"

namespace dentsim {
namespace {

// A 128^3 grid of 0.07 mm voxels (8.96 mm): the tooth stands on the vertical line x = y = 4.48 mm
// (a voxel face), crown up. Mesial is the frame's default, -x; buccal is z x mesial = -y.
constexpr int kLevel = 7;
constexpr double kVoxelMm = 0.07;
constexpr double kCentreMm = 4.48;
// The original: a round crown of radius 3 mm from z = 0.35 to 8.4 mm, its top an occlusal table of
// radius 1.5 mm with a 60-degree bevel round it (so the table lies inside the preparation's top and
// every original sample outside it faces the side: a wall sample). Enamel 1 mm thick on the sides
// and 1.2 mm on top, down to the CEJ at z = 2 mm; dentin inside and below.
constexpr double kRadiusMm = 3.0, kBaseMm = 0.35, kTopMm = 8.4, kCejMm = 2.0, kTableMm = 1.5;
const double kBevelRise = std::tan(60.0 * std::numbers::pi / 180.0);

double originalRadius(double z) {
  if (z < kBaseMm || z > kTopMm) return -1;
  const double bevel_foot = kTopMm - (kRadiusMm - kTableMm) * kBevelRise;
  return z <= bevel_foot ? kRadiusMm : kRadiusMm - (z - bevel_foot) / kBevelRise;
}

// A preparation: below the margin the original; above it a frustum whose foot is `shoulder` inside
// the original (the shoulder's width) and whose walls lean in `half_angle_deg`, up to `occlusal`
// under the original's top. `ledge`: a block 0.6 mm wide left standing out of the distal (+x) wall
// from z = 5.0 to 5.5 mm, 2 mm across, above the gingival 2 mm where the taper is read: an undercut.
struct Prep {
  double margin_mm = 2.5;       // 0.5 mm over the CEJ
  double shoulder_mm = 1.0;
  double half_angle_deg = 7.0;  // TOC 14 deg, in the middle of 10-20
  double occlusal_mm = 1.75;
  bool ledge = false;
};

double prepRadius(const Prep& p, double z) {
  if (z <= p.margin_mm) return originalRadius(z);
  if (z > kTopMm - p.occlusal_mm) return -1;
  return kRadiusMm - p.shoulder_mm - (z - p.margin_mm) * std::tan(p.half_angle_deg * std::numbers::pi / 180.0);
}

// Every voxel whose centre lies inside: the original's tissue where the preparation keeps it.
// with_pulp: a pulp chamber of radius 1 mm from z = 2 to 5.5 mm inside the dentin.
ToothVolume tooth(const Prep* prep, bool with_pulp = false) {
  ToothVolume t{VolumeFrame::axisAligned(kLevel, kVoxelMm, {0, 0, 0}), BrickVolume(kLevel)};
  const int n = 1 << kLevel;
  for (int z = 0; z < n; ++z) {
    const double pz = (z + 0.5) * kVoxelMm;
    const double outer = originalRadius(pz);
    const double r = prep ? prepRadius(*prep, pz) : outer;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double dx = (x + 0.5) * kVoxelMm - kCentreMm, dy = (y + 0.5) * kVoxelMm - kCentreMm;
        const double d = std::sqrt(dx * dx + dy * dy);
        const bool in_ledge = prep && prep->ledge && pz > 5.0 && pz < 5.5 && std::abs(dy) < 1.0 && dx > 0 && d <= r + 0.6;
        if (d > outer || (d > r && !in_ledge)) continue;
        const bool enamel = pz > kCejMm && (d > outer - 1.0 || pz > kTopMm - 1.2);
        const bool pulp = with_pulp && d < 1.0 && pz > 2.0 && pz < 5.5;
        t.voxels.setVoxel(uint32_t(x), uint32_t(y), uint32_t(z),
                          makeVoxel(pulp ? Material::Pulp : enamel ? Material::Enamel : Material::Dentin));
      }
  }
  return t;
}

Task crownTask() {
  Task t;
  t.name = "test_crown";
  t.kind = TaskKind::Crown;
  t.title = "Crown";
  t.target_s = 900;
  t.insertion_axis = {0, 0, 1};
  return t;  // the crown's targets are CrownTask's defaults: an all-ceramic crown on a chamfer
}

CrownScore scored(const ToothVolume& initial, const ToothVolume& final_, const Task& task = crownTask()) {
  auto diff = compareTeeth(initial, final_, nullptr, ZoneOptions{task.leeway_mm, task.insertion_axis});
  EXPECT_TRUE(diff.ok()) << (diff.ok() ? "" : diff.message());
  if (!diff) return {};
  auto s = scoreCrownPreparation(task, initial, final_, *diff);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.message());
  return s.ok() ? *s : CrownScore{};
}

const CrownCriterion& at(const CrownScore& s, CrownCriterionId id) { return s.criterion(id); }

// Every criterion but `except` within and earning its whole points.
void expectWithinBut(const CrownScore& s, std::optional<CrownCriterionId> except) {
  for (int i = 0; i < kCrownCriterionCount; ++i) {
    const CrownCriterion& k = s.criteria[size_t(i)];
    if (except && int(*except) == i) continue;
    EXPECT_EQ(k.verdict, CrownVerdict::Within) << k.name << ": " << k.value << " " << k.why;
    EXPECT_DOUBLE_EQ(k.points, k.max) << k.name;
  }
}

ToothVolume& original() {
  static ToothVolume t = tooth(nullptr);
  return t;
}

// The points are 20 + 20 + 15 + 10 + 15 + 10 + 10 = 100.
TEST(CrownScore, APreparationWithinEveryRangeScoresAll) {
  const Prep prep;
  const CrownScore s = scored(original(), tooth(&prep));
  ASSERT_TRUE(s.margin_found);
  // The measures against the shape's own figures: the shoulder at 2.5 mm, 1 mm wide; the top 1.75
  // under the table; TOC 2 x 7 = 14 deg; height 6.65 - 2.5 = 4.15 mm.
  EXPECT_NEAR(s.margin_height_mm, 2.5, 2 * kVoxelMm);
  EXPECT_NEAR(s.margin.min_width_mm, 1.0, 0.1);
  ASSERT_TRUE(s.reduction.has_value());
  EXPECT_NEAR(s.reduction->occlusal.mean_mm, 1.75, 0.05);
  ASSERT_TRUE(s.shape.has_value());
  for (const TaperPlane& p : s.shape->planes) EXPECT_NEAR(p.toc_deg, 14.0, 1.5) << p.name;
  EXPECT_NEAR(s.shape->height_mm, 4.15, 2 * kVoxelMm);
  ASSERT_TRUE(s.undercut.has_value());
  EXPECT_LE(s.undercut->area_mm2, 0.1);
  EXPECT_DOUBLE_EQ(s.completion, 1.0);
  EXPECT_DOUBLE_EQ(s.coverage, 1.0);
  expectWithinBut(s, std::nullopt);
  EXPECT_DOUBLE_EQ(s.total, 100.0);
  EXPECT_DOUBLE_EQ(s.criteria_total, 100.0);
  EXPECT_FALSE(s.undercut_cap_applied);
  EXPECT_FALSE(s.pulp_exposed);
}

// A bur leaves the voxels it grazed with a little fill. Here every removed voxel keeps 5 of 31: read
// as tooth, the preparation would not show at all; at half fill it scores as the clean one, 100.
TEST(CrownScore, GrainsABurLeavesAreNotTooth) {
  const Prep prep;
  ToothVolume dusty = tooth(&prep);
  const ToothVolume& o = original();
  for (uint32_t z = 0; z < 128; ++z)
    for (uint32_t y = 0; y < 128; ++y)
      for (uint32_t x = 0; x < 128; ++x) {
        const Voxel was = o.voxels.voxel(x, y, z);
        if (voxelMaterial(was) != Material::Empty && voxelMaterial(dusty.voxels.voxel(x, y, z)) == Material::Empty)
          dusty.voxels.setVoxel(x, y, z, makeVoxel(voxelMaterial(was), 5));
      }
  const CrownScore s = scored(o, dusty);
  expectWithinBut(s, std::nullopt);
  EXPECT_DOUBLE_EQ(s.total, 100.0);
}

// A bur that passes inside a proximal wall it cannot reach (at a contact) leaves the wall's outer
// shell standing free: here the original's outer 0.3 mm on the mesial (-x) side, 2 mm across, from
// z = 4 to 5.5 mm (below the bevel, where the original is round), joined to nothing. It falls away in the mouth; read as tooth it would be an
// unprepared wall and an undercut. The score drops it and reads the clean preparation's 100.
TEST(CrownScore, AShellCutFreeOfTheWallIsMeasuredAsGone) {
  const Prep prep;
  ToothVolume shelled = tooth(&prep);
  const ToothVolume& o = original();
  uint64_t shell = 0;
  for (uint32_t z = 0; z < 128; ++z)
    for (uint32_t y = 0; y < 128; ++y)
      for (uint32_t x = 0; x < 128; ++x) {
        const double px = (x + 0.5) * kVoxelMm - kCentreMm, py = (y + 0.5) * kVoxelMm - kCentreMm, pz = (z + 0.5) * kVoxelMm;
        const double d = std::hypot(px, py);
        if (pz > 4.0 && pz < 5.5 && px < 0 && std::abs(py) < 1.0 && d > kRadiusMm - 0.3 && d <= kRadiusMm) {
          shelled.voxels.setVoxel(x, y, z, o.voxels.voxel(x, y, z));
          ++shell;
        }
      }
  ASSERT_GT(shell, 1000u);
  const CrownScore s = scored(o, shelled);
  EXPECT_EQ(s.loose.pieces, 1u);
  EXPECT_EQ(s.loose.voxels, shell);
  EXPECT_NEAR(s.loose_mm3, double(shell) * kVoxelMm * kVoxelMm * kVoxelMm, 1e-9);
  expectWithinBut(s, std::nullopt);
  EXPECT_DOUBLE_EQ(s.total, 100.0);
  ASSERT_TRUE(s.undercut.has_value());
  EXPECT_LE(s.undercut->area_mm2, 0.1);
  // Read as tooth, the shell would hang over the margin below it: about its 2 x 0.3 mm footprint.
  auto raw = measureUndercut(shelled.voxels, kVoxelMm, {0, 0, 1}, {-1, 0, 0}, s.margin_height_mm);
  ASSERT_TRUE(raw) << raw.message();
  EXPECT_GT(raw->area_mm2, 0.3);
}

// The measures copy the teeth over their tissue's box (about two bytes a voxel): past the memory
// budget the score is refused in one line naming the size and the budget, before anything is taken.
// Here the box is 96 x 96 x 128 voxels (the crown's 12 x 12 x 16 bricks), about 2.4 MB, against 1 MiB.
TEST(CrownScore, ATissueBoxPastTheMemoryBudgetIsRefused) {
  const Prep prep;
  const ToothVolume prepared = tooth(&prep);
  auto diff = compareTeeth(original(), prepared, nullptr, ZoneOptions{crownTask().leeway_mm, crownTask().insertion_axis});
  ASSERT_TRUE(diff.ok()) << diff.message();
  setMemoryBudget(1 << 20);
  const auto refused = scoreCrownPreparation(crownTask(), original(), prepared, *diff);
  setMemoryBudget(0);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("over the memory budget"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find("voxels"), std::string::npos) << refused.message();
  EXPECT_TRUE(scoreCrownPreparation(crownTask(), original(), prepared, *diff).ok());  // the default budget
}

// Nothing prepared: no finish line, every criterion outside and unmeasured, nothing earned.
TEST(CrownScore, AnUntouchedToothEarnsNothing) {
  const CrownScore s = scored(original(), original());
  EXPECT_FALSE(s.margin_found);
  EXPECT_DOUBLE_EQ(s.completion, 0.0);
  for (const CrownCriterion& k : s.criteria) {
    EXPECT_EQ(k.verdict, CrownVerdict::Outside) << k.name;
    EXPECT_FALSE(k.measured) << k.name;
    EXPECT_DOUBLE_EQ(k.points, 0.0) << k.name;
  }
  EXPECT_DOUBLE_EQ(s.total, 0.0);
}

// The crown cut off flat 1.75 mm down: the cut's edge reads as a finish line, but no wall stands above
// it and no sample's ray meets anything: nothing to grade, not even the undercut it cannot have.
TEST(CrownScore, ACrownCutOffFlatEarnsNothing) {
  ToothVolume flat = original();
  const uint32_t z0 = uint32_t(std::ceil((kTopMm - 1.75) / kVoxelMm - 0.5));  // centres above 6.65 mm
  for (uint32_t z = z0; z < 128; ++z)
    for (uint32_t y = 0; y < 128; ++y)
      for (uint32_t x = 0; x < 128; ++x) flat.voxels.setVoxel(x, y, z, Voxel{0});
  const CrownScore s = scored(original(), flat);
  EXPECT_TRUE(s.margin_found);
  EXPECT_DOUBLE_EQ(s.completion, 0.0);
  for (const CrownCriterion& k : s.criteria) EXPECT_DOUBLE_EQ(k.points, 0.0) << k.name << " " << k.value;
  EXPECT_DOUBLE_EQ(s.total, 0.0);
}

// The top taken down 0.5 mm, a third of the band's 1.5: the occlusal is outside (1.0 short, past the
// 0.5 near), and nothing else moves: the walls, taper, line and undercut are the same preparation's,
// the height grows to 5.4 mm, and the occlusal's samples, about a tenth of all, leave the reached
// share over the 0.8 at which the preparation counts as done.
TEST(CrownScore, AShallowOcclusalLosesOnlyTheOcclusalPart) {
  Prep prep;
  prep.occlusal_mm = 0.5;
  const CrownScore s = scored(original(), tooth(&prep));
  const CrownCriterion& occlusal = at(s, CrownCriterionId::OcclusalReduction);
  EXPECT_EQ(occlusal.verdict, CrownVerdict::Outside) << occlusal.value;
  EXPECT_DOUBLE_EQ(occlusal.points, 0.0);
  EXPECT_LT(s.reached_share, 1.0);
  EXPECT_DOUBLE_EQ(s.completion, 1.0);
  expectWithinBut(s, CrownCriterionId::OcclusalReduction);
  EXPECT_DOUBLE_EQ(s.total, 80.0);
}

// Walls parallel to the axis: TOC 0, under the near range's 4 deg: the taper's 15 are lost and
// nothing else (the walls stay 1 mm off, the shoulder's width).
TEST(CrownScore, ParallelWallsLoseOnlyTheTaper) {
  Prep prep;
  prep.half_angle_deg = 0.0;
  const CrownScore s = scored(original(), tooth(&prep));
  const CrownCriterion& taper = at(s, CrownCriterionId::Taper);
  EXPECT_EQ(taper.verdict, CrownVerdict::Outside) << taper.value;
  EXPECT_DOUBLE_EQ(taper.points, 0.0);
  expectWithinBut(s, CrownCriterionId::Taper);
  EXPECT_DOUBLE_EQ(s.total, 85.0);
}

// 20 deg a wall: TOC 40, past the 30 still judged acceptable.
TEST(CrownScore, OverTaperedWallsAreOutside) {
  Prep prep;
  prep.half_angle_deg = 20.0;
  const CrownScore s = scored(original(), tooth(&prep));
  ASSERT_TRUE(s.shape.has_value());
  for (const TaperPlane& p : s.shape->planes) EXPECT_NEAR(p.toc_deg, 40.0, 2.0) << p.name;
  EXPECT_EQ(at(s, CrownCriterionId::Taper).verdict, CrownVerdict::Outside);
  EXPECT_DOUBLE_EQ(at(s, CrownCriterionId::Taper).points, 0.0);
}

// A ledge 0.6 mm out of the distal wall hides about 0.6 x 2 mm of the wall under it from the path of
// insertion, beyond the 0.5 mm^2 tolerance: the undercut is outside, and the total held to the cap, 50.
TEST(CrownScore, AnUndercutCapsTheTotal) {
  Prep prep;
  prep.ledge = true;
  const CrownScore s = scored(original(), tooth(&prep));
  ASSERT_TRUE(s.undercut.has_value());
  EXPECT_GT(s.undercut->area_mm2, crownTask().crown.undercut_tolerance_mm2);
  // The ledge is 2 mm across and 0.6 mm out: a shadow of 1.2 mm^2 by hand, within 10 %.
  EXPECT_NEAR(s.undercut->area_mm2, 1.2, 0.12);
  std::printf("ledge: shadow %.3f mm2 (distal %.3f)\n", s.undercut->area_mm2, s.undercut->wall_area_mm2[size_t(AxialWall::Distal)]);
  EXPECT_EQ(at(s, CrownCriterionId::Undercut).verdict, CrownVerdict::Outside);
  EXPECT_TRUE(s.undercut_failed);
  EXPECT_TRUE(s.undercut_cap_applied);
  EXPECT_DOUBLE_EQ(s.total, crownTask().crown.undercut_cap);
}

// The top taken down 3.5 mm, to z = 4.9 mm, opens the pulp chamber (up to 5.5 mm): the occlusal is
// outside (1.5 past the band), the rest within, 80, held to the pulp's cap of 50.
TEST(CrownScore, AnExposedPulpCapsTheTotal) {
  Prep prep;
  prep.occlusal_mm = 3.5;
  const CrownScore s = scored(tooth(nullptr, true), tooth(&prep, true));
  EXPECT_TRUE(s.pulp_exposed);
  EXPECT_EQ(at(s, CrownCriterionId::OcclusalReduction).verdict, CrownVerdict::Outside);
  EXPECT_TRUE(s.pulp_cap_applied);
  EXPECT_FALSE(s.undercut_cap_applied);
  EXPECT_DOUBLE_EQ(s.total, crownTask().pulp_exposure_cap);
}

// A neighbour 0.12 mm beside the distal wall (x from 7.6 mm), nicked by 2 x 2 x 10 voxels:
// 40 x 0.07^3 = 0.01372 mm^3, above the 3-voxel noise floor: 25 + 100 x 0.01372 off a perfect 100.
TEST(CrownScore, ANickedNeighbourCostsTheAdjacentDeduction) {
  const Prep prep;
  ToothVolume initial = original();
  ToothVolume final_tooth = tooth(&prep);
  const uint32_t x0 = uint32_t(std::ceil(7.6 / kVoxelMm));  // 109
  for (uint32_t z = 30; z < 70; ++z)
    for (uint32_t y = 44; y < 84; ++y)
      for (uint32_t x = x0; x < 127; ++x) {
        initial.voxels.setVoxel(x, y, z, makeVoxel(Material::Neighbour));
        const bool nicked = x < x0 + 2 && y >= 63 && y < 65 && z >= 50 && z < 60;
        if (!nicked) final_tooth.voxels.setVoxel(x, y, z, makeVoxel(Material::Neighbour));
      }
  const CrownScore s = scored(initial, final_tooth);
  ASSERT_TRUE(s.adjacent.has_neighbour);
  EXPECT_TRUE(s.adjacent.damaged);
  const double removed = 40 * kVoxelMm * kVoxelMm * kVoxelMm;
  EXPECT_NEAR(s.adjacent.removed_mm3, removed, 1e-9);
  expectWithinBut(s, std::nullopt);
  EXPECT_NEAR(s.total, 100.0 - (25.0 + 100.0 * removed), 1e-9);
  const std::vector<ScoreLine> lines = scoreLines(s);
  ASSERT_EQ(lines.size(), 8u);
  EXPECT_EQ(lines.back().name, "adjacent");
  EXPECT_TRUE(lines.back().deduction);
}

// Sector i spans [5i, 5i + 5) degrees from mesial toward buccal; its middle names it.
TEST(CrownScore, MarginSectorsAreNamedByTheirSide) {
  EXPECT_STREQ(marginSectorDirection(0), "mesial");
  EXPECT_STREQ(marginSectorDirection(9), "mesiobuccal");   // 47.5 deg
  EXPECT_STREQ(marginSectorDirection(18), "buccal");       // 92.5
  EXPECT_STREQ(marginSectorDirection(36), "distal");       // 182.5
  EXPECT_STREQ(marginSectorDirection(54), "lingual");      // 272.5
  EXPECT_STREQ(marginSectorDirection(71), "mesial");       // 357.5
}

// End to end: scoreCut's crown branch, its report read back as every reader reads it, the lines for
// the screen and the picture's paint.
TEST(CrownScore, TheReportReadsBackWithItsPartsAndCompletion) {
  Prep prep;
  prep.half_angle_deg = 0.0;  // taper outside, so a part shows a loss
  const ToothVolume final_tooth = tooth(&prep);
  const Task task = crownTask();
  auto score = scoreCut(task, original(), final_tooth, nullptr, nullptr, scoreFiles("a.dvol", "b.dvol", ""));
  ASSERT_TRUE(score.ok()) << score.message();
  EXPECT_DOUBLE_EQ(score->total, 85.0);
  EXPECT_EQ(score->report["task"]["kind"], "crown");
  EXPECT_EQ(score->report["components"]["taper"]["verdict"], "outside");
  EXPECT_EQ(score->report["components"]["taper"]["range"], "10-20 deg TOC in every plane (near 4-30)");
  EXPECT_FALSE(score->report.contains("zones"));  // no ideal: no caries zone to count the preparation against
  EXPECT_EQ(score->report["session"]["scored"], false);
  auto back = ScoreReportSummary::fromJson(score->report);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->task_kind, "crown");
  EXPECT_DOUBLE_EQ(back->total, 85.0);
  ASSERT_TRUE(back->completion_share.has_value());
  EXPECT_DOUBLE_EQ(*back->completion_share, 1.0);
  const char* names[] = {"occlusal_reduction", "axial_reduction", "taper", "height", "margin_width", "margin_line", "undercut"};
  ASSERT_GE(back->parts.size(), 7u);
  for (size_t i = 0; i < 7; ++i) {
    EXPECT_EQ(back->parts[i].name, names[i]);
    EXPECT_FALSE(back->parts[i].deduction);
    EXPECT_TRUE(back->parts[i].max.has_value());
  }
  EXPECT_DOUBLE_EQ(*back->parts[2].points, 0.0);
  EXPECT_DOUBLE_EQ(*back->parts[2].table_points, 0.0);
  EXPECT_DOUBLE_EQ(*back->parts[3].table_points, 10.0);
  EXPECT_DOUBLE_EQ(*back->parts[3].earned_share, 1.0);
  // The undercut's cap sits among the deductions as the pulp's does: a cap and whether it held.
  bool cap_found = false;
  for (const ScoreReportPart& p : back->parts)
    if (p.name == "undercut_cap") {
      cap_found = true;
      EXPECT_TRUE(p.deduction);
      EXPECT_DOUBLE_EQ(*p.cap, 50.0);
      EXPECT_FALSE(*p.applied);
    }
  EXPECT_TRUE(cap_found);
  ASSERT_EQ(score->lines.size(), 7u);
  EXPECT_EQ(score->lines[2].name, "taper");
  EXPECT_NE(score->lines[2].detail.find(" deg "), std::string::npos) << score->lines[2].detail;
  EXPECT_NE(score->lines[2].detail.find("(10-20 deg) outside"), std::string::npos) << score->lines[2].detail;
  EXPECT_EQ(score->summary.rfind("crown preparation score 85.00 / 100", 0), 0u) << score->summary;
  ASSERT_TRUE(score->crown.has_value());
  // The paint: the finish line yellow and the reduction map; no undercut on this one.
  const CutMarks paint = crownPaint(*score->crown);
  uint64_t line = 0;
  for (uint64_t key : score->crown->margin.line_voxels) {
    const uint32_t mask = (1u << 21) - 1;
    line += paint.at(uint32_t(key & mask), uint32_t((key >> 21) & mask), uint32_t(key >> 42)) == kPaintYellow ? 1 : 0;
  }
  EXPECT_EQ(line, score->crown->margin.line_voxels.size());
  EXPECT_GT(score->crown->reduction->prepared_within.size(), 0u);
}

// With an ideal (here the well-prepared tooth), the report adds the zones against it and the surface
// agreement, reported and not scored: the total is the same as without.
TEST(CrownScore, AnIdealAddsTheSurfaceAgreementButNoPoints) {
  const Prep good;
  const ToothVolume ideal = tooth(&good);
  Prep parallel;
  parallel.half_angle_deg = 0.0;
  const ToothVolume final_tooth = tooth(&parallel);
  auto score = scoreCut(crownTask(), original(), final_tooth, &ideal, nullptr, scoreFiles("a.dvol", "b.dvol", ""));
  ASSERT_TRUE(score.ok()) << score.message();
  EXPECT_DOUBLE_EQ(score->total, 85.0);
  ASSERT_TRUE(score->agreement.has_value());
  EXPECT_EQ(score->report["surface_agreement"]["scored"], false);
  EXPECT_EQ(score->report["zones"]["target"], "ideal cavity");
  ASSERT_TRUE(score->reported.agreement.has_value());
  // The parallel walls stand up to 0.5 mm off the ideal's leaning ones near the top, inside the
  // band at their foot: some of the surface within, not all.
  EXPECT_GT(score->reported.agreement->within_percent, 0.0);
  EXPECT_LT(score->reported.agreement->within_percent, 100.0);
}

// The picture: the finish line yellow and the ledge's hidden underside magenta, in the oblique view.
TEST(CrownScore, ThePictureShowsTheLineAndTheUndercut) {
  Prep prep;
  prep.ledge = true;
  const ToothVolume final_tooth = tooth(&prep);
  auto score = scoreCut(crownTask(), original(), final_tooth, nullptr, nullptr, scoreFiles("", "", ""));
  ASSERT_TRUE(score.ok()) << score.message();
  const RgbImage picture = scorePicture(crownTask(), original(), final_tooth, *score, nullptr);
  int yellow = 0, magenta = 0, green = 0;
  for (int y = 0; y < picture.height; ++y)
    for (int x = 0; x < picture.width; ++x) {
      const auto p = picture.pixel(x, y);
      const int r = p[0], g = p[1], b = p[2];
      // Shading scales a colour, so its hue is read from the channels' proportions.
      if (r > 60 && g > 0.7 * r && b < 0.3 * r) ++yellow;
      if (r > 60 && b > 0.7 * r && g < 0.4 * r) ++magenta;
      if (g > 60 && r < 0.4 * g && b < 0.5 * g) ++green;
    }
  EXPECT_GT(yellow, 100);
  EXPECT_GT(magenta, 10);
  EXPECT_GT(green, 1000);
}

}  // namespace
}  // namespace dentsim
