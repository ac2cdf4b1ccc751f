// A scanner's series of a real tooth with a known answer: tooth_2's labels as a phantom CT of 400 DICOM slices, read, segmented and voxelized back, and opened in the simulator.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "io/dicom_series.h"
#include "io/nifti_labels.h"
#include "test_support.h"
#include "volume/ct_segment.h"
#include "volume/label_import.h"
#include "volume/scan_model.h"
#include "volume/tissue_table.h"
#include "volume/volume_compare.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;
constexpr double kPitchMm = 0.034;  // tooth_2's real pitch; its header says 1.0 (data README)

// Under the sanitizers the same steps run on the tooth at half resolution (300 x 300 x 200 at 0.068 mm):
// their job there is memory errors, and a full-size phantom costs minutes at -O1. The release build
// holds the full 400 slices to the figures.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kStride = 2;
#else
constexpr int kStride = 1;
#endif

std::string tooth2Path() {
  const fs::path data = test::dataDir();
  if (data.empty() || !fs::exists(data / "ct" / "tooth_2.nii.gz")) return {};
  return (data / "ct" / "tooth_2.nii.gz").string();
}

// Every stride-th voxel along each axis (nearest neighbour), the pitch grown to match.
LabelImage everyNth(LabelImage in, int stride) {
  if (stride == 1) {
    for (size_t a = 0; a < 3; ++a) {
      for (size_t r = 0; r < 3; ++r) in.scanner_from_voxel[4 * r + a] *= kPitchMm / in.pitch_mm[a];
      in.pitch_mm[a] = kPitchMm;
    }
    return in;
  }
  LabelImage out;
  for (size_t a = 0; a < 3; ++a) out.dims[a] = in.dims[a] / stride;
  out.pitch_mm = {kPitchMm * stride, kPitchMm * stride, kPitchMm * stride};
  out.scanner_from_voxel = {kPitchMm * stride, 0, 0, 0, 0, kPitchMm * stride, 0, 0, 0, 0, kPitchMm * stride, 0};
  out.labels.resize(size_t(out.voxelCount()));
  for (int64_t k = 0; k < out.dims[2]; ++k)
    for (int64_t j = 0; j < out.dims[1]; ++j)
      for (int64_t i = 0; i < out.dims[0]; ++i)
        out.labels[out.index(i, j, k)] = in.labels[in.index(i * stride, j * stride, k * stride)];
  return out;
}

double dice(uint64_t both, uint64_t a, uint64_t b) { return a + b == 0 ? 1.0 : 2.0 * double(both) / double(a + b); }

// The model (volume/scan_model.h): air -1000, enamel 2900, dentin 1700, caries 700 HU; Gaussian blur of
// 0.04 mm; noise of 100 HU. Without --find-caries the lesion is hard tissue of dentin's class, so the
// truth for "dentin" is tooth_2's dentin and caries together.
TEST(CtScanTooth2, APhantomSeriesSegmentsBackToItsLabels) {
  const std::string path = tooth2Path();
  if (path.empty()) GTEST_SKIP() << "real CT data (tooth_2.nii.gz) not found in " << test::dataDir();
  Result<LabelImage> read = readNiftiLabels(path);
  ASSERT_TRUE(read) << read.message();
  const LabelImage truth = everyNth(std::move(read).value(), kStride);
  const std::map<int32_t, Material> tissues{{1, Material::Caries}, {2, Material::Enamel}, {3, Material::Dentin}};

  test::TempDir tmp;
  const std::string series = tmp.file("tooth_2");
  {
    Result<GreyImage> phantom = simulateScan(truth, tissues, ScanModel{});
    ASSERT_TRUE(phantom) << phantom.message();
    DicomWriteOptions w;
    w.scramble_names = true;
    w.signed_pixels = false;  // stored HU + 1024 with an intercept, as many scanners write
    w.rescale_intercept = -1024;
    auto files = writeDicomSeries(series, *phantom, w);
    ASSERT_TRUE(files) << files.message();
    EXPECT_EQ(files->size(), size_t(truth.dims[2]));
  }
  DicomSeriesInfo info;
  Result<GreyImage> scan = readDicomSeries(series, {}, nullInterrupter(), &info);
  ASSERT_TRUE(scan) << scan.message();
  ASSERT_EQ(scan->dims, truth.dims);
  for (size_t q = 0; q < 12; ++q) EXPECT_NEAR(scan->scanner_from_voxel[q], truth.scanner_from_voxel[q], 1e-6) << q;
  EXPECT_EQ(scan->unit, GreyUnit::Hounsfield);
  EXPECT_EQ(info.files, truth.dims[2]);

  ToothSegmentOptions seg;
  seg.where = series;
  ToothSegmentReport report;
  Result<LabelImage> found = segmentTooth(*scan, seg, nullInterrupter(), &report);
  ASSERT_TRUE(found) << found.message();
  // With --find-caries: the lesion (700 HU against dentin's 1700) comes out as caries, by an
  // automatic cut 3 sigma below the dentin peak.
  ToothSegmentOptions with_caries = seg;
  with_caries.caries = true;
  ToothSegmentReport caries_report;
  Result<LabelImage> carious = segmentTooth(*scan, with_caries, nullInterrupter(), &caries_report);
  ASSERT_TRUE(carious) << carious.message();
  scan = Error{};  // the grey values are not needed again
  uint64_t lesion[3] = {};  // both, truth, found
  for (int64_t k = 0; k < carious->dims[2]; ++k)
    for (int64_t j = 0; j < carious->dims[1]; ++j)
      for (int64_t i = 0; i < carious->dims[0]; ++i) {
        const bool f = carious->labels[carious->index(i, j, k)] == 4;
        const bool t = truth.labels[truth.index(i + caries_report.out_lo[0], j + caries_report.out_lo[1],
                                                k + caries_report.out_lo[2])] == 1;
        lesion[0] += t && f, lesion[1] += t, lesion[2] += f;
      }
  uint64_t truth_lesion = 0;
  for (Label l : truth.labels) truth_lesion += l == 1;
  ASSERT_EQ(lesion[1], truth_lesion);  // the output box holds the whole lesion
  const double caries_dice = dice(lesion[0], lesion[1], lesion[2]);
  std::printf("scan voxels: Dice caries %.4f (%llu voxels found, %llu in the labels; caries below %.1f HU)\n",
              caries_dice, static_cast<unsigned long long>(lesion[2]), static_cast<unsigned long long>(lesion[1]),
              *caries_report.caries_below);
  EXPECT_GE(caries_dice, 0.6);
  // The automatic thresholds fall between the classes' values.
  EXPECT_GT(report.dentin_above, -1000.0);
  EXPECT_LT(report.dentin_above, 1700.0);
  EXPECT_GT(report.enamel_above, 1700.0);
  EXPECT_LT(report.enamel_above, 2900.0);

  // Dice at the scan's own voxels: the output is the image's box out_lo .. out_hi.
  uint64_t enamel[3] = {}, dentin[3] = {};  // both, truth, found
  for (int64_t k = 0; k < truth.dims[2]; ++k)
    for (int64_t j = 0; j < truth.dims[1]; ++j)
      for (int64_t i = 0; i < truth.dims[0]; ++i) {
        const Label t = truth.labels[truth.index(i, j, k)];
        Label f = 0;
        const int64_t fi = i - report.out_lo[0], fj = j - report.out_lo[1], fk = k - report.out_lo[2];
        if (fi >= 0 && fj >= 0 && fk >= 0 && fi < found->dims[0] && fj < found->dims[1] && fk < found->dims[2])
          f = found->labels[found->index(fi, fj, fk)];
        const bool te = t == 2, fe = f == 1, td = t == 3 || t == 1, fd = f == 2;
        enamel[0] += te && fe, enamel[1] += te, enamel[2] += fe;
        dentin[0] += td && fd, dentin[1] += td, dentin[2] += fd;
      }
  const double enamel_dice = dice(enamel[0], enamel[1], enamel[2]), dentin_dice = dice(dentin[0], dentin[1], dentin[2]);
  std::printf("scan voxels: Dice enamel %.4f, dentin %.4f (thresholds %.1f, %.1f HU)\n", enamel_dice, dentin_dice,
              report.dentin_above, report.enamel_above);
  EXPECT_GE(enamel_dice, 0.95);
  EXPECT_GE(dentin_dice, 0.95);

  // Level 9, as `voxelize` makes it: both imports fit the truth's tissue box, so they share a grid.
  std::array<std::array<int64_t, 2>, 3> box{{{truth.dims[0], -1}, {truth.dims[1], -1}, {truth.dims[2], -1}}};
  for (int64_t k = 0; k < truth.dims[2]; ++k)
    for (int64_t j = 0; j < truth.dims[1]; ++j)
      for (int64_t i = 0; i < truth.dims[0]; ++i)
        if (truth.labels[truth.index(i, j, k)] != 0) {
          const int64_t at[3] = {i, j, k};
          for (size_t a = 0; a < 3; ++a) box[a] = {std::min(box[a][0], at[a]), std::max(box[a][1], at[a])};
        }
  LabelImportOptions import;
  import.level = 9;
  import.fill_enclosed = Material::Pulp;
  import.seal_mm = 0.2;
  import.fit_box = box;
  import.map = parseLabelMap("1=dentin,2=enamel,3=dentin").value();
  Result<ToothVolume> from_labels = importLabels(truth, import);
  ASSERT_TRUE(from_labels) << from_labels.message();
  for (size_t a = 0; a < 3; ++a)
    for (int64_t& end : (*import.fit_box)[a]) end -= report.out_lo[a];
  import.map = parseLabelMap("1=enamel,2=dentin,4=caries").value();
  Result<ToothVolume> from_scan = importLabels(*found, import);
  ASSERT_TRUE(from_scan) << from_scan.message();
  ASSERT_EQ(from_scan->frame.voxel_mm, from_labels->frame.voxel_mm);
  for (size_t q = 0; q < 12; ++q)
    EXPECT_NEAR(from_scan->frame.scanner_from_grid[q], from_labels->frame.scanner_from_grid[q], 1e-9) << q;
  for (auto [tissue, least] : {std::pair{Material::Enamel, 0.95}, {Material::Dentin, 0.95}, {Material::Pulp, 0.85}}) {
    Result<TissueOverlap> o = compareTissues(from_labels->voxels, from_scan->voxels, tissue);
    ASSERT_TRUE(o) << o.message();
    const double d = dice(o->intersection, o->a_voxels, o->b_voxels);
    std::printf("level 9: Dice %s %.4f (%llu voxels from the labels, %llu from the scan)\n", materialName(tissue).c_str(), d,
                static_cast<unsigned long long>(o->a_voxels), static_cast<unsigned long long>(o->b_voxels));
    EXPECT_GE(d, least) << materialName(tissue);
  }
}

// The same as a teacher types it: make-scan, voxelize --dicom, info, and the simulator opening the tooth.
TEST(CtScanTooth2, TheCommandsMakeAToothThatOpensInTheSimulator) {
  const std::string path = tooth2Path();
  if (path.empty()) GTEST_SKIP() << "real CT data (tooth_2.nii.gz) not found in " << test::dataDir();
  test::TempDir tmp;
  std::string labels = path;
  if (kStride != 1) {  // the sanitizers' half-resolution copy
    Result<LabelImage> read = readNiftiLabels(path);
    ASSERT_TRUE(read);
    labels = tmp.file("tooth_2_half.nii.gz");
    LabelImage half = everyNth(std::move(read).value(), kStride);
    ASSERT_TRUE(writeNiftiLabels(labels, half));
  }
  const std::string series = tmp.file("series"), tooth = tmp.file("tooth_2.dvol"), out = tmp.file("run");
  const auto made = test::runDentsim("make-scan --labels " + labels + " --label-map 1=caries,2=enamel,3=dentin" +
                                     (kStride == 1 ? " --voxel-size 0.034" : "") + " --scramble-names -o " + series);
  ASSERT_EQ(made.exit_code, 0) << made.output;
  EXPECT_NE(made.output.find(kStride == 1 ? "400 DICOM slices of 600 x 600" : "200 DICOM slices of 300 x 300"),
            std::string::npos)
      << made.output;
  const auto voxelized = test::runDentsim("voxelize --dicom " + series + " -o " + tooth);
  ASSERT_EQ(voxelized.exit_code, 0) << voxelized.output;
  EXPECT_NE(voxelized.output.find("grid 512^3 (level 9)"), std::string::npos) << voxelized.output;
  EXPECT_NE(voxelized.output.find("thresholds (automatic"), std::string::npos) << voxelized.output;
  const auto info = test::runDentsim("info " + tooth);
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("made from"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("DICOM files), " + std::string(kStride == 1 ? "600 x 600 x 400" : "300 x 300 x 200")),
            std::string::npos)
      << info.output;
  const test::NoLeakCheckForGpuChild gpu_child;  // the run drives lavapipe (test_support.h says why)
  const auto run = test::runDentsim("run --headless --tooth " + tooth +
                                    " --no-sound --shot 0.05 --exit-after 0.1 --width 640 --height 480 --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_TRUE(fs::exists(out + "/shot-1.png")) << run.output;
  EXPECT_GT(fs::file_size(out + "/shot-1.png"), 10000u);  // a picture of a tooth, not a blank frame
}

}  // namespace
}  // namespace dentsim
