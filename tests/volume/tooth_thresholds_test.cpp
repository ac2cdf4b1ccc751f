// Tests of src/volume/tooth_thresholds.cpp: presets, given values, Otsu on the ROI and the refinements on the tooth, against hand values and analytic ones.
#include "volume/tooth_thresholds.h"

#include "volume/ct_segment.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dentsim {
namespace {

// A histogram callback that must not be called: the thresholds are all known without one.
GreyHistogram noHistogram() {
  ADD_FAILURE() << "the ROI's histogram was built though no threshold was automatic";
  return {};
}

// The robust histogram of the values of `values` in [lo, hi), as segmentTooth hands the tooth's.
GreyHistogram histogramOf(const std::vector<float>& values, double lo = -1e300, double hi = 1e300) {
  return robustHistogram([&](auto&& f) {
    for (float v : values)
      if (v >= lo && v < hi) f(v);
  });
}

TEST(ToothThresholds, APresetWithCariesMovesItsCutsDown) {
  // ct-hu is 1000 | 2100 HU with caries from 500: with caries, hard tissue starts at 500 and
  // dentin at 1000.
  ToothSegmentOptions o;
  o.preset = "ct-hu";
  o.caries = true;
  const Result<ToothThresholds> t = chooseThresholds(o, GreyUnit::Hounsfield, noHistogram);
  ASSERT_TRUE(t) << t.error().message;
  EXPECT_EQ(t->hard, 500.0);
  EXPECT_EQ(t->caries_below, 1000.0);
  EXPECT_EQ(t->enamel, 2100.0);
  EXPECT_EQ(t->dentinFloor(), 1000.0);
  EXPECT_EQ(thresholdsFrom(*t), "preset ct-hu");
}

TEST(ToothThresholds, GivenValuesReplaceAPresetsOneByOne) {
  ToothSegmentOptions o;
  o.preset = "cbct-hu";
  o.enamel_above = 1800;
  const Result<ToothThresholds> t = chooseThresholds(o, GreyUnit::Hounsfield, noHistogram);
  ASSERT_TRUE(t) << t.error().message;
  EXPECT_EQ(t->hard, 700.0);
  EXPECT_EQ(t->enamel, 1800.0);
  EXPECT_FALSE(t->caries_below);
  EXPECT_EQ(thresholdsFrom(*t), "dentin_above preset cbct-hu, enamel_above given");
}

TEST(ToothThresholds, ErrorsNameTheSourceAndTheValues) {
  ToothSegmentOptions o;
  o.where = "scan/";
  o.dentin_above = 2000;
  o.enamel_above = 1000;
  Result<ToothThresholds> t = chooseThresholds(o, GreyUnit::Raw, noHistogram);
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().message.find("dentin_above 2000 raw is not below enamel_above 1000 raw"), std::string::npos)
      << t.error().message;
  o = ToothSegmentOptions{};
  o.preset = "ct-hu";
  t = chooseThresholds(o, GreyUnit::Raw, noHistogram);
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().message.find("is for images in"), std::string::npos) << t.error().message;
}

TEST(ToothThresholds, AutomaticCutsFallInTheGapsOfATriModalRoi) {
  // Air -1000, dentin 1700, enamel 2900 HU, each spread +-100 HU: 3-class Otsu cuts in the gaps.
  std::vector<float> roi;
  for (int i = 0; i < 20000; ++i) {
    const float spread = -100.0f + 200.0f * float(i) / 19999.0f;
    roi.push_back(-1000.0f + spread);
    if (i % 2 == 0) roi.push_back(1700.0f + spread);
    if (i % 8 == 0) roi.push_back(2900.0f + spread);
  }
  ToothSegmentOptions o;
  const Result<ToothThresholds> t = chooseThresholds(o, GreyUnit::Hounsfield, [&] { return histogramOf(roi); });
  ASSERT_TRUE(t) << t.error().message;
  EXPECT_GT(t->hard, -900.0);
  EXPECT_LE(t->hard, 1600.0);
  EXPECT_GT(t->enamel, 1800.0);
  EXPECT_LE(t->enamel, 2800.0);
  EXPECT_TRUE(t->enamel_automatic);
  EXPECT_FALSE(t->caries_automatic);
}

TEST(ToothThresholds, RefinedEnamelIsHalfWayBetweenTheToothsPeaks) {
  // The tooth: 3000 voxels of dentin at 1700 HU and 1000 of enamel at 2900, with an edge blur
  // spread evenly from 300 to 1700 (the surface's, which pulls plain Otsu down). The bins span
  // about 305 .. 2900 HU (the 0.1 and 99.9 percentiles), about 10.1 HU each; the cut is half-way
  // between the two peaks' bin centres: 2300 HU, give or take a bin for where the peaks sit in them.
  std::vector<float> tooth(3000, 1700.0f);
  tooth.insert(tooth.end(), 1000, 2900.0f);
  for (int i = 0; i < 1000; ++i) tooth.push_back(300.0f + 1400.0f * float(i) / 1000.0f);
  ToothThresholds t;
  t.hard = 300;
  t.enamel = 1000;  // a placeholder from the ROI, as chooseThresholds leaves it
  t.enamel_automatic = true;
  ASSERT_TRUE(refineOnTooth(t, GreyUnit::Hounsfield, "t", [&](double lo, double hi) { return histogramOf(tooth, lo, hi); }));
  EXPECT_NEAR(t.enamel, 2300.0, 2600.0 / 256.0);
}

TEST(ToothThresholds, RefinedCariesCutIsThreeSigmaBelowSoundDentin) {
  // A hand-made histogram of the tooth below enamel: bins 4 HU wide, sound dentin a Gaussian of
  // sigma 50 HU whose peak is bin 150 (centre 1700 HU), and a flat lesion tail below it. The count
  // first falls to half the peak's 15 bins (60 HU) above it (exp(-60^2 / (2 x 50^2)) = 0.487), so
  // sigma is read as 60 / 1.1774 and the cut is 1700 - 3 x 60 / 1.1774 = 1547.1 HU.
  GreyHistogram h;
  h.lo = 1700.0 - 150.5 * 4.0;
  h.width = 4.0;
  h.count.assign(kOtsuBins, 0.0);
  for (size_t b = 0; b < kOtsuBins; ++b) {
    const double x = h.centre(b) - 1700.0;
    h.count[b] = 10000.0 * std::exp(-x * x / (2 * 50.0 * 50.0)) + (b < 100 ? 300.0 : 0.0);
    h.total += h.count[b];
  }
  ToothThresholds t;
  t.hard = 500;
  t.caries_below = 1000;  // a placeholder from the ROI
  t.enamel = 2300;
  t.caries_automatic = true;
  double asked_lo = 0, asked_hi = 0;
  ASSERT_TRUE(refineOnTooth(t, GreyUnit::Hounsfield, "t", [&](double lo, double hi) {
    asked_lo = lo;
    asked_hi = hi;
    return h;
  }));
  // The tooth's values from hard tissue up to enamel.
  EXPECT_EQ(asked_lo, 500.0);
  EXPECT_EQ(asked_hi, 2300.0);
  ASSERT_TRUE(t.caries_below);
  EXPECT_NEAR(*t.caries_below, 1700.0 - 3.0 * 60.0 / 1.1774, 1e-9);
}

}  // namespace
}  // namespace dentsim
