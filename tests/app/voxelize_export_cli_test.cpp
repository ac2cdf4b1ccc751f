// Tests of `dentsim voxelize --labels` and `dentsim export`: a round trip through the binary, and one-line errors that leave no file behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/nifti_labels.h"
#include "test_support.h"

namespace dentsim {
namespace {

// 11 x 7 x 5 with every CT label, counted by hand: 1 caries voxel, 6 enamel (a 3x2x1 patch),
// 22 dentin (the row j=0,k=0 and the row j=6,k=4, 11 each); the flipped CT matrix, header pitch 1.
LabelImage ctLikeImage() {
  LabelImage im;
  im.dims = {11, 7, 5};
  im.pitch_mm = {1, 1, 1};
  im.scanner_from_voxel = {-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0};
  im.labels.assign(385, 0);
  im.labels[im.index(5, 3, 2)] = 1;
  for (int j = 2; j <= 3; ++j)
    for (int i = 1; i <= 3; ++i) im.labels[im.index(i, j, 1)] = 2;
  for (int i = 0; i < 11; ++i) {
    im.labels[im.index(i, 0, 0)] = 3;
    im.labels[im.index(i, 6, 4)] = 3;
  }
  return im;
}

size_t entries(const std::filesystem::path& dir) {
  size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    (void)e;
    ++n;
  }
  return n;
}


TEST(VoxelizeExportCliTest, RoundTripReproducesTheLabels) {
  test::TempDir dir;
  const LabelImage im = ctLikeImage();
  const std::string in = dir.file("tooth.nii.gz");
  ASSERT_TRUE(writeNiftiLabels(in, im).ok());
  const std::string dvol = dir.file("tooth.dvol");
  const test::CommandResult v = test::runDentsim("voxelize --labels " + in +
                                                 " --label-map 1=caries,2=enamel,3=dentin --voxel-size 0.034 -o " + dvol);
  ASSERT_EQ(v.exit_code, 0) << v.output;
  EXPECT_NE(v.output.find("level 4"), std::string::npos) << v.output;  // 11 voxels need a 16^3 grid
  EXPECT_NE(v.output.find("dentin"), std::string::npos) << v.output;
  EXPECT_NE(v.output.find("(22 voxels)"), std::string::npos) << v.output;

  const std::string out = dir.file("back.nii.gz");
  const test::CommandResult e = test::runDentsim("export " + dvol + " -o " + out);
  ASSERT_EQ(e.exit_code, 0) << e.output;
  Result<LabelImage> back = readNiftiLabels(out);
  ASSERT_TRUE(back.ok()) << back.message();
  ASSERT_EQ(back->dims, im.dims);
  EXPECT_NEAR(back->pitch_mm[0], 0.034, 1e-7);
  EXPECT_NEAR(back->scanner_from_voxel[0], -0.034, 1e-7);
  EXPECT_NEAR(back->scanner_from_voxel[5], -0.034, 1e-7);
  EXPECT_NEAR(back->scanner_from_voxel[10], 0.034, 1e-7);
  const Label renumber[4] = {0, 4, 1, 2};  // caries -> 4, enamel -> 1, dentin -> 2
  for (size_t i = 0; i < im.labels.size(); ++i) ASSERT_EQ(back->labels[i], renumber[im.labels[i]]) << i;
}

// A label file whose header pitch is a placeholder gets the warning an STL in the wrong unit gets.
TEST(VoxelizeExportCliTest, AnImplausibleVoxelSizeIsAWarning) {
  test::TempDir dir;
  LabelImage im = ctLikeImage();
  im.pitch_mm = {20, 20, 20};  // 11 voxels of 20 mm: a 220 mm "tooth"
  const std::string in = dir.file("tooth.nii.gz");
  ASSERT_TRUE(writeNiftiLabels(in, im).ok());
  const auto big = test::runDentsim("voxelize --labels " + in + " --label-map 1=caries,2=enamel,3=dentin -o " + dir.file("a.dvol"));
  ASSERT_EQ(big.exit_code, 0) << big.output;
  EXPECT_NE(big.output.find("dentsim: warning: " + in + ": the tissue spans 220 mm at 20 mm voxels, which does not look like a tooth"),
            std::string::npos) << big.output;
  EXPECT_NE(big.output.find("give the true one with --voxel-size"), std::string::npos) << big.output;
  const auto right = test::runDentsim("voxelize --labels " + in + " --label-map 1=caries,2=enamel,3=dentin --voxel-size 1.5 -o " +
                                      dir.file("b.dvol"));
  ASSERT_EQ(right.exit_code, 0) << right.output;
  EXPECT_EQ(right.output.find("does not look like a tooth"), std::string::npos) << right.output;  // 16.5 mm
}

TEST(VoxelizeExportCliTest, FillEnclosedAndLevelRun) {
  test::TempDir dir;
  LabelImage im = ctLikeImage();
  for (auto& l : im.labels) l = 3;
  im.labels[im.index(5, 3, 2)] = 0;  // one enclosed empty voxel
  const std::string in = dir.file("solid.nii");
  ASSERT_TRUE(writeNiftiLabels(in, im).ok());
  const std::string dvol = dir.file("solid.dvol");
  const test::CommandResult v = test::runDentsim("voxelize --labels " + in +
                                                 " --label-map 3=dentin --fill-enclosed pulp -o " + dvol);
  ASSERT_EQ(v.exit_code, 0) << v.output;
  EXPECT_NE(v.output.find("pulp"), std::string::npos) << v.output;
  EXPECT_NE(v.output.find("(1 voxels)"), std::string::npos) << v.output;
  const test::CommandResult l = test::runDentsim("voxelize --labels " + in +
                                                 " --label-map 3=dentin --level 5 -o " + dir.file("fit.dvol"));
  ASSERT_EQ(l.exit_code, 0) << l.output;
  EXPECT_NE(l.output.find("level 5"), std::string::npos) << l.output;
}

TEST(VoxelizeExportCliTest, BadInputsFailCleanly) {
  test::TempDir dir;
  const std::string dvol = dir.file("out.dvol");
  const std::string missing = dir.file("missing.nii.gz");
  test::expectCleanFailure(test::runDentsim("voxelize --labels " + missing + " --label-map 1=caries -o " + dvol), missing,
                     "cannot open");

  const std::string text = dir.file("notes.nii");
  { std::ofstream(text) << std::string(600, 'x') << "\n"; }
  test::expectCleanFailure(test::runDentsim("voxelize --labels " + text + " --label-map 1=caries -o " + dvol), text,
                     "not a NIfTI file");

  const std::string good = dir.file("good.nii");
  ASSERT_TRUE(writeNiftiLabels(good, ctLikeImage()).ok());
  const std::string cut = dir.file("cut.nii");
  std::filesystem::copy_file(good, cut);
  std::filesystem::resize_file(cut, std::filesystem::file_size(good) - 10);
  test::expectCleanFailure(test::runDentsim("voxelize --labels " + cut + " --label-map 1=caries,2=enamel,3=dentin -o " + dvol),
                     cut, "truncated");

  // Label 3 (22 voxels) is in the data but not in the map.
  test::expectCleanFailure(test::runDentsim("voxelize --labels " + good + " --label-map 1=caries,2=enamel -o " + dvol), good,
                     "label 3 (22 voxels) is not in the label map");
  test::expectCleanFailure(test::runDentsim("voxelize --labels " + good + " --label-map 1=caries,2=bone -o " + dvol),
                     "--label-map", "unknown tissue 'bone'");

  const std::string bad_dvol = dir.file("bad.dvol");
  { std::ofstream(bad_dvol) << "not a volume"; }
  const std::string out_nii = dir.file("out.nii.gz");
  const test::CommandResult e = test::runDentsim("export " + bad_dvol + " -o " + out_nii);
  EXPECT_NE(e.exit_code, 0);
  EXPECT_EQ(e.output.rfind("dentsim: " + bad_dvol + ": ", 0), 0u) << e.output;
  EXPECT_EQ(e.output.find('\n'), e.output.size() - 1) << e.output;

  // Nothing but the inputs remains: no .dvol, no .nii.gz, no temporary siblings.
  EXPECT_FALSE(std::filesystem::exists(dvol));
  EXPECT_FALSE(std::filesystem::exists(out_nii));
  EXPECT_EQ(entries(dir.path()), 4u);  // notes.nii, good.nii, cut.nii, bad.dvol
}

}  // namespace
}  // namespace dentsim
