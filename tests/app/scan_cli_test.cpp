// `dentsim make-scan` and `voxelize --dicom/--ct` as a user runs them: a small phantom tooth made, read and segmented, and broken series each refused in one line that names the problem.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "dicom/forge.h"
#include "dicom/nested_sequences.h"
#include "io/dicom_series.h"
#include "io/nifti_labels.h"
#include "volume/scan_model.h"
#include "volume/tissue_table.h"
#include "test_support.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;
using test::runDentsim;

// A small tooth at 0.1 mm: a dentin ball of radius 2 mm with a pulp hollow of 0.7 mm, under an enamel
// cap 0.5 mm thick (the top half of a shell around it), in a 60 x 60 x 60 grid. Labels as tooth_2's:
// 2 enamel, 3 dentin. Its 48 mm^3 of hard tissue is under any human tooth's, so the voxelizations that
// keep it give --any-size (volume/tooth_sanity.h).
LabelImage smallTooth() {
  LabelImage im;
  im.dims = {60, 60, 60};
  im.pitch_mm = {0.1, 0.1, 0.1};
  im.scanner_from_voxel = {0.1, 0, 0, 10, 0, 0.1, 0, 20, 0, 0, 0.1, 30};
  im.labels.assign(size_t(im.voxelCount()), 0);
  for (int k = 0; k < 60; ++k)
    for (int j = 0; j < 60; ++j)
      for (int i = 0; i < 60; ++i) {
        const double r = 0.1 * std::sqrt(double((i - 30) * (i - 30) + (j - 30) * (j - 30) + (k - 28) * (k - 28)));
        Label l = 0;
        if (r < 2.0 && r >= 0.7) l = 3;
        else if (r >= 2.0 && r < 2.5 && k >= 28) l = 2;
        im.labels[im.index(i, j, k)] = l;
      }
  return im;
}

class ScanCli : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(writeNiftiLabels(dir_.file("tooth.nii.gz"), smallTooth()));
    const auto made = runDentsim("make-scan --labels " + dir_.file("tooth.nii.gz") +
                                 " --label-map 2=enamel,3=dentin --blur-mm 0.1 --noise-hu 80 -o " + series());
    ASSERT_EQ(made.exit_code, 0) << made.output;
    made_output_ = made.output;
  }
  std::string series() const { return dir_.file("series"); }
  std::string out() const { return dir_.file("tooth.dvol"); }
  // A refusal: exit code 1, one line on stderr starting "dentsim: " that holds `words`, and no
  // output file. stdout may have said the plan before the error.
  void expectRefused(const std::string& args, const std::string& words) {
    const auto r = test::runCommand("{ " + std::string(DENTSIM_BINARY) + " " + args + " >/dev/null; }");
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("dentsim: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(out())) << args;
  }
  test::TempDir dir_;
  std::string made_output_;  // what make-scan printed in SetUp
};

// make-scan says the value it painted for empty and for every tissue of the table, in table order:
// a tissue added to the table shows up without another list to edit.
TEST_F(ScanCli, MakeScanNamesTheValueOfEveryTissueOfTheTable) {
  const ScanModel model;
  std::string expected = "  values (HU): empty " + std::to_string(std::lround(model.value[0]));
  for (const TissueRow& row : kTissueTable)
    expected += ", " + std::string(row.name) + " " + std::to_string(std::lround(model.value[size_t(row.material)]));
  expected += "; blur 0.1 mm";
  EXPECT_NE(made_output_.find(expected), std::string::npos) << expected << "\n" << made_output_;
}

TEST_F(ScanCli, APhantomBecomesAToothWithItsTissues) {
  const auto r = runDentsim("voxelize --dicom " + series() + " --any-size --level 7 -o " + out());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("60 DICOM files"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("enamel"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("pulp"), std::string::npos) << r.output;
  const auto info = runDentsim("info --json " + out());
  ASSERT_EQ(info.exit_code, 0) << info.output;
  // Volumes against the phantom's labels, counted here (0.001 mm^3 a voxel); the pulp is the hollow,
  // 4/3 pi 0.7^3 = 1.44 mm^3.
  const LabelImage truth = smallTooth();
  const double enamel_mm3 = 0.001 * double(std::count(truth.labels.begin(), truth.labels.end(), Label(2)));
  const double dentin_mm3 = 0.001 * double(std::count(truth.labels.begin(), truth.labels.end(), Label(3)));
  const auto j = nlohmann::json::parse(info.output);
  EXPECT_NEAR(j["tissues"]["dentin"]["volume_mm3"].get<double>(), dentin_mm3, 0.05 * dentin_mm3);
  // The cap is 5 source voxels thick, so a tenth of a voxel on either face is 4 % of it.
  EXPECT_NEAR(j["tissues"]["enamel"]["volume_mm3"].get<double>(), enamel_mm3, 0.08 * enamel_mm3);
  EXPECT_NEAR(j["tissues"]["pulp"]["volume_mm3"].get<double>(), 1.44, 0.25 * 1.44);
  ASSERT_TRUE(j.contains("source_note")) << info.output;
  const auto text = runDentsim("info " + out());
  EXPECT_NE(text.output.find("made from"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("thresholds (automatic"), std::string::npos) << text.output;
}

TEST_F(ScanCli, GivenThresholdsAndARoiAreUsedAndReported) {
  // The tooth's box in mm: centre (13, 23, 32.8), radius 2.5 mm.
  const auto r = runDentsim("voxelize --dicom " + series() +
                            " --roi 10,20,29.5:16,26,35.9 --dentin-above 800 --enamel-above 2300 --any-size --level 7 -o " + out());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("thresholds (given): dentin from 800 HU, enamel from 2300 HU"), std::string::npos) << r.output;
  const auto preset = runDentsim("voxelize --dicom " + series() + " --scanner ct-hu --any-size --level 7 -o " + dir_.file("p.dvol"));
  ASSERT_EQ(preset.exit_code, 0) << preset.output;
  EXPECT_NE(preset.output.find("preset ct-hu"), std::string::npos) << preset.output;
}

TEST_F(ScanCli, BrokenSeriesAreOneLineEach) {
  // A missing slice.
  fs::copy(series(), dir_.file("gap"));
  fs::remove(dir_.file("gap/slice-0031.dcm"));
  expectRefused("voxelize --dicom " + dir_.file("gap") + " -o " + out(),
                "missing slice: a gap of 0.2 mm between slice-0030.dcm and slice-0032.dcm");
  // A mixed series: a second scan in a folder below the first.
  fs::copy(series(), dir_.file("mixed"));
  const auto second = runDentsim("make-scan --labels " + dir_.file("tooth.nii.gz") +
                                 " --label-map 2=enamel,3=dentin -o " + dir_.file("mixed/again"));
  ASSERT_EQ(second.exit_code, 0) << second.output;
  expectRefused("voxelize --dicom " + dir_.file("mixed") + " -o " + out(), "mixed series: 2 series in one folder");
  // A truncated file.
  fs::copy(series(), dir_.file("cut"));
  fs::resize_file(dir_.file("cut/slice-0017.dcm"), fs::file_size(dir_.file("cut/slice-0017.dcm")) / 2);
  expectRefused("voxelize --dicom " + dir_.file("cut") + " -o " + out(), "slice-0017.dcm: truncated");
  // No DICOM at all, and no folder.
  fs::create_directories(dir_.file("empty"));
  expectRefused("voxelize --dicom " + dir_.file("empty") + " -o " + out(), "holds no files");
  expectRefused("voxelize --dicom " + dir_.file("nowhere") + " -o " + out(), "no such file or folder");
}

// Made-up data (issue 40): Rows forged to 65,535 in every slice, whose pixels the files never held,
// and slices 1e15 mm apart, are each one line, exit 1 and no output.
TEST_F(ScanCli, MadeUpPixelsAndGeometryAreRefused) {
  fs::copy(series(), dir_.file("forged"));
  for (const auto& e : fs::directory_iterator(dir_.file("forged")))
    ASSERT_TRUE(test::forgeUs(e.path().string(), 0x0028, 0x0010, 65535)) << e.path();
  expectRefused("voxelize --dicom " + dir_.file("forged") + " -o " + out(),
                "slice-0001.dcm: Rows x Columns x frames x samples (65535 x 60 x 1 x 1) need 7864200 bytes of pixels "
                "but its Pixel Data holds 7200");
  GreyImage far;
  far.dims = {4, 4, 3};
  far.scanner_from_voxel = {0.1, 0, 0, 0, 0, 0.1, 0, 0, 0, 0, 1e15, 0};
  far.pitch_mm = {0.1, 0.1, 1e15};
  far.values.assign(size_t(far.voxelCount()), 1000.0f);
  ASSERT_TRUE(writeDicomSeries(dir_.file("far"), far));
  expectRefused("voxelize --dicom " + dir_.file("far") + " -o " + out(),
                "slice-0002.dcm: Image Position (Patient) '0\\0\\1e+15' lies beyond 1e+04 mm");
}

TEST_F(ScanCli, OptionsThatCannotApplyAreRefused) {
  expectRefused("voxelize --dicom " + series() + " --label-map 1=enamel -o " + out(), "--label-map: applies to --labels");
  expectRefused("voxelize --labels x.nii.gz --label-map 1=enamel --seed 1,2,3 -o " + out(), "--seed: segments a scan");
  expectRefused("voxelize --dicom " + series() + " --caries-below 900 -o " + out(), "give --find-caries");
  expectRefused("voxelize --dicom " + series() + " --scanner nope -o " + out(), "unknown scanner preset \"nope\"");
  expectRefused("voxelize --dicom " + series() + " --roi 1,2 -o " + out(), "--roi: expected x0,y0,z0:x1,y1,z1");
  expectRefused("voxelize --dicom " + series() + " --roi 0,0,0:5,5,5 -o " + out(), "outside the image");
  expectRefused("voxelize --dicom " + series() + " --seed 13,23,32.8 -o " + out(), "is not in hard tissue");  // the pulp
  expectRefused("voxelize --dicom " + series() + " --dentin-above 2500 --enamel-above 2000 -o " + out(), "2500");
  expectRefused("voxelize --ct " + dir_.file("tooth.vtk") + " -o " + out(), "tooth.vtk");
  expectRefused("voxelize --dicom " + series() + " --ct " + dir_.file("a.nrrd") + " -o " + out(), "give one source");
}

// Hostile NRRD headers through the binary: a data-file format other than one %d, and a FIFO behind
// 10,000 comments or at line 10,401 of a LIST, each one line and exit 1 (timeout only guards a
// broken build from hanging the suite).
TEST(ScanCliHostile, NrrdHeadersAreOneLineEach) {
  test::TempDir dir;
  const std::string head = "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nencoding: raw\nendian: little\n";
  ASSERT_EQ(::mkfifo(dir.file("pipe.raw").c_str(), 0600), 0);
  std::vector<std::pair<std::string, std::string>> cases;  // header text, words of the refusal
  for (const char* format : {"x%n%n%n%n.raw 1 1 1", "x%s.raw 1 1 1", "x%x.raw 1 1 1", "x%%.raw 1 1 1", "x%10000d.raw 1 1 1"})
    cases.push_back({head + "data file: " + format + "\n\n", "line 7: data file '"});
  std::string comments;
  for (int n = 0; n < 10000; ++n) comments += "# comment\n";
  cases.push_back({head + comments + "data file: pipe.raw\n\n", "pipe.raw: not a regular file (a FIFO)"});
  std::string list;
  for (int n = 1; n <= 10500; ++n) {
    list += (n == 10401 ? std::string("pipe.raw") : "s" + std::to_string(n) + ".raw") + "\n";
    if (n != 10401) std::ofstream(dir.file("s" + std::to_string(n) + ".raw"));
  }
  cases.push_back({head + "data file: LIST\n" + list, "pipe.raw: not a regular file (a FIFO)"});
  for (size_t c = 0; c < cases.size(); ++c) {
    const std::string header = dir.file("case" + std::to_string(c) + ".nhdr");
    std::ofstream(header, std::ios::binary) << cases[c].first;
    const auto r = test::runCommand("timeout 60 " DENTSIM_BINARY " voxelize --ct " + header + " -o " + dir.file("out.dvol"));
    EXPECT_EQ(r.exit_code, 1) << c << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("dentsim: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(cases[c].second), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(dir.file("out.dvol")));
  }
}

// A 3.6 kB slice with sequences nested 100 deep (GDCM's length of it would never finish): one line
// naming the file, exit 1 (timeout only guards a broken build from hanging the suite).
TEST(ScanCliHostile, DeeplyNestedDicomIsOneLine) {
  test::TempDir dir;
  fs::create_directories(dir.file("deep"));
  std::ofstream(dir.file("deep/nested.dcm"), std::ios::binary) << test::nestedSequenceSlice(100);
  const auto r = test::runCommand("timeout 60 " DENTSIM_BINARY " voxelize --dicom " + dir.file("deep") + " -o " +
                                  dir.file("out.dvol"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind("dentsim: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("nested.dcm: sequences nested more than 8 deep"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(dir.file("out.dvol")));
}

TEST_F(ScanCli, TheScanReadIsPlannedAndRefusedBeyondTheMemoryBudget) {
  // 60^3 voxels read slice by slice: 64 MiB for the program and 6 bytes a voxel (floats, the
  // segmentation), about 68 MB. The plan says so before the read; a 40 MiB budget refuses it, in
  // one line naming the stage, the estimate, the budget and the flag, and writes nothing.
  const auto ok = runDentsim("voxelize --dicom " + series() + " --any-size --level 6 -o " + out());
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("plan: reading the scan (216 000 voxels): about 0.068 GB of memory"), std::string::npos)
      << ok.output;
  EXPECT_NE(ok.output.find("plan: level 6 (64^3 voxels)"), std::string::npos) << ok.output;
  fs::remove(out());
  expectRefused("--max-memory-mb 40 voxelize --dicom " + series() + " --level 6 -o " + out(),
                "voxelize: reading the scan (216 000 voxels): about 0.068 GB of memory and under a second, beyond the "
                "memory budget of 0.042 GB (set with --max-memory-mb)");
}

}  // namespace
}  // namespace dentsim
