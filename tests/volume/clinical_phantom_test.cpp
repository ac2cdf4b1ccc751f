// The clinical phantom's steps on grids of a few voxels: a neighbour's place, the bone slab's slices, the coarse voxels' means and centres.
#include <gtest/gtest.h>

#include "volume/clinical_phantom.h"

namespace dentsim {
namespace {

// Four voxels of 0.5 mm along i, values 0, 2, 4, 6, the first centre at x = 10 mm.
GreyImage fourInARow() {
  GreyImage g;
  g.dims = {4, 1, 1};
  g.pitch_mm = {0.5, 0.5, 0.5};
  g.scanner_from_voxel = {0.5, 0, 0, 10, 0, 0.5, 0, 0, 0, 0, 0.5, 0};
  g.values = {0, 2, 4, 6};
  return g;
}

TEST(ClinicalPhantom, CoarseVoxelsAreTheMeansOfTheFineOnesAndSitAtTheirMiddle) {
  Result<GreyImage> c = averageOntoVoxel(fourInARow(), 1.0, "row");
  ASSERT_TRUE(c.ok()) << c.message();
  // Two fine voxels a coarse one along i; j and k are one voxel, kept (1 mm is coarser, but there is one).
  ASSERT_EQ(c->dims[0], 2);
  EXPECT_FLOAT_EQ(c->values[0], 1.0f);
  EXPECT_FLOAT_EQ(c->values[1], 5.0f);
  EXPECT_DOUBLE_EQ(c->pitch_mm[0], 1.0);
  // Coarse voxel 0 covers fine centres 10 and 10.5: its centre is 10.25, the next 1 mm on.
  EXPECT_DOUBLE_EQ(c->scanner_from_voxel[3], 10.25);
  EXPECT_DOUBLE_EQ(c->scanner_from_voxel[0], 1.0);
  EXPECT_FALSE(averageOntoVoxel(fourInARow(), 0.0, "row").ok());
}

TEST(ClinicalPhantom, TheNeighbourIsTheToothShiftedByItsWidth) {
  LabelImage l;
  l.dims = {4, 1, 1};
  l.labels = {0, 2, 3, 0};  // the tooth spans i 1..2: 2 voxels wide
  Result<LabelImage> pair = withNeighbourCopy(l, "labels");
  ASSERT_TRUE(pair.ok()) << pair.message();
  ASSERT_EQ(pair->dims[0], 6);
  EXPECT_EQ(pair->labels, (std::vector<Label>{0, 2, 3, 2, 3, 0}));  // touching at i 2|3
  l.labels = {0, 0, 0, 0};
  EXPECT_FALSE(withNeighbourCopy(l, "labels").ok());
}

TEST(ClinicalPhantom, TheBoneSlabStartsAtTheToothsLowestSlice) {
  GreyImage g;
  g.dims = {1, 1, 5};
  g.pitch_mm = {1, 1, 1};
  g.values = {-1000, -1000, 1700, -1000, 2900};
  LabelImage l;
  l.dims = g.dims;
  l.labels = {0, 0, 3, 0, 2};  // the tooth starts at k = 2
  EXPECT_EQ(addBoneSlab(g, l, 2.0, 1000.0f), 2);
  EXPECT_EQ(g.values, (std::vector<float>{-1000, -1000, 1700, 1000, 2900}));  // dentin stays brighter than bone
}

}  // namespace
}  // namespace dentsim
