// A tooth scanned as a clinical head CT sees it (1 mm voxels, noise, a neighbour, bone round the roots) is refused or flagged by `voxelize`, never written as a tooth of bone and teeth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "io/nifti_labels.h"
#include "test_support.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;
using test::runDentsim;

// A molar-sized tooth at 0.25 mm, crown up along k: a tapering root of dentin (radius 2 mm at the apex
// to 4 mm at the cervix, k 4..49) with a canal of 0.6 mm, under a crown of radius 5 mm (k 50..79)
// whose dentin core (radius 3.8 mm, to k 75) holds a pulp chamber of 1.5 mm, the rest enamel. About
// 330 mm^3 of root and 590 of crown: a permanent molar's 600..1000 mm^3 of hard tissue, 19 mm long.
// Labels as tooth_2's: 2 enamel, 3 dentin. Voxel (i, j, k) sits at (10, 20, 30) + 0.25 (i, j, k) mm.
LabelImage molarSizedTooth() {
  LabelImage im;
  im.dims = {48, 48, 88};
  im.pitch_mm = {0.25, 0.25, 0.25};
  im.scanner_from_voxel = {0.25, 0, 0, 10, 0, 0.25, 0, 20, 0, 0, 0.25, 30};
  im.labels.assign(size_t(im.voxelCount()), 0);
  for (int k = 4; k < 80; ++k)
    for (int j = 0; j < 48; ++j)
      for (int i = 0; i < 48; ++i) {
        const double r = 0.25 * std::hypot(i - 23.5, j - 23.5);
        Label l = 0;
        if (k < 50) {
          const double root = 2.0 + 2.0 * double(k - 4) / 45.0;
          if (r < root && r >= 0.6) l = 3;
        } else if (r < 5.0) {
          const bool core = r < 3.8 && k < 76;
          if (!core) l = 2;
          else if (!(r < 1.5 && k < 62)) l = 3;
        }
        im.labels[im.index(i, j, k)] = l;
      }
  return im;
}

class ClinicalScanCli : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(writeNiftiLabels(dir_.file("tooth.nii.gz"), molarSizedTooth())); }
  // make-scan of the tooth with `extra` flags into `name`; its output, exit 0 asserted.
  std::string makeScan(const std::string& extra, const std::string& name) {
    const auto made = runDentsim("make-scan --labels " + dir_.file("tooth.nii.gz") + " --label-map 2=enamel,3=dentin " +
                                 extra + " -o " + dir_.file(name));
    EXPECT_EQ(made.exit_code, 0) << made.output;
    return made.output;
  }
  std::string out() const { return dir_.file("tooth.dvol"); }
  test::TempDir dir_;
};

// The head CT: 1 mm voxels, 60 HU of noise, the neighbour touching, bone round the roots.
// With or without a seed, the "tooth" is refused in one line that names what was found and what to
// try, and the tooth already at the output path is left as it was.
TEST_F(ClinicalScanCli, AHeadCtLikePhantomIsRefusedAndTheOutputLeftAlone) {
  const std::string made = makeScan("--scan-voxel-mm 1.0 --noise-hu 60 --bone-slab 10 --neighbour-copy", "head");
  EXPECT_NE(made.find("a copy of the tooth beside it"), std::string::npos) << made;
  EXPECT_NE(made.find("bone of 1000 HU around the lowest 10 mm of the tooth"), std::string::npos) << made;
  const std::string before = "a tooth made earlier";
  std::ofstream(out()) << before;
  for (const std::string seed : {"", " --seed 16,26,46.25"}) {
    SCOPED_TRACE(seed);
    const auto r = test::runCommand("{ " + std::string(DENTSIM_BINARY) + " voxelize --dicom " + dir_.file("head") + seed +
                                    " -o " + out() + " >/dev/null; }");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output.rfind("dentsim: ", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    const bool size = r.output.find("is no human tooth") != std::string::npos;
    const bool threshold = r.output.find("below soft tissue") != std::string::npos;
    EXPECT_TRUE(size || threshold) << r.output;
    EXPECT_NE(r.output.find("--roi"), std::string::npos) << r.output;
    std::ifstream in(out());
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), before);
  }
}

// The tooth alone at 1 mm voxels: its partial-volume rim fills the histogram from air to dentin, and
// Otsu's cut falls in it below 0 HU, which is refused. With a scanner's thresholds it is a tooth, and
// the warning says its enamel is partial volume.
TEST_F(ClinicalScanCli, ClinicalVoxelsAreAWarningAboutTheEnamel) {
  makeScan("--scan-voxel-mm 1.0 --noise-hu 60", "alone");
  const auto automatic = runDentsim("voxelize --dicom " + dir_.file("alone") + " --level 7 -o " + out());
  EXPECT_EQ(automatic.exit_code, 1) << automatic.output;
  EXPECT_NE(automatic.output.find("HU is below soft tissue"), std::string::npos) << automatic.output;
  EXPECT_NE(automatic.output.find("give --dentin-above"), std::string::npos) << automatic.output;
  const auto r = runDentsim("voxelize --dicom " + dir_.file("alone") + " --scanner ct-hu --level 7 -o " + out());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("dentsim: warning: " + dir_.file("alone") +
                          ": voxels of 1 x 1 x 1 mm are coarser than the 0.3 mm enamel can be thin"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("CBCT or micro-CT"), std::string::npos) << r.output;
}

// At the labels' own 0.25 mm the same tooth passes every check without a word.
TEST_F(ClinicalScanCli, TheToothAtItsOwnVoxelsPassesWithoutAWarning) {
  makeScan("--noise-hu 60", "fine");
  const auto r = runDentsim("voxelize --dicom " + dir_.file("fine") + " --level 7 -o " + out());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
}

// A tooth of no human size is kept when --any-size says it truly is: a 2.5 times enlarged model.
TEST_F(ClinicalScanCli, AnySizeKeepsAnEnlargedModel) {
  makeScan("--voxel-size 0.625 --noise-hu 60", "big");
  const auto refused = runDentsim("voxelize --dicom " + dir_.file("big") + " --level 7 -o " + out());
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("is no human tooth"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("--any-size"), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(out()));
  const auto kept = runDentsim("voxelize --dicom " + dir_.file("big") + " --any-size --level 7 -o " + out());
  EXPECT_EQ(kept.exit_code, 0) << kept.output;
  EXPECT_TRUE(fs::exists(out()));
}

}  // namespace
}  // namespace dentsim
