// Tests of the seeded cut on a real tooth: tooth_2 as a head CT sees it keeps its whole self from any seed in it.
//
// The phantom is make-scan's clinical one (volume/clinical_phantom.h): tooth_2's labels at every
// second voxel (0.068 mm; the 1 mm average hardly changes with the fine grid, and this keeps the
// test at a quarter of a gigabyte), the scan model without noise, averaged onto 1 mm voxels, then
// noise of 60 HU. At 1 mm the pulp makes the hard mask's walls one or two voxels thin, which is
// where the cut used to part the tooth from itself. That two touching teeth still part is
// CtSegment.SeedKeepsTheToothAndCutsTheTouchingToothAndTheBone (ct_segment_test.cpp): make-scan's
// copy of tooth_2 does not touch it in the hard mask at 1, 0.5 or 0.3 mm (its contact averages
// below the dentin threshold).
#include "volume/ct_segment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include "io/nifti_labels.h"
#include "test_support.h"
#include "volume/clinical_phantom.h"
#include "volume/scan_model.h"

namespace dentsim {
namespace {

constexpr double kPitchMm = 0.034;  // tooth_2's real pitch; its header says 1.0 (data README)
constexpr int kStride = 2;

// tooth_2's labels at every second voxel, the geometry scaled to the true pitch; empty when the
// shared data is not there.
std::optional<LabelImage> tooth2Labels() {
  const std::filesystem::path data = test::dataDir();
  if (data.empty() || !std::filesystem::exists(data / "ct" / "tooth_2.nii.gz")) return std::nullopt;
  Result<LabelImage> read = readNiftiLabels((data / "ct" / "tooth_2.nii.gz").string());
  if (!read) return std::nullopt;
  const LabelImage& in = *read;
  LabelImage out;
  for (size_t a = 0; a < 3; ++a) out.dims[a] = in.dims[a] / kStride;
  const double pitch = kPitchMm * kStride;
  out.pitch_mm = {pitch, pitch, pitch};
  out.scanner_from_voxel = in.scanner_from_voxel;
  for (size_t r = 0; r < 3; ++r)
    for (size_t a = 0; a < 3; ++a) out.scanner_from_voxel[4 * r + a] *= pitch / in.pitch_mm[a];
  out.labels.resize(size_t(out.voxelCount()));
  for (int64_t k = 0; k < out.dims[2]; ++k)
    for (int64_t j = 0; j < out.dims[1]; ++j)
      for (int64_t i = 0; i < out.dims[0]; ++i)
        out.labels[out.index(i, j, k)] = in.labels[in.index(i * kStride, j * kStride, k * kStride)];
  return out;
}

// make-scan's steps without the bone: the scan, the 1 mm average, then the noise.
GreyImage clinicalScan(const LabelImage& labels) {
  const std::map<int32_t, Material> tissues{{1, Material::Caries}, {2, Material::Enamel}, {3, Material::Dentin}};
  ScanModel model;
  model.noise = 0.0;
  Result<GreyImage> fine = simulateScan(labels, tissues, model);
  EXPECT_TRUE(fine) << fine.message();
  Result<GreyImage> coarse = averageOntoVoxel(*fine, 1.0, "tooth_2");
  EXPECT_TRUE(coarse) << coarse.message();
  addScanNoise(*coarse, 60.0, 1);
  return std::move(coarse).value();
}

std::array<double, 3> mmOf(const GreyImage& im, int64_t i, int64_t j, int64_t k) {
  std::array<double, 3> p{};
  for (size_t r = 0; r < 3; ++r)
    p[r] = im.scanner_from_voxel[4 * r] * double(i) + im.scanner_from_voxel[4 * r + 1] * double(j) +
           im.scanner_from_voxel[4 * r + 2] * double(k) + im.scanner_from_voxel[4 * r + 3];
  return p;
}

ToothSegmentOptions ctHu() {
  ToothSegmentOptions o;
  o.preset = "ct-hu";  // at 1 mm automatic thresholds land in the partial-volume rim (PATIENT_SCANS.md)
  o.where = "tooth_2";
  return o;
}

TEST(SeededSplitTooth2, EverySeedInTheToothKeepsTheWholeTooth) {
  const std::optional<LabelImage> labels = tooth2Labels();
  if (!labels) GTEST_SKIP() << "real CT data (tooth_2.nii.gz) not found in " << test::dataDir();
  const GreyImage scan = clinicalScan(*labels);
  ToothSegmentOptions o = ctHu();
  ToothSegmentReport whole;
  ASSERT_TRUE(segmentTooth(scan, o, nullInterrupter(), &whole).ok());
  // One tooth alone: the largest hard piece is all of it, a few hundred 1 mm voxels.
  ASSERT_GT(whole.tooth_voxels, 300u);
  uint64_t seeds = 0, worst = whole.tooth_voxels;
  for (int64_t k = 0; k < scan.dims[2]; ++k)
    for (int64_t j = 0; j < scan.dims[1]; ++j)
      for (int64_t i = 0; i < scan.dims[0]; ++i) {
        if (scan.values[scan.index(i, j, k)] < 1000.0f) continue;  // ct-hu's dentin_above
        o.seed_mm = mmOf(scan, i, j, k);
        ToothSegmentReport cut;
        Result<LabelImage> r = segmentTooth(scan, o, nullInterrupter(), &cut);
        // A hard speck apart from the tooth is refused as no tooth; it is not the tooth's to keep.
        if (!r.ok() || cut.hard_component_voxels != whole.tooth_voxels) continue;
        ++seeds;
        worst = std::min(worst, cut.tooth_voxels);
      }
  std::printf("tooth_2 at 1 mm: %llu seeds; the worst kept %llu of %llu hard voxels (%.1f %%)\n",
              (unsigned long long)seeds, (unsigned long long)worst, (unsigned long long)whole.tooth_voxels,
              100.0 * double(worst) / double(whole.tooth_voxels));
  EXPECT_GT(seeds, whole.tooth_voxels / 2);
  EXPECT_GE(double(worst), 0.98 * double(whole.tooth_voxels));
}

}  // namespace
}  // namespace dentsim
