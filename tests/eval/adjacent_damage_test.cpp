// Tests of the adjacent-tooth deduction on a hand-made tooth with a neighbour block: the volume cut, the noise floor, the points, the report, the summary, the class report and the red in the picture.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "eval/attempt_reader.h"
#include "eval/class_report.h"
#include "eval/cut_score.h"
#include "eval/score_image.h"
#include "eval/score_summary.h"
#include "eval/scores.h"
#include "eval/tooth_diff.h"
#include "eval_fixtures.h"

namespace dentsim {
namespace {

using test::cariesTask;
using test::cavityTask;
using test::emptyTooth;
using test::kVoxelMm;
using test::setBox;

constexpr Voxel kEmpty = 0;
constexpr double kVoxelMm3 = kVoxelMm * kVoxelMm * kVoxelMm;  // 0.001 mm^3

// The treated tooth: enamel x 0..7, y 0..15, z 0..7 with a caries block x 2..5, y 6..9, z 4..7 open
// at the top. Its neighbour: a block x 10..15, y 0..15, z 0..7 (768 voxels), two empty voxels away.
ToothVolume toothWithNeighbour() {
  ToothVolume t = emptyTooth();
  setBox(t, {0, 0, 0}, {8, 16, 8}, makeVoxel(Material::Enamel));
  setBox(t, {2, 6, 4}, {6, 10, 8}, makeVoxel(Material::Caries));
  setBox(t, {10, 0, 0}, {16, 16, 8}, makeVoxel(Material::Neighbour));
  return t;
}

// The same tooth alone.
ToothVolume toothAlone() {
  ToothVolume t = toothWithNeighbour();
  setBox(t, {10, 0, 0}, {16, 16, 8}, kEmpty);
  return t;
}

// The caries removed whole; then `k` neighbour voxels cut out of its top row (x 10, y 0..k-1, z 7),
// the side that faces the tooth.
ToothVolume cariesRemovedAndNeighbourCut(const ToothVolume& initial, uint32_t k) {
  ToothVolume t = initial;
  setBox(t, {2, 6, 4}, {6, 10, 8}, kEmpty);
  setBox(t, {10, 0, 7}, {11, k, 8}, kEmpty);
  return t;
}

ToothDiff diffOf(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal = nullptr) {
  auto diff = compareTeeth(initial, final_, ideal, ZoneOptions{});
  EXPECT_TRUE(diff.ok()) << diff.message();
  return *diff;
}

TEST(AdjacentDamage, KNeighbourVoxelsCutAreKVoxelsOfVolumeAndCostTheFormula) {
  const ToothVolume initial = toothWithNeighbour();
  const Task task = cariesTask();
  for (uint32_t k : {4u, 7u, 16u}) {
    const ToothDiff diff = diffOf(initial, cariesRemovedAndNeighbourCut(initial, k));
    // Every cut voxel was full: k x 31 fill units.
    EXPECT_EQ(diff.adjacent().removed, uint64_t{k} * 31) << k;
    EXPECT_EQ(diff.adjacent().initial, uint64_t{768} * 31);
    const CariesScore s = scoreCariesRemoval(diff, nullptr, task);
    EXPECT_DOUBLE_EQ(s.adjacent.removed_mm3, k * kVoxelMm3) << k;
    EXPECT_TRUE(s.adjacent.damaged) << k;  // above the 3 voxels of the default floor
    // 25 + 100 points/mm^3 x k x 0.001 mm^3: 25.4, 25.7, 26.6.
    EXPECT_NEAR(s.adjacent.deduction, 25.0 + 0.1 * k, 1e-9) << k;
    // Removal 50 of 50 without a session, less the deduction; no healthy tissue was cut.
    EXPECT_DOUBLE_EQ(s.healthy_deduction, 0.0);
    EXPECT_NEAR(s.total, 50.0 - (25.0 + 0.1 * k), 1e-9) << k;
  }
}

TEST(AdjacentDamage, AtOrUnderTheNoiseFloorCostsNothingAndOneFillUnitMoreCostsTheMinimum) {
  const ToothVolume initial = toothWithNeighbour();
  const Task task = cariesTask();
  // Three whole voxels: exactly the floor of 3 voxels' fill. Not damage.
  const CariesScore at_floor = scoreCariesRemoval(diffOf(initial, cariesRemovedAndNeighbourCut(initial, 3)), nullptr, task);
  EXPECT_DOUBLE_EQ(at_floor.adjacent.removed_mm3, 3 * kVoxelMm3);
  EXPECT_FALSE(at_floor.adjacent.damaged);
  EXPECT_EQ(at_floor.adjacent.deduction, 0.0);
  EXPECT_DOUBLE_EQ(at_floor.total, 50.0);
  // One fill unit more (a fourth voxel at 30 of 31): damage, at 25 points and a little.
  ToothVolume grazed = cariesRemovedAndNeighbourCut(initial, 3);
  grazed.voxels.setVoxel(10, 3, 7, makeVoxel(Material::Neighbour, 30));
  const CariesScore over = scoreCariesRemoval(diffOf(initial, grazed), nullptr, task);
  EXPECT_TRUE(over.adjacent.damaged);
  EXPECT_NEAR(over.adjacent.deduction, 25.0 + 100.0 * (94.0 / 31.0) * kVoxelMm3, 1e-9);
  // The task's terms decide: a floor of 0 makes any cut damage, a coefficient of 0 leaves the minimum.
  Task strict = task;
  strict.adjacent.noise_voxels = 0.0;
  strict.adjacent.coefficient = 0.0;
  strict.adjacent.min_points = 40.0;
  const CariesScore s = scoreCariesRemoval(diffOf(initial, cariesRemovedAndNeighbourCut(initial, 1)), nullptr, strict);
  EXPECT_TRUE(s.adjacent.damaged);
  EXPECT_DOUBLE_EQ(s.adjacent.deduction, 40.0);
  EXPECT_DOUBLE_EQ(s.total, 10.0);
}

TEST(AdjacentDamage, TheToothsOwnSumsIgnoreTheNeighbour) {
  const ToothVolume with = toothWithNeighbour(), alone = toothAlone();
  const ToothDiff cut = diffOf(with, cariesRemovedAndNeighbourCut(with, 16));
  const ToothDiff clean = diffOf(with, cariesRemovedAndNeighbourCut(with, 0));
  const ToothDiff lone = diffOf(alone, cariesRemovedAndNeighbourCut(alone, 0));
  // healthy() and total() are the tooth's: cutting the neighbour, or having one, changes neither.
  EXPECT_EQ(cut.healthy(), clean.healthy());
  EXPECT_EQ(cut.healthy(), lone.healthy());
  EXPECT_EQ(cut.total(), lone.total());
  EXPECT_EQ(cut.healthy().initial, uint64_t{8 * 16 * 8 - 4 * 4 * 4} * 31);  // the enamel alone
  // The neighbour is never target, and its cut is not the tooth's over-cut or its healthy tissue outside.
  EXPECT_EQ(cut.adjacent().target, 0u);
  EXPECT_TRUE(cut.beyond_target.empty());
  EXPECT_TRUE(cut.healthy_outside_zone.empty());
  EXPECT_EQ(cut.adjacent_removed.voxelCount(), 16u);
  // The crown estimate is the tooth's: the same with the neighbour beside it.
  EXPECT_EQ(cut.crown.axis.x, lone.crown.axis.x);
  EXPECT_EQ(cut.crown.lo, lone.crown.lo);
  EXPECT_EQ(cut.crown.hi, lone.crown.hi);
}

TEST(AdjacentDamage, ACavityCountsTheNeighbourApartFromItsOvercutAndAnIdealThatCutItSetsNoTarget) {
  const ToothVolume initial = toothWithNeighbour();
  // The professional removed the caries and, by a slip, two neighbour voxels.
  ToothVolume ideal = cariesRemovedAndNeighbourCut(initial, 2);
  // The student removed the caries and eight neighbour voxels, nothing else of the tooth.
  const ToothVolume student = cariesRemovedAndNeighbourCut(initial, 8);
  const ToothDiff diff = diffOf(initial, student, &ideal);
  auto s = scoreCavityPreparation(diff, nullptr, cavityTask());
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_DOUBLE_EQ(s->ideal_mm3, 64 * kVoxelMm3);  // the caries block alone
  EXPECT_EQ(s->overcut_mm3, 0.0);                   // the neighbour is not the over-cut
  EXPECT_EQ(s->undercut_mm3, 0.0);
  EXPECT_DOUBLE_EQ(s->adjacent.removed_mm3, 8 * kVoxelMm3);
  EXPECT_NEAR(s->adjacent.deduction, 25.8, 1e-9);
  EXPECT_NEAR(s->total, 50.0 - 25.8, 1e-9);  // under-cut 25 + over-cut 25, no session
}

TEST(AdjacentDamage, TheReportHasThePartOnlyWhenTheToothHasANeighbour) {
  const Task task = cariesTask();
  const ToothVolume with = toothWithNeighbour(), alone = toothAlone();
  const ToothDiff cut = diffOf(with, cariesRemovedAndNeighbourCut(with, 5));
  const auto report = scoreReportJson(task, {}, cut, nullptr, scoreCariesRemoval(cut, nullptr, task));
  ASSERT_TRUE(report["deductions"].contains("adjacent"));
  const auto& a = report["deductions"]["adjacent"];
  EXPECT_NEAR(a["points"].get<double>(), 25.5, 1e-9);
  EXPECT_DOUBLE_EQ(a["removed_mm3"].get<double>(), 5 * kVoxelMm3);
  EXPECT_TRUE(a["damaged"].get<bool>());
  EXPECT_DOUBLE_EQ(a["noise_floor_mm3"].get<double>(), 3 * kVoxelMm3);
  EXPECT_DOUBLE_EQ(report["volumes"]["neighbour"]["removed_mm3"].get<double>(), 5 * kVoxelMm3);
  EXPECT_FALSE(report["healthy_removed_mm3"].contains("neighbour"));
  const std::vector<ScoreLine> lines = scoreLines(scoreCariesRemoval(cut, nullptr, task));
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[4].name, "adjacent");
  EXPECT_TRUE(lines[4].deduction);

  // No neighbour: no part, no neighbour volume, no line; the keys are the ones reports always had.
  const ToothDiff lone = diffOf(alone, cariesRemovedAndNeighbourCut(alone, 0));
  const CariesScore s = scoreCariesRemoval(lone, nullptr, task);
  EXPECT_FALSE(s.adjacent.has_neighbour);
  EXPECT_EQ(s.adjacent.deduction, 0.0);
  const auto plain = scoreReportJson(task, {}, lone, nullptr, s);
  std::vector<std::string> deductions, volumes;
  for (const auto& [key, value] : plain["deductions"].items()) deductions.push_back(key);
  for (const auto& [key, value] : plain["volumes"].items()) volumes.push_back(key);
  EXPECT_EQ(deductions, (std::vector<std::string>{"healthy", "pulp_exposure"}));
  EXPECT_EQ(volumes, (std::vector<std::string>{"voxel_mm", "fill_unit_mm3", "enamel", "dentin", "pulp", "caries", "healthy",
                                               "all", "pulp_exposed", "exposed_pulp_voxels"}));
  EXPECT_EQ(scoreLines(s).size(), 4u);
  EXPECT_EQ(scoreSummary(s, {}).find("adjacent"), std::string::npos);
  // With a neighbour left whole the part is there, at 0.
  const ToothDiff whole = diffOf(with, cariesRemovedAndNeighbourCut(with, 0));
  const auto kept = scoreReportJson(task, {}, whole, nullptr, scoreCariesRemoval(whole, nullptr, task));
  EXPECT_EQ(kept["deductions"]["adjacent"]["points"].get<double>(), 0.0);
  EXPECT_FALSE(kept["deductions"]["adjacent"]["damaged"].get<bool>());
}

TEST(AdjacentDamage, TheTerminalLineNamesTheDamage) {
  const ToothVolume with = toothWithNeighbour();
  const ToothDiff cut = diffOf(with, cariesRemovedAndNeighbourCut(with, 5));
  const std::string line = scoreSummary(scoreCariesRemoval(cut, nullptr, cariesTask()), {});
  EXPECT_NE(line.find(", adjacent tooth damaged -25.50"), std::string::npos) << line;
  EXPECT_NE(line.find("; adjacent tooth 0.005 mm^3 removed"), std::string::npos) << line;
}

TEST(AdjacentDamage, TheSummaryReadsAndWritesThePartAndOldReportsStillRead) {
  const Task task = cariesTask();
  const ToothVolume with = toothWithNeighbour();
  const ToothDiff cut = diffOf(with, cariesRemovedAndNeighbourCut(with, 5));
  const auto report = scoreReportJson(task, {}, cut, nullptr, scoreCariesRemoval(cut, nullptr, task));
  auto summary = ScoreReportSummary::fromJson(report);
  ASSERT_TRUE(summary.ok()) << summary.message();
  ASSERT_TRUE(summary->adjacent_removed_mm3.has_value());
  EXPECT_DOUBLE_EQ(*summary->adjacent_removed_mm3, 5 * kVoxelMm3);
  EXPECT_TRUE(summary->adjacent_damaged);
  EXPECT_DOUBLE_EQ(*summary->removed_mm3[size_t(tissueIndex(Material::Neighbour))], 5 * kVoxelMm3);
  const auto part = std::find_if(summary->parts.begin(), summary->parts.end(),
                                 [](const ScoreReportPart& p) { return p.name == "adjacent"; });
  ASSERT_NE(part, summary->parts.end());
  EXPECT_TRUE(part->deduction);
  EXPECT_NEAR(*part->points, 25.5, 1e-9);
  // Round trip through the cut-down report.
  auto again = ScoreReportSummary::fromJson(summary->toJson());
  ASSERT_TRUE(again.ok()) << again.message();
  EXPECT_EQ(*again, *summary);
  // A report without the part (an older one, or a tooth without neighbours) reads as no damage.
  nlohmann::ordered_json old = report;
  old["deductions"].erase("adjacent");
  old["volumes"].erase("neighbour");
  auto plain = ScoreReportSummary::fromJson(old);
  ASSERT_TRUE(plain.ok()) << plain.message();
  EXPECT_FALSE(plain->adjacent_removed_mm3.has_value());
  EXPECT_FALSE(plain->adjacent_damaged);
  EXPECT_FALSE(plain->removed_mm3[size_t(tissueIndex(Material::Neighbour))].has_value());
  EXPECT_FALSE(plain->toJson()["deductions"].contains("adjacent"));
}

TEST(AdjacentDamage, TheClassReportListsTheAttemptThatDamagedANeighbour) {
  const Task task = cariesTask();
  const ToothVolume with = toothWithNeighbour();
  AttemptReadOptions options;
  options.student = "dana";
  std::vector<ClassAttempt> attempts;
  for (uint32_t k : {0u, 6u}) {
    const ToothDiff diff = diffOf(with, cariesRemovedAndNeighbourCut(with, k));
    const auto report = scoreReportJson(task, {}, diff, nullptr, scoreCariesRemoval(diff, nullptr, task));
    auto a = parseScoreReport(report.dump(), "dana/" + std::to_string(k) + "/score.json", 1000.0 + k, "", options);
    ASSERT_TRUE(a.ok()) << a.message();
    EXPECT_EQ(a->adjacent_damaged, k > 0);
    attempts.push_back(*a);
  }
  const ClassReport r = buildClassReport(attempts, {});
  // Only the attempt that cut six neighbour voxels is flagged, for that alone (no pass mark given).
  ASSERT_EQ(r.flags.size(), 1u);
  EXPECT_EQ(r.attempts[r.flags[0].attempt].source, "dana/6/score.json");
  EXPECT_EQ(r.flags[0].reasons, (std::vector<std::string>{"adjacent tooth damaged"}));
}

bool redDominant(std::array<uint8_t, 3> c) { return c[0] > 2 * c[1] && c[0] > 2 * c[2]; }

int redPixels(const RgbImage& image) {
  int n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) n += redDominant(image.pixel(x, y)) ? 1 : 0;
  return n;
}

TEST(AdjacentDamage, TheScorePicturePaintsTheNeighbourCutRedAndTheNeighbourInItsColour) {
  // An enamel tooth with no caries, so that only the neighbour can be red.
  ToothVolume initial = toothWithNeighbour();
  setBox(initial, {2, 6, 4}, {6, 10, 8}, makeVoxel(Material::Enamel));
  ToothVolume final_ = initial;
  setBox(final_, {10, 4, 5}, {13, 12, 8}, kEmpty);  // a notch 3 x 8 x 3 voxels into the neighbour's top
  for (TaskKind kind : {TaskKind::Caries, TaskKind::Cavity}) {
    const ToothDiff cut = diffOf(initial, final_), none = diffOf(initial, initial);
    const CutMarks red = scorePictureRed(kind, cut), no_red = scorePictureRed(kind, none);
    EXPECT_EQ(red.voxelCount(), 72u);
    EXPECT_EQ(no_red.voxelCount(), 0u);
    const ScoreImage picture = renderScoreImage(initial, final_, nullptr, &red, {64, 64});
    const ScoreImage clean = renderScoreImage(initial, initial, nullptr, &no_red, {64, 64});
    EXPECT_EQ(redPixels(clean.image), 0);
    // The notch's 3 x 8 voxels from above, a few pixels each.
    EXPECT_GT(redPixels(picture.image), 20);
    const ScoreView& view = picture.views.at(0);
    auto pixelAbove = [&](const ScoreImage& s, double x, double y) {
      const auto p = view.pixelOf({x, y, 8.0});
      return s.image.pixel(int(std::floor(p[0])), int(std::floor(p[1])));
    };
    EXPECT_TRUE(redDominant(pixelAbove(picture, 11.5, 8.0)));
    // Untouched, the neighbour shows in its table colour (grey-blue): blue at least red, not red.
    const auto whole = pixelAbove(picture, 14.5, 8.0);
    EXPECT_FALSE(redDominant(whole));
    EXPECT_GE(whole[2], whole[0]);
    // The treated tooth's enamel is ivory: red above blue.
    const auto enamel = pixelAbove(picture, 4.0, 8.0);
    EXPECT_GT(enamel[0], enamel[2]);
  }
}

}  // namespace
}  // namespace dentsim
