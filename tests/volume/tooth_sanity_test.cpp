// The human-tooth ranges of volume/tooth_sanity.h on made-up sizes, thresholds and voxels: which pass, which are named.
#include <gtest/gtest.h>

#include "volume/tissue_table.h"
#include "volume/tooth_sanity.h"

namespace dentsim {
namespace {

bool names(const std::string& text, const std::string& words) { return text.find(words) != std::string::npos; }

TEST(ToothSanity, HumanTeethPassAndTheHeadCtToothIsNamed) {
  EXPECT_EQ(humanToothSizeProblem({250.0, 21.0}), "");   // a lower incisor
  EXPECT_EQ(humanToothSizeProblem({800.0, 20.0}), "");   // a permanent molar
  EXPECT_EQ(humanToothSizeProblem({1000.0, 32.0}), "");  // a long canine
  // The head CT of issue 42: bone and teeth together at a soft-tissue threshold.
  const std::string head = humanToothSizeProblem({62000.0, 48.0});
  EXPECT_TRUE(names(head, "62000 mm^3")) << head;
  EXPECT_TRUE(names(head, "50..3000 mm^3")) << head;
  const std::string speck = humanToothSizeProblem({12.0, 4.0});
  EXPECT_TRUE(names(speck, "12 mm^3")) << speck;
}

TEST(ToothSanity, ALengthBeyondAnyToothIsNamedEvenAtAToothsVolume) {
  // 900 mm^3 is a molar's, but 40 mm is longer than any tooth: a root and the bone below it.
  const std::string long_one = humanToothSizeProblem({900.0, 40.0});
  EXPECT_TRUE(names(long_one, "40.0 mm long")) << long_one;
  EXPECT_TRUE(names(long_one, "at most 35 mm")) << long_one;
  EXPECT_EQ(humanToothSizeProblem({900.0, human_tooth::kMaxLengthMm}), "");  // the bound itself passes
}

TEST(ToothSanity, TheSizeOfASegmentationCountsHardTissueAndItsLongestBoxEdge) {
  ToothSegmentReport r;
  for (size_t t = 0; t < kTissueCount; ++t)  // 100 voxels of each tissue
    r.tissue_voxels[t] = 100;
  r.tooth_lo = {13, 23, 33};
  r.tooth_hi = {16, 36, 76};  // 4, 14 and 44 voxels
  const ToothSize size = segmentedToothSize(r, {0.5, 0.5, 0.25});
  // Enamel, dentin and caries: 300 voxels of 0.0625 mm^3. The pulp (never a grey class) and a
  // neighbour (another tooth, not this one's volume) are left out.
  EXPECT_DOUBLE_EQ(size.hard_mm3, 300 * 0.0625);
  EXPECT_DOUBLE_EQ(size.length_mm, 44 * 0.25);  // 11 mm along k: longer than j's 7 mm though fewer voxels
}

TEST(ToothSanity, ANeighbourBesideTheToothAddsNothingToItsHardTissue) {
  ToothSegmentReport alone;
  alone.tissue_voxels[size_t(tissueIndex(Material::Enamel))] = 4000;
  alone.tissue_voxels[size_t(tissueIndex(Material::Dentin))] = 12000;
  ToothSegmentReport beside = alone;
  // An adjacent tooth five times the treated one's size: a whole second molar in the volume.
  beside.tissue_voxels[size_t(tissueIndex(Material::Neighbour))] = 80000;
  const std::array<double, 3> pitch{0.1, 0.1, 0.1};
  EXPECT_DOUBLE_EQ(segmentedToothSize(beside, pitch).hard_mm3, segmentedToothSize(alone, pitch).hard_mm3);
  EXPECT_NEAR(segmentedToothSize(beside, pitch).hard_mm3, 16.0, 1e-9);  // 16000 voxels of 0.001 mm^3
}

TEST(ToothSanity, ADentinThresholdInSoftTissueIsNamedOnlyInHu) {
  EXPECT_EQ(dentinThresholdProblem(354.0, GreyUnit::Hounsfield), "");
  const std::string low = dentinThresholdProblem(-474.0, GreyUnit::Hounsfield);
  EXPECT_TRUE(names(low, "-474 HU")) << low;
  EXPECT_EQ(dentinThresholdProblem(-474.0, GreyUnit::Raw), "");  // a raw scale's zero means nothing
}

TEST(ToothSanity, VoxelsCoarserThanThinEnamelAreNamed) {
  EXPECT_EQ(coarseVoxelProblem({0.034, 0.034, 0.034}), "");  // micro-CT
  EXPECT_EQ(coarseVoxelProblem({0.3, 0.3, 0.3}), "");        // a CBCT at the bound
  const std::string clinical = coarseVoxelProblem({0.96, 0.96, 1.5});  // the head CT of issue 42
  EXPECT_TRUE(names(clinical, "0.96 x 0.96 x 1.5 mm")) << clinical;
}

}  // namespace
}  // namespace dentsim
