// Tests of src/volume/tissue_boundary_rules.cpp: classes and means, the outside, partial volume, edges and open caries on rows and small boxes counted by hand.
#include "volume/tissue_boundary_rules.h"

#include <gtest/gtest.h>

#include "volume/tissue_table.h"

namespace dentsim {
namespace {

using namespace tooth_cell;

// A grey image of dims holding `values` (i fastest), and the box of cells over all of it.
struct Box {
  GreyImage image;
  ToothBoxCells cells;
  Box(std::array<int32_t, 3> d, std::vector<float> values, std::vector<uint8_t> classes)
      : image(makeImage(d, std::move(values))), cells{image, {0, 0, 0}, d, std::move(classes)} {}
  static GreyImage makeImage(std::array<int32_t, 3> d, std::vector<float> values) {
    GreyImage im;
    im.dims = d;
    im.values = std::move(values);
    return im;
  }
};

// Every tissue of the table is either a class the grey values give or pulp, which importLabels fills
// as enclosed space: a tissue added to the table fails here until segmentation decides which it is.
// A neighbour is neither: a scan's segmentation keeps one tooth, and its neighbours are cut away.
// Each class is a table tissue, darker classes first (caries < dentin < enamel in mineral).
TEST(TissueBoundaryRules, EveryTissueOfTheTableIsAGreyClassOrFilledAfter) {
  for (const TissueRow& row : kTissueTable) {
    if (row.material == Material::Neighbour) {
      EXPECT_FALSE(isGreyClass(row.material));
      continue;
    }
    EXPECT_NE(isGreyClass(row.material), row.material == Material::Pulp) << row.name;
  }
  EXPECT_EQ(kClassTissue[0], Material::Empty);
  for (size_t c = 1; c < kClassTissue.size(); ++c) EXPECT_NE(findTissue(kClassTissue[c]), nullptr) << c;
  EXPECT_EQ(kClassTissue, (std::array<Material, 4>{Material::Empty, Material::Caries, Material::Dentin, Material::Enamel}));
}

TEST(TissueBoundaryRules, ClassifyByValueAndMeansByHand) {
  // Thresholds hard 500 | caries_below 1000 | enamel 2000 on a row of five: two empty cells (100 and
  // 300: mean 200), one non-tooth cell at 1500 (cut-away hard tissue: in no mean), and tooth cells at
  // 700 (caries), 1200 and 1400 (dentin, mean 1300), 2500 (enamel).
  Box b({8, 1, 1}, {100, 300, 1500, 700, 1200, 1400, 2500, 2500},
        {0, 0, 0, kToothMark, kToothMark, kToothMark, kToothMark, kToothMark});
  ToothThresholds thr;
  thr.hard = 500;
  thr.caries_below = 1000;
  thr.enamel = 2000;
  const ClassMeans m = classify(b.cells, thr);
  EXPECT_EQ(b.cells.cells, (std::vector<uint8_t>{0, 0, 0, kCaries, kDentin, kDentin, kEnamel, kEnamel}));
  EXPECT_DOUBLE_EQ(m.mean[0], 200.0);
  EXPECT_DOUBLE_EQ(m.mean[kCaries], 700.0);
  EXPECT_DOUBLE_EQ(m.mean[kDentin], 1300.0);
  EXPECT_DOUBLE_EQ(m.mean[kEnamel], 2500.0);
}

TEST(TissueBoundaryRules, OutsideStopsAtAClosedShellAndDarkMeansSplit) {
  // A 5^3 box with a closed shell of dentin around (2, 2, 2): 98 cells outside, the centre
  // enclosed. Values: the outside 0, the enclosed centre 40 (pulp), the shell 1700.
  const std::array<int32_t, 3> d{5, 5, 5};
  std::vector<uint8_t> classes(125, 0);
  std::vector<float> values(125, 0.0f);
  for (int64_t z = 1; z <= 3; ++z)
    for (int64_t y = 1; y <= 3; ++y)
      for (int64_t x = 1; x <= 3; ++x) {
        const uint64_t l = voxelIndex({x, y, z}, d);
        const bool centre = x == 2 && y == 2 && z == 2;
        classes[l] = centre ? 0 : kDentin;
        values[l] = centre ? 40.0f : 1700.0f;
      }
  Box b(d, values, classes);
  std::deque<uint64_t> queue;
  markOutside(b.cells.cells, d, queue);
  int outside = 0;
  for (uint8_t c : b.cells.cells) outside += (c & kOutside) != 0;
  EXPECT_EQ(outside, 98);
  EXPECT_EQ(b.cells.cells[voxelIndex({2, 2, 2}, d)], 0);
  const std::array<double, 2> dark = darkMeans(b.cells, 500.0, -1.0);
  EXPECT_DOUBLE_EQ(dark[0], 0.0);
  EXPECT_DOUBLE_EQ(dark[1], 40.0);
}

TEST(TissueBoundaryRules, PartialVolumeTurnsTheRimBrighterOrEmpty) {
  // Air | dentin 1700 | enamel | enamel | dentin 1200 | air, w = 1: both dentin cells lie within one
  // cell of the outside and of enamel. The split is half-way between the empty mean (0) and the
  // enamel mean (2900): 1450. So 1700 becomes enamel and 1200 empty: two cells reassigned.
  Box b({6, 1, 1}, {0, 1700, 2900, 2900, 1200, 0}, {0, kDentin, kEnamel, kEnamel, kDentin, 0});
  ClassMeans m;
  m.mean = {0.0, 700.0, 1700.0, 2900.0};
  std::deque<uint64_t> queue;
  EXPECT_EQ(applyPartialVolume(b.cells, 1, false, m, queue), 2u);
  EXPECT_EQ(b.cells.cells, (std::vector<uint8_t>{0, kEnamel, kEnamel, kEnamel, 0, 0}));
}

TEST(TissueBoundaryRules, EdgeRulePeelsCellsDarkerThanHalfWay) {
  // Air | 400 | 900 | 1700 | 1700 | air, all dentin (mean 1700), outside mean 0: the split is 850.
  // The first pass empties 400 (the 900 cell does not face empty space yet); the second empties
  // nothing more, since 900 > 850. One cell emptied; it becomes outside.
  Box b({6, 1, 1}, {0, 400, 900, 1700, 1700, 0}, {0, kDentin, kDentin, kDentin, kDentin, 0});
  std::deque<uint64_t> queue;
  markOutside(b.cells.cells, b.cells.d, queue);
  ClassMeans m;
  m.mean = {0.0, 700.0, 1700.0, 2900.0};
  EXPECT_EQ(applyEdgeRule(b.cells, 2, {0.0, 0.0}, m), 1u);
  EXPECT_EQ(b.cells.cells[1], kOutside);
  EXPECT_EQ(classOf(b.cells.cells[2]), kDentin);
}

TEST(TissueBoundaryRules, OpenThickCariesStaysAndAThinRimGoes) {
  // A 5^3 box of dentin (1700) with air at x = 0. A caries piece of 3^3 cells at x 1..3, y and z
  // 1..3 (value 800) is open (it touches the outside's column at x = 0, within w = 1) and thick (its
  // centre's six faces are all caries): kept. Separately the row x = 1..2 at (y, z) = (4, 4), a
  // caries rim of two cells with no thick cell, is rejected: at 800 it lies below half-way from the
  // outside's mean (0) to dentin's (1700), so it empties. 2 voxels rejected.
  const std::array<int32_t, 3> d{5, 5, 5};
  std::vector<uint8_t> classes(125, kDentin);
  std::vector<float> values(125, 1700.0f);
  for (int64_t z = 0; z < 5; ++z)
    for (int64_t y = 0; y < 5; ++y) {
      classes[voxelIndex({0, y, z}, d)] = 0;
      values[voxelIndex({0, y, z}, d)] = 0.0f;
    }
  for (int64_t z = 1; z <= 3; ++z)
    for (int64_t y = 1; y <= 3; ++y)
      for (int64_t x = 1; x <= 3; ++x) {
        classes[voxelIndex({x, y, z}, d)] = kCaries;
        values[voxelIndex({x, y, z}, d)] = 800.0f;
      }
  for (int64_t x = 1; x <= 2; ++x) {
    classes[voxelIndex({x, 4, 4}, d)] = kCaries;
    values[voxelIndex({x, 4, 4}, d)] = 800.0f;
  }
  Box b(d, values, classes);
  std::deque<uint64_t> queue;
  markOutside(b.cells.cells, d, queue);
  ClassMeans m;
  m.mean = {0.0, 800.0, 1700.0, 2900.0};
  EXPECT_EQ(keepOpenCaries(b.cells, 1, {0.0, 0.0}, m, queue), 2u);
  EXPECT_EQ(b.cells.cells[voxelIndex({2, 2, 2}, d)], kCaries);
  EXPECT_EQ(b.cells.cells[voxelIndex({1, 4, 4}, d)], 0);
  EXPECT_EQ(b.cells.cells[voxelIndex({2, 4, 4}, d)], 0);
}

}  // namespace
}  // namespace dentsim
