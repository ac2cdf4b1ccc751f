// Grey-value volumes from NRRD (hand-written files: attached, detached, gzip, spacing only) and NIfTI (scaled and not), against the values written.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstring>
#include <fstream>

#include "io/grey_volume_file.h"
#include "io/nifti_labels.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::TempDir;

// 4 x 3 x 2 shorts 0..23, i fastest, little endian.
std::string shorts() {
  std::string data;
  for (int v = 0; v < 24; ++v) {
    data += char((v - 10) & 0xff);
    data += char((v - 10) < 0 ? 0xff : 0x00);
  }
  return data;
}

void write(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

void expectCounting(const GreyImage& g) {
  ASSERT_EQ(g.dims, (std::array<int32_t, 3>{4, 3, 2}));
  ASSERT_EQ(g.values.size(), 24u);
  for (int v = 0; v < 24; ++v) EXPECT_EQ(g.values[size_t(v)], float(v - 10)) << v;
}

TEST(GreyVolumeFile, NrrdWithSpaceDirectionsAndOrigin) {
  TempDir tmp;
  write(tmp.file("a.nrrd"),
        "NRRD0004\n# a comment\ntype: short\ndimension: 3\nspace: left-posterior-superior\nsizes: 4 3 2\n"
        "space directions: (0,0.5,0) (0.25,0,0) (0,0,-2)\nspace origin: (1,2,3)\nendian: little\nencoding: raw\n\n" +
            shorts());
  Result<GreyImage> g = readGreyVolume(tmp.file("a.nrrd"));
  ASSERT_TRUE(g) << g.message();
  expectCounting(*g);
  // Column a of the matrix is axis a's space direction; the last column the origin.
  const std::array<double, 12> want{0, 0.25, 0, 1, 0.5, 0, 0, 2, 0, 0, -2, 3};
  EXPECT_EQ(g->scanner_from_voxel, want);
  EXPECT_EQ(g->pitch_mm, (std::array<double, 3>{0.5, 0.25, 2}));
  EXPECT_EQ(g->unit, GreyUnit::Raw);
}

TEST(GreyVolumeFile, DetachedNrrdWithSpacingsInMicrons) {
  TempDir tmp;
  write(tmp.file("data.raw"), shorts());
  write(tmp.file("a.nhdr"),
        "NRRD0004\ntype: int16\ndimension: 3\nsizes: 4 3 2\nspacings: 34 34 68\nendian: little\nencoding: raw\n"
        "data file: data.raw\n\n");
  Result<GreyImage> g = readGreyVolume(tmp.file("a.nhdr"));
  ASSERT_TRUE(g) << g.message();
  expectCounting(*g);
  EXPECT_EQ(g->pitch_mm, (std::array<double, 3>{34, 34, 68}));  // spacings carry no unit: mm
  write(tmp.file("b.nrrd"),
        "NRRD0004\ntype: short\ndimension: 3\nspace: RAS\nsizes: 4 3 2\nspace units: \"um\" \"um\" \"um\"\n"
        "space directions: (34,0,0) (0,34,0) (0,0,68)\nendian: little\nencoding: raw\n\n" + shorts());
  Result<GreyImage> um = readGreyVolume(tmp.file("b.nrrd"));
  ASSERT_TRUE(um) << um.message();
  EXPECT_NEAR(um->pitch_mm[0], 0.034, 1e-12);
  EXPECT_NEAR(um->pitch_mm[2], 0.068, 1e-12);
}

TEST(GreyVolumeFile, BrokenNrrdIsOneLine) {
  TempDir tmp;
  const std::string header = "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nencoding: raw\nendian: little\n\n";
  write(tmp.file("cut.nrrd"), header + shorts().substr(0, 30));
  write(tmp.file("four.nrrd"), "NRRD0004\ntype: short\ndimension: 4\nsizes: 2 4 3 2\nencoding: raw\nendian: little\n\n" +
                                   shorts() + shorts());
  write(tmp.file("rgb.nrrd"), "NRRD0004\ntype: block\nblocksize: 3\ndimension: 3\nsizes: 4 3 2\nencoding: raw\nendian: little\n\n" +
                                  std::string(72, 'x'));
  write(tmp.file("a.vtk"), "# vtk DataFile Version 3.0\n");
  for (auto [name, words] : {std::pair{"cut.nrrd", "truncated or damaged NRRD data"}, {"four.nrrd", "4D NRRD"},
                             {"rgb.nrrd", "not a scan's grey value"}, {"a.vtk", "expected .nii, .nii.gz, .nrrd or .nhdr"},
                             {"missing.nrrd", "missing.nrrd"}}) {
    Result<GreyImage> g = readGreyVolume(tmp.file(name));
    ASSERT_FALSE(g) << name;
    EXPECT_NE(g.message().find(words), std::string::npos) << g.message();
    EXPECT_EQ(g.message().find('\n'), std::string::npos) << g.message();
  }
  Result<GreyImage> big = readNrrdGrey(tmp.file("four.nrrd"), 50);
  ASSERT_FALSE(big);
}

// Teem opens a detached header's data files even to read the header: standard input, a FIFO or a
// missing file among them is refused before Teem sees the header, so nothing blocks.
TEST(GreyVolumeFile, DetachedDataMustBeRegularFiles) {
  TempDir tmp;
  ASSERT_EQ(::mkfifo(tmp.file("pipe.raw").c_str(), 0600), 0);
  const std::string head = "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nencoding: raw\nendian: little\n";
  write(tmp.file("fifo.nhdr"), head + "data file: pipe.raw\n\n");
  write(tmp.file("stdin.nhdr"), head + "data file: -\n\n");
  write(tmp.file("list.nhdr"), head + "data file: LIST 2\nfirst.raw\npipe.raw\n");
  write(tmp.file("first.raw"), shorts().substr(0, 24));
  write(tmp.file("format.nhdr"), head + "data file: part%d.raw 1 2 1 2\n\n");
  write(tmp.file("part1.raw"), shorts().substr(0, 24));
  for (auto [name, words] : {std::pair{"fifo.nhdr", "data file " + tmp.file("pipe.raw") + ": not a regular file (a FIFO)"},
                             {"stdin.nhdr", std::string("its data file is standard input")},
                             {"list.nhdr", "data file " + tmp.file("pipe.raw") + ": not a regular file (a FIFO)"},
                             {"format.nhdr", "data file " + tmp.file("part2.raw")}}) {
    Result<GreyImage> g = readGreyVolume(tmp.file(name));
    ASSERT_FALSE(g) << name;
    EXPECT_NE(g.message().find(words), std::string::npos) << g.message();
  }
  write(tmp.file("part2.raw"), shorts().substr(24));
  Result<GreyImage> both = readGreyVolume(tmp.file("format.nhdr"));
  ASSERT_TRUE(both) << both.message();
  expectCounting(*both);
}

// NIfTI grey values take the scaling that labels refuse: stored * scl_slope + scl_inter.
TEST(GreyVolumeFile, ScaledNiftiIsRescaled) {
  TempDir tmp;
  LabelImage labels;
  labels.dims = {4, 3, 2};
  labels.pitch_mm = {0.5, 0.5, 0.5};
  labels.scanner_from_voxel = {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0};
  for (int v = 0; v < 24; ++v) labels.labels.push_back(Label(v));
  ASSERT_TRUE(writeNiftiLabels(tmp.file("a.nii"), labels));
  Result<GreyImage> plain = readGreyVolume(tmp.file("a.nii"));
  ASSERT_TRUE(plain) << plain.message();
  for (int v = 0; v < 24; ++v) EXPECT_EQ(plain->values[size_t(v)], float(v));
  // scl_slope and scl_inter are the floats at bytes 112 and 116 of a NIfTI-1 header.
  std::vector<uint8_t> bytes = test::readBytes(tmp.file("a.nii"));
  const float slope = 2.5f, inter = -1024.0f;
  std::memcpy(&bytes[112], &slope, 4);
  std::memcpy(&bytes[116], &inter, 4);
  std::ofstream(tmp.file("s.nii"), std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  Result<GreyImage> scaled = readGreyVolume(tmp.file("s.nii"));
  ASSERT_TRUE(scaled) << scaled.message();
  for (int v = 0; v < 24; ++v) EXPECT_EQ(scaled->values[size_t(v)], float(v * 2.5 - 1024)) << v;
  EXPECT_EQ(scaled->pitch_mm, labels.pitch_mm);
  EXPECT_FALSE(readNiftiLabels(tmp.file("s.nii")));  // labels still refuse a scale
}

}  // namespace
}  // namespace dentsim
