// DICOM series through GDCM: written and read back, checked against pydicom (an independent reader), real sample files, and broken series.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "dicom/forge.h"
#include "dicom/nested_sequences.h"
#include "io/dicom_series.h"
#include "test_support.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// 6 x 5 x 7 voxels whose value says where they are: 100 i + 10 j + k - 500 (HU-like, signed).
GreyImage coded(std::array<double, 12> scanner = {0.3, 0, 0, -10, 0, 0.4, 0, 20, 0, 0, 0.5, 30}) {
  GreyImage g;
  g.dims = {6, 5, 7};
  g.scanner_from_voxel = scanner;
  for (int a = 0; a < 3; ++a)
    g.pitch_mm[size_t(a)] = std::hypot(scanner[size_t(a)], scanner[size_t(4 + a)], scanner[size_t(8 + a)]);
  g.values.resize(size_t(g.voxelCount()));
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 6; ++i) g.values[g.index(i, j, k)] = float(100 * i + 10 * j + k - 500);
  return g;
}

std::vector<std::string> writeSeries(const std::string& dir, const GreyImage& g, DicomWriteOptions o = {}) {
  auto files = writeDicomSeries(dir, g, o);
  EXPECT_TRUE(files) << files.message();
  return files ? *files : std::vector<std::string>{};
}

void expectSameVolume(const GreyImage& got, const GreyImage& want) {
  ASSERT_EQ(got.dims, want.dims);
  for (size_t q = 0; q < 12; ++q) EXPECT_NEAR(got.scanner_from_voxel[q], want.scanner_from_voxel[q], 1e-5) << q;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(got.pitch_mm[size_t(a)], want.pitch_mm[size_t(a)], 1e-6);
  ASSERT_EQ(got.values.size(), want.values.size());
  for (size_t n = 0; n < got.values.size(); ++n) ASSERT_EQ(got.values[n], want.values[n]) << "voxel " << n;
}

TEST(DicomSeries, ScrambledFileNamesReadInPositionOrder) {
  TempDir tmp;
  const GreyImage g = coded();
  DicomWriteOptions o;
  o.scramble_names = true;
  writeSeries(tmp.file("ct"), g, o);
  DicomSeriesInfo info;
  Result<GreyImage> back = readDicomSeries(tmp.file("ct"), {}, nullInterrupter(), &info);
  ASSERT_TRUE(back) << back.message();
  expectSameVolume(*back, g);
  EXPECT_EQ(back->unit, GreyUnit::Hounsfield);
  EXPECT_EQ(back->modality, "CT");
  EXPECT_EQ(info.files, 7);
  EXPECT_NEAR(info.slice_spacing_mm, 0.5, 1e-9);
  EXPECT_TRUE(info.signed_pixels);
}

// Slices may run the other way (k towards -z) and the rows may lie along y: the volume follows the
// positions, so its k axis is the normal row x column, and voxel (i,j,0) is the lowest slice on it.
TEST(DicomSeries, OrientationAndDescendingPositionsAreHonoured) {
  TempDir tmp;
  // i along +y, j along -x: the normal (+y) x (-x) is +z; k is written along -z, so files run downwards.
  const GreyImage g = coded({0, -0.4, 0, 5, 0.3, 0, 0, 6, 0, 0, -0.5, 7});
  writeSeries(tmp.file("ct"), g);
  Result<GreyImage> back = readDicomSeries(tmp.file("ct"));
  ASSERT_TRUE(back) << back.message();
  ASSERT_EQ(back->dims, g.dims);
  // Read k = 0 is the written k = 6 (the lowest along +z), and the k column now points up.
  EXPECT_NEAR(back->scanner_from_voxel[10], 0.5, 1e-6);
  EXPECT_NEAR(back->scanner_from_voxel[11], 7 - 6 * 0.5, 1e-5);
  for (int k = 0; k < 7; ++k) EXPECT_EQ(back->values[back->index(2, 3, k)], g.values[g.index(2, 3, 6 - k)]);
}

TEST(DicomSeries, UnsignedStoredValuesWithSlopeAndIntercept) {
  TempDir tmp;
  GreyImage g = coded();
  for (float& v : g.values) v = v * 0.5f;  // -250 .. 40: every value a multiple of the slope
  DicomWriteOptions o;
  o.signed_pixels = false;
  o.rescale_slope = 0.5;
  o.rescale_intercept = -1024;
  writeSeries(tmp.file("ct"), g, o);
  DicomSeriesInfo info;
  Result<GreyImage> back = readDicomSeries(tmp.file("ct"), {}, nullInterrupter(), &info);
  ASSERT_TRUE(back) << back.message();
  expectSameVolume(*back, g);
  EXPECT_FALSE(info.signed_pixels);
  EXPECT_DOUBLE_EQ(info.rescale_slope, 0.5);
  EXPECT_DOUBLE_EQ(info.rescale_intercept, -1024);
}

// Where pydicom is installed, it reads the files dentsim writes to the same values and positions.
TEST(DicomSeries, PydicomReadsTheWrittenSeries) {
  if (!fs::exists("/usr/bin/python3") || test::runCommand("/usr/bin/python3 -c 'import pydicom, numpy'").exit_code != 0)
    GTEST_SKIP() << "pydicom (python3-pydicom with numpy) is not installed";
  TempDir tmp;
  const GreyImage g = coded();
  const std::vector<std::string> files = writeSeries(tmp.file("ct"), g);
  ASSERT_EQ(files.size(), 7u);
  const auto run = test::runCommand("/usr/bin/python3 " DENTSIM_SOURCE_DIR "/tests/dicom/pydicom_reference.py " + files[3]);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto j = nlohmann::json::parse(run.output.substr(run.output.find('{')));
  ASSERT_FALSE(j.contains("error")) << run.output;
  EXPECT_EQ(j["rows"], 5);
  EXPECT_EQ(j["columns"], 6);
  double sum = 0;
  for (int jj = 0; jj < 5; ++jj)
    for (int i = 0; i < 6; ++i) sum += g.values[g.index(i, jj, 3)];
  EXPECT_DOUBLE_EQ(j["sum"].get<double>(), sum);
  EXPECT_NEAR(j["ImagePositionPatient"][2].get<double>(), 30 + 3 * 0.5, 1e-6);
  EXPECT_NEAR(j["PixelSpacing"][0].get<double>(), 0.4, 1e-9);  // between rows
  EXPECT_NEAR(j["PixelSpacing"][1].get<double>(), 0.3, 1e-9);  // between columns
  EXPECT_EQ(j["Modality"], "CT");
}

// ---- broken series: each one clear line -------------------------------------------------------
void expectOneLineError(const Result<GreyImage>& r, const std::string& words) {
  ASSERT_FALSE(r) << "expected an error with '" << words << "'";
  EXPECT_NE(r.message().find(words), std::string::npos) << r.message();
  EXPECT_EQ(r.message().find('\n'), std::string::npos) << r.message();
}

TEST(DicomSeries, MissingSliceIsNamed) {
  TempDir tmp;
  const auto files = writeSeries(tmp.file("ct"), coded());
  fs::remove(files[4]);
  const Result<GreyImage> r = readDicomSeries(tmp.file("ct"));
  expectOneLineError(r, "missing slice: a gap of 1 mm between slice-0004.dcm and slice-0006.dcm");
  EXPECT_NE(r.message().find("about 1 slice missing"), std::string::npos) << r.message();
}

TEST(DicomSeries, MixedSeriesListsEachAndIsPickedBySeriesUid) {
  TempDir tmp;
  DicomWriteOptions a, b;
  a.series_uid = "1.2.826.0.1.3680043.2.1125.1";
  b.series_uid = "1.2.826.0.1.3680043.2.1125.2";
  b.series_description = "scout";
  writeSeries(tmp.file("ct"), coded(), a);
  writeSeries(tmp.file("ct/scout"), coded(), b);  // a second series below the first
  expectOneLineError(readDicomSeries(tmp.file("ct")), "mixed series: 2 series in one folder");
  expectOneLineError(readDicomSeries(tmp.file("ct")), "'scout'");
  DicomReadOptions pick;
  pick.series_uid = b.series_uid;
  Result<GreyImage> r = readDicomSeries(tmp.file("ct"), pick);
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(r->description, "scout");
  pick.series_uid = "1.2.3";
  expectOneLineError(readDicomSeries(tmp.file("ct"), pick), "no series 1.2.3 here");
}

TEST(DicomSeries, TruncatedFileIsNamed) {
  TempDir tmp;
  const auto files = writeSeries(tmp.file("ct"), coded());
  for (size_t keep : {size_t(200), fs::file_size(files[2]) - 20}) {  // cut in the header, and in the pixels
    std::vector<uint8_t> bytes = test::readBytes(files[2]);
    bytes.resize(keep);
    std::ofstream(files[2], std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(bytes.data()),
                                                                        std::streamsize(bytes.size()));
    const Result<GreyImage> r = readDicomSeries(tmp.file("ct"));
    expectOneLineError(r, "slice-0003.dcm");
    EXPECT_NE(r.message().find("truncated"), std::string::npos) << r.message();
  }
}

TEST(DicomSeries, GantryTiltIsRefused) {
  TempDir tmp;
  // Each slice shifts 0.05 mm along y per 0.5 mm step: a tilt of about 5.7 degrees.
  writeSeries(tmp.file("ct"), coded({0.3, 0, 0, -10, 0, 0.4, 0.05, 20, 0, 0, 0.5, 30}));
  expectOneLineError(readDicomSeries(tmp.file("ct")), "gantry tilt");
}

TEST(DicomSeries, OtherBrokenFolders) {
  TempDir tmp;
  fs::create_directories(tmp.file("empty"));
  expectOneLineError(readDicomSeries(tmp.file("empty")), "holds no files");
  expectOneLineError(readDicomSeries(tmp.file("nowhere")), "no such file or folder");
  // Two files at one position.
  const auto files = writeSeries(tmp.file("ct"), coded());
  fs::copy_file(files[1], tmp.file("ct/copy.dcm"));
  expectOneLineError(readDicomSeries(tmp.file("ct")), "two slices at one position");
  fs::remove(tmp.file("ct/copy.dcm"));
  // A file that is not DICOM is skipped, and counted.
  std::ofstream(tmp.file("ct/README.txt")) << "scanner export notes\n";
  DicomSeriesInfo info;
  Result<GreyImage> ok = readDicomSeries(tmp.file("ct"), {}, nullInterrupter(), &info);
  ASSERT_TRUE(ok) << ok.message();
  EXPECT_EQ(info.files_skipped, 1);
  // A FIFO among the slices is not read (it would block), and a link to a folder above is not followed.
  ASSERT_EQ(::mkfifo(tmp.file("ct/pipe").c_str(), 0600), 0);
  fs::create_directory_symlink(tmp.path(), tmp.file("ct/up"));
  Result<GreyImage> beside = readDicomSeries(tmp.file("ct"));
  ASSERT_TRUE(beside) << beside.message();
  EXPECT_EQ(beside->dims[2], 7);
  // Only junk: no image.
  fs::create_directories(tmp.file("junk"));
  std::ofstream(tmp.file("junk/a.dcm")) << "not a scan";
  expectOneLineError(readDicomSeries(tmp.file("junk")), "no DICOM image among its 1 files");
  // A volume beyond the budget is refused before it is allocated.
  DicomReadOptions small;
  small.max_bytes = 100;
  expectOneLineError(readDicomSeries(tmp.file("ct"), small), "exceeds the limit of 100 bytes");
}

// GDCM's length of a data set grows about sixfold a level of nesting (100 levels never finish):
// deeper than 8 is refused as the header is read, and 8 itself is read.
TEST(DicomSeries, DeeplyNestedSequencesAreRefused) {
  TempDir tmp;
  fs::create_directories(tmp.file("deep"));
  std::ofstream(tmp.file("deep/nested.dcm"), std::ios::binary) << test::nestedSequenceSlice(100);
  expectOneLineError(readDicomFile(tmp.file("deep/nested.dcm")), "nested.dcm: sequences nested more than 8 deep");
  expectOneLineError(readDicomSeries(tmp.file("deep")), "nested.dcm: sequences nested more than 8 deep");
  std::ofstream(tmp.file("nine.dcm"), std::ios::binary) << test::nestedSequenceSlice(9);
  expectOneLineError(readDicomFile(tmp.file("nine.dcm")), "sequences nested more than 8 deep");
  std::ofstream(tmp.file("eight.dcm"), std::ios::binary) << test::nestedSequenceSlice(8);
  const Result<GreyImage> eight = readDicomFile(tmp.file("eight.dcm"));
  ASSERT_TRUE(eight) << eight.message();
  EXPECT_EQ(eight->dims, (std::array<int32_t, 3>{2, 2, 1}));
}

// ---- made-up data: pixels, geometry and units the files do not back ----------------------------
// Rows forged to 65,535 in every slice: 6 x 5 pixels of 16 bits (60 bytes) are all the files hold,
// so the header's 65,535 x 6 would be 99.99 % padding. Refused from the header, naming both sizes.
TEST(DicomSeries, ForgedRowsAreRefused) {
  TempDir tmp;
  const auto files = writeSeries(tmp.file("ct"), coded());
  for (const std::string& f : files) ASSERT_TRUE(test::forgeUs(f, 0x0028, 0x0010, 65535)) << f;
  const Result<GreyImage> r = readDicomSeries(tmp.file("ct"));
  expectOneLineError(r, "slice-0001.dcm: Rows x Columns x frames x samples (65535 x 6 x 1 x 1) need 786420 bytes");
  EXPECT_NE(r.message().find("its Pixel Data holds 60"), std::string::npos) << r.message();
  expectOneLineError(readDicomFile(files[0]), "need 786420 bytes of pixels but its Pixel Data holds 60");
  // Columns too, and one row more than the file holds is already too many: 6 x 6 x 2 = 72 > 60.
  ASSERT_TRUE(test::forgeUs(files[1], 0x0028, 0x0010, 6));
  expectOneLineError(readDicomFile(files[1]), "(6 x 6 x 1 x 1) need 72 bytes of pixels but its Pixel Data holds 60");
  // Bits Allocated forged from 16 to 32 asks for twice the bytes.
  ASSERT_TRUE(test::forgeUs(files[2], 0x0028, 0x0010, 5));
  ASSERT_TRUE(test::forgeUs(files[2], 0x0028, 0x0100, 32));
  expectOneLineError(readDicomFile(files[2]), "need 120 bytes of pixels but its Pixel Data holds 60");
}

// Positions and spacings must be finite and within a scanner's room (docs/PATIENT_SCANS.md): slices
// 1e15 mm apart, infinite or NaN positions, pixels or slices over 100 mm are each one line.
TEST(DicomSeries, AbsurdGeometryIsRefused) {
  TempDir tmp;
  writeSeries(tmp.file("far"), coded({0.3, 0, 0, -10, 0, 0.4, 0, 20, 0, 0, 1e15, 30}));
  expectOneLineError(readDicomSeries(tmp.file("far")), "slice-0002.dcm: Image Position (Patient) '-10\\20\\1e+15' lies beyond 1e+04 mm");
  writeSeries(tmp.file("inf"), coded({0.3, 0, 0, -10, 0, 0.4, 0, 20, 0, 0, 0.5, INFINITY}));
  expectOneLineError(readDicomSeries(tmp.file("inf")), "Image Position (Patient) is not three finite numbers");
  writeSeries(tmp.file("nan"), coded({0.3, 0, 0, NAN, 0, 0.4, 0, 20, 0, 0, 0.5, 30}));
  expectOneLineError(readDicomSeries(tmp.file("nan")), "Image Position (Patient) is not three finite numbers");
  writeSeries(tmp.file("steps"), coded({0.3, 0, 0, -10, 0, 0.4, 0, 20, 0, 0, 200, 30}));
  expectOneLineError(readDicomSeries(tmp.file("steps")), "its slices are 200 mm apart, beyond 100 mm");
  writeSeries(tmp.file("pixels"), coded({150, 0, 0, -10, 0, 0.4, 0, 20, 0, 0, 0.5, 30}));
  expectOneLineError(readDicomSeries(tmp.file("pixels")), "slice-0001.dcm: Pixel Spacing '0.4\\150' is beyond 100 mm");
  // At the limits themselves the series is read: 100 mm slices, 10 m from the origin.
  writeSeries(tmp.file("edge"), coded({0.3, 0, 0, -10000, 0, 0.4, 0, 20, 0, 0, 100, 9000}));
  const Result<GreyImage> edge = readDicomSeries(tmp.file("edge"));
  ASSERT_TRUE(edge) << edge.message();
  EXPECT_NEAR(edge->pitch_mm[2], 100, 1e-9);
}

// The k-th slice of coded() alone, as a series of one, to be added to another series' folder.
GreyImage codedSlice(int k) {
  GreyImage g = coded();
  const size_t plane = size_t(g.dims[0]) * size_t(g.dims[1]);
  g.values = std::vector<float>(g.values.begin() + std::ptrdiff_t(plane * size_t(k)),
                                g.values.begin() + std::ptrdiff_t(plane * size_t(k + 1)));
  g.dims[2] = 1;
  g.scanner_from_voxel[11] += 0.5 * k;
  return g;
}

// An MR slice, a slice without a Modality, or one in other units among CT slices of one series
// would be read as HU: refused, listing what was found.
TEST(DicomSeries, MixedModalitiesAndUnitsAreRefused) {
  TempDir tmp;
  DicomWriteOptions ct;
  ct.series_uid = "1.2.826.0.1.3680043.2.1125.7";
  GreyImage six = coded();
  six.dims[2] = 6;
  six.values.resize(size_t(six.voxelCount()));
  const auto add = [&](const std::string& dir, DicomWriteOptions o) {
    writeSeries(tmp.file(dir), six, ct);
    writeSeries(tmp.file("extra-" + dir), codedSlice(6), o);
    fs::rename(tmp.file("extra-" + dir + "/slice-0001.dcm"), tmp.file(dir + "/last.dcm"));
  };
  DicomWriteOptions mr = ct;
  mr.modality = "MR";
  add("mr", mr);
  expectOneLineError(readDicomSeries(tmp.file("mr")),
                     "mixed series: its slices are of more than one modality: CT (6 files), MR (1 file)");
  DicomWriteOptions none = ct;
  none.modality = "";
  add("none", none);
  expectOneLineError(readDicomSeries(tmp.file("none")), "more than one modality: no Modality (1 file), CT (6 files)");
  DicomWriteOptions us = ct;
  us.hounsfield = false;
  add("us", us);
  expectOneLineError(readDicomSeries(tmp.file("us")),
                     "more than one unit (Rescale Type): HU (6 files), US (1 file)");
  // The same seventh slice as CT in HU completes the series.
  add("same", ct);
  const Result<GreyImage> same = readDicomSeries(tmp.file("same"));
  ASSERT_TRUE(same) << same.message();
  expectSameVolume(*same, coded());
}

// Deflated Explicit VR Little Endian (1.2.840.10008.1.2.1.99): the elements' lengths measure the
// inflated stream, so the file is shorter than they add up to and is still whole. gdcmconv (Debian's
// libgdcm-tools, an encoder apart from dentsim's reader) makes the copies.
TEST(DicomSeries, DeflatedFilesAreRead) {
  if (test::runCommand("gdcmconv --version").exit_code != 0) GTEST_SKIP() << "gdcmconv (libgdcm-tools) is not installed";
  TempDir tmp;
  const GreyImage g = coded();
  const auto files = writeSeries(tmp.file("ct"), g);
  fs::create_directories(tmp.file("deflated"));
  for (const std::string& f : files) {
    const auto run = test::runCommand("gdcmconv --deflated " + f + " " + tmp.file("deflated/" + fs::path(f).filename().string()));
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  DicomSeriesInfo info;
  const Result<GreyImage> back = readDicomSeries(tmp.file("deflated"), {}, nullInterrupter(), &info);
  ASSERT_TRUE(back) << back.message();
  expectSameVolume(*back, g);
  EXPECT_NE(info.transfer_syntax.find("1.2.840.10008.1.2.1.99"), std::string::npos) << info.transfer_syntax;
  // Cut inside its compressed stream, a deflated slice is still one line naming it (zlib refuses it).
  const std::string third = tmp.file("deflated/slice-0003.dcm");
  fs::resize_file(third, fs::file_size(third) - 100);
  expectOneLineError(readDicomSeries(tmp.file("deflated")), "slice-0003.dcm: truncated or damaged");
}

// ---- the sample files Debian's python3-pydicom ships -------------------------------------------
std::string samplesDir() {
  if (test::runCommand("/usr/bin/python3 -c 'import pydicom, numpy'").exit_code != 0) return {};
  auto run = test::runCommand("/usr/bin/python3 " DENTSIM_SOURCE_DIR "/tests/dicom/pydicom_reference.py --samples");
  std::string dir = run.output.substr(0, run.output.find('\n'));
  return run.exit_code == 0 && fs::is_directory(dir) ? dir : std::string{};
}

// pydicom may warn on stderr before its line: the JSON is the last line.
nlohmann::json pydicomSays(const std::string& path) {
  auto run = test::runCommand("/usr/bin/python3 " DENTSIM_SOURCE_DIR "/tests/dicom/pydicom_reference.py " + path);
  std::string out = run.output;
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return nlohmann::json::parse(out.substr(out.rfind('\n') == std::string::npos ? 0 : out.rfind('\n') + 1));
}

void expectSameAsPydicom(const GreyImage& g, const nlohmann::json& want, const std::string& name) {
  ASSERT_FALSE(want.contains("error")) << name << ": " << want.dump();
  EXPECT_EQ(g.dims[0], want["columns"].get<int>()) << name;
  EXPECT_EQ(g.dims[1], want["rows"].get<int>()) << name;
  EXPECT_EQ(g.dims[2], want["frames"].get<int>()) << name;
  double sum = 0, lo = 1e30, hi = -1e30;
  for (float v : g.values) {
    sum += v;
    lo = std::min(lo, double(v));
    hi = std::max(hi, double(v));
  }
  EXPECT_DOUBLE_EQ(sum, want["sum"].get<double>()) << name;
  EXPECT_DOUBLE_EQ(lo, want["min"].get<double>()) << name;
  EXPECT_DOUBLE_EQ(hi, want["max"].get<double>()) << name;
  for (size_t n = 0; n < want["first"].size(); ++n) EXPECT_EQ(double(g.values[n]), want["first"][n].get<double>()) << name;
}

TEST(DicomSamples, CtAndMrFilesMatchPydicom) {
  const std::string dir = samplesDir();
  if (dir.empty()) GTEST_SKIP() << "pydicom's sample files (python3-pydicom with numpy) are not installed";
  for (const char* name : {"CT_small.dcm", "MR_small.dcm", "MR_small_implicit.dcm", "MR_small_bigendian.dcm",
                           "MR_small_expb.dcm", "MR_small_RLE.dcm", "MR_small_padded.dcm"}) {
    DicomSeriesInfo info;
    Result<GreyImage> g = readDicomFile(dir + "/" + name, inputBudget().max_bytes, &info);
    ASSERT_TRUE(g) << g.message();
    expectSameAsPydicom(*g, pydicomSays(dir + "/" + name), name);
  }
  // CT_small is a CT in HU with a rescale intercept; its position and spacing come from the header.
  Result<GreyImage> ct = readDicomFile(dir + "/CT_small.dcm");
  ASSERT_TRUE(ct);
  EXPECT_EQ(ct->unit, GreyUnit::Hounsfield);
  const auto want = pydicomSays(dir + "/CT_small.dcm");
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(ct->scanner_from_voxel[size_t(4 * r + 3)], want["ImagePositionPatient"][r].get<double>(), 1e-6);
  EXPECT_NEAR(ct->pitch_mm[0], want["PixelSpacing"][1].get<double>(), 1e-9);
  EXPECT_NEAR(ct->pitch_mm[1], want["PixelSpacing"][0].get<double>(), 1e-9);
}

// pydicom cannot decode these without plug-ins Debian lacks, but they are MR_small losslessly
// compressed: GDCM must give MR_small's values exactly.
TEST(DicomSamples, LosslessCompressionGivesTheUncompressedValues) {
  const std::string dir = samplesDir();
  if (dir.empty()) GTEST_SKIP() << "pydicom's sample files (python3-pydicom with numpy) are not installed";
  const auto want = pydicomSays(dir + "/MR_small.dcm");
  for (const char* name : {"MR_small_jpeg_ls_lossless.dcm", "MR_small_jp2klossless.dcm"}) {
    DicomSeriesInfo info;
    Result<GreyImage> g = readDicomFile(dir + "/" + name, inputBudget().max_bytes, &info);
    ASSERT_TRUE(g) << name << ": " << g.message();
    expectSameAsPydicom(*g, want, name);
    EXPECT_NE(info.transfer_syntax.find("JPEG"), std::string::npos) << info.transfer_syntax;
  }
}

// A multi-frame file is a volume of its own: rtdose.dcm holds 15 frames of 10 x 10, stepped 5 mm by its
// Grid Frame Offset Vector, with values scaled by Dose Grid Scaling (1e-6), which GDCM reads as the
// slope; pydicom gives the stored values.
TEST(DicomSamples, AMultiFrameFileIsAVolume) {
  const std::string dir = samplesDir();
  if (dir.empty()) GTEST_SKIP() << "pydicom's sample files (python3-pydicom with numpy) are not installed";
  Result<GreyImage> g = readDicomSeries(dir + "/rtdose.dcm");
  ASSERT_TRUE(g) << g.message();
  const auto want = pydicomSays(dir + "/rtdose.dcm");
  ASSERT_FALSE(want.contains("error")) << want.dump();
  EXPECT_EQ(g->dims, (std::array<int32_t, 3>{want["columns"].get<int>(), want["rows"].get<int>(), want["frames"].get<int>()}));
  EXPECT_EQ(g->dims[2], 15);
  EXPECT_NEAR(g->pitch_mm[2], 5.0, 1e-9);
  EXPECT_NEAR(g->pitch_mm[0], want["PixelSpacing"][1].get<double>(), 1e-9);
  for (int r = 0; r < 3; ++r)
    EXPECT_NEAR(g->scanner_from_voxel[size_t(4 * r + 3)], want["ImagePositionPatient"][r].get<double>(), 1e-6);
  double sum = 0;
  for (float v : g->values) sum += v;
  EXPECT_NEAR(sum, want["sum"].get<double>() * 1e-6, 1e-3);
  EXPECT_NEAR(g->values[0], want["first"][0].get<double>() * 1e-6, 1e-6);
  EXPECT_EQ(g->unit, GreyUnit::Raw);  // a dose, not a CT
}

// MR_small's JPEG-LS file relabelled JPIP Referenced (same UID length, so the header stays whole): its
// pixels are JPEG-LS, which no JPIP decoder reads, and the error names the transfer syntax.
TEST(DicomSamples, ACompressionGdcmCannotDecodeIsNamed) {
  const std::string dir = samplesDir();
  if (dir.empty()) GTEST_SKIP() << "pydicom's sample files (python3-pydicom with numpy) are not installed";
  std::vector<uint8_t> bytes = test::readBytes(dir + "/MR_small_jpeg_ls_lossless.dcm");
  const std::string from = "1.2.840.10008.1.2.4.80", to = "1.2.840.10008.1.2.4.94";
  auto at = std::search(bytes.begin(), bytes.end(), from.begin(), from.end());
  ASSERT_NE(at, bytes.end());
  std::copy(to.begin(), to.end(), at);
  TempDir tmp;
  std::ofstream(tmp.file("jpip.dcm"), std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  expectOneLineError(readDicomFile(tmp.file("jpip.dcm")), "cannot decode its pixel data (transfer syntax JPIP Referenced");
}

TEST(DicomSamples, DamagedAndUnsuitableFilesAreOneLine) {
  const std::string dir = samplesDir();
  if (dir.empty()) GTEST_SKIP() << "pydicom's sample files (python3-pydicom with numpy) are not installed";
  expectOneLineError(readDicomFile(dir + "/MR_truncated.dcm"), "MR_truncated.dcm");
  expectOneLineError(readDicomFile(dir + "/SC_rgb_rle.dcm"), "colour image");
  expectOneLineError(readDicomFile(dir + "/rtplan.dcm"), "without an image");
  // A folder holding one slice is not a volume.
  TempDir tmp;
  fs::create_directories(tmp.file("one"));
  fs::copy_file(dir + "/CT_small.dcm", tmp.file("one/CT_small.dcm"));
  expectOneLineError(readDicomSeries(tmp.file("one")), "one slice is not a volume");
}

}  // namespace
}  // namespace dentsim
