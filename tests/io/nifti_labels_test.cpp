// Tests of src/io/nifti_labels.cpp: label images survive a write/read round trip, and every malformed file gets a one-line error.
#include "io/nifti_labels.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

#include <zlib.h>

#include "io/input_budget.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readBytes;
// 5 x 4 x 3 = 60 voxels, counted by hand: a 2x2x1 block of 3 (4 voxels), one voxel of 1, and the
// row j=3,k=2 of label 2 (5 voxels); the other 50 are 0.
LabelImage smallImage() {
  LabelImage im;
  im.dims = {5, 4, 3};
  im.pitch_mm = {0.034, 0.05, 0.1};
  // Flipped x and y, as the CT files are, with an offset [mm].
  im.scanner_from_voxel = {-0.034, 0, 0, 12.5, 0, -0.05, 0, -3.0, 0, 0, 0.1, 7.25};
  im.labels.assign(60, 0);
  for (int j = 1; j <= 2; ++j)
    for (int i = 2; i <= 3; ++i) im.labels[im.index(i, j, 0)] = 3;
  im.labels[im.index(4, 0, 1)] = 1;
  for (int i = 0; i < 5; ++i) im.labels[im.index(i, 3, 2)] = 2;
  return im;
}

template <class T>
void poke(std::vector<uint8_t>& bytes, size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

// NIfTI-1 header offsets [B] used to forge hostile files from a valid one.
constexpr size_t kDim = 40, kDatatype = 70, kBitpix = 72, kSclSlope = 112, kSformCode = 254, kHeaderAndExt = 352;

// One line, naming the file, and saying what went wrong.
void expectError(const Result<LabelImage>& r, const std::string& path, const std::string& problem) {
  ASSERT_FALSE(r.ok()) << "expected an error for " << path;
  EXPECT_EQ(r.message().rfind(path + ": ", 0), 0u) << r.message();
  EXPECT_NE(r.message().find(problem), std::string::npos) << r.message();
  EXPECT_EQ(r.message().find('\n'), std::string::npos) << r.message();
}

void expectSame(const LabelImage& a, const LabelImage& b, double matrix_tol) {
  EXPECT_EQ(a.dims, b.dims);
  for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(a.pitch_mm[i], b.pitch_mm[i], 1e-7);
  for (size_t i = 0; i < 12; ++i) EXPECT_NEAR(a.scanner_from_voxel[i], b.scanner_from_voxel[i], matrix_tol) << i;
  EXPECT_EQ(a.labels, b.labels);
}

class NiftiLabelsTest : public ::testing::Test {
 protected:
  test::TempDir dir;
  // A valid uncompressed file of smallImage() as bytes: header, 4-byte extender, 60 uint8 voxels.
  std::vector<uint8_t> validBytes() {
    const std::string p = dir.file("valid.nii");
    EXPECT_TRUE(writeNiftiLabels(p, smallImage()).ok());
    return readBytes(p);
  }
};

TEST_F(NiftiLabelsTest, RoundTripUncompressedAndGzip) {
  const LabelImage im = smallImage();
  for (const char* name : {"a.nii", "a.nii.gz"}) {
    const std::string p = dir.file(name);
    ASSERT_TRUE(writeNiftiLabels(p, im).ok());
    Result<LabelImage> back = readNiftiLabels(p);
    ASSERT_TRUE(back.ok()) << back.message();
    expectSame(im, *back, 1e-6);  // the sform is stored as float32
    // Hand counts survive: 50 zeros, one 1, five 2s, four 3s.
    EXPECT_EQ(std::count(back->labels.begin(), back->labels.end(), 0), 50);
    EXPECT_EQ(std::count(back->labels.begin(), back->labels.end(), 1), 1);
    EXPECT_EQ(std::count(back->labels.begin(), back->labels.end(), 2), 5);
    EXPECT_EQ(std::count(back->labels.begin(), back->labels.end(), 3), 4);
  }
  // The uncompressed file is exactly header + extender + one byte per voxel; the gzip one is compressed.
  EXPECT_EQ(readBytes(dir.file("a.nii")).size(), kHeaderAndExt + 60);
  const std::vector<uint8_t> gz = readBytes(dir.file("a.nii.gz"));
  ASSERT_GE(gz.size(), 2u);
  EXPECT_EQ(gz[0], 0x1f);
  EXPECT_EQ(gz[1], 0x8b);
}

TEST_F(NiftiLabelsTest, QformAloneGivesTheSameMatrix) {
  // Turn the sform off: the reader must fall back to the qform, which the writer set too.
  std::vector<uint8_t> bytes = validBytes();
  poke<int16_t>(bytes, kSformCode, 0);
  const std::string p = dir.file("qform.nii");
  test::writeBytes(p, bytes);
  Result<LabelImage> back = readNiftiLabels(p);
  ASSERT_TRUE(back.ok()) << back.message();
  expectSame(smallImage(), *back, 1e-5);
}

TEST_F(NiftiLabelsTest, WriteLeavesNoTemporaryAndReplacesAtomically) {
  const std::string p = dir.file("out.nii.gz");
  ASSERT_TRUE(writeNiftiLabels(p, smallImage()).ok());
  ASSERT_TRUE(writeNiftiLabels(p, smallImage()).ok());
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST_F(NiftiLabelsTest, WriteRefusesLabelsThatDoNotFitUint8) {
  LabelImage im = smallImage();
  im.labels[0] = 300;
  const std::string p = dir.file("big.nii");
  const Status s = writeNiftiLabels(p, im);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("label 300"), std::string::npos) << s.message();
  EXPECT_FALSE(std::filesystem::exists(p));
}

TEST_F(NiftiLabelsTest, MissingFile) {
  const std::string p = dir.file("nothing.nii.gz");
  expectError(readNiftiLabels(p), p, "cannot open");
}

TEST_F(NiftiLabelsTest, MissingUncompressedDoesNotFallBackToGzipSibling) {
  ASSERT_TRUE(writeNiftiLabels(dir.file("x.nii.gz"), smallImage()).ok());
  const std::string p = dir.file("x.nii");
  expectError(readNiftiLabels(p), p, "cannot open");
}

TEST_F(NiftiLabelsTest, EmptyFile) {
  const std::string p = dir.file("empty.nii");
  test::writeBytes(p, {});
  expectError(readNiftiLabels(p), p, "empty file");
}

TEST_F(NiftiLabelsTest, TextFile) {
  const std::string p = dir.file("notes.nii");
  std::string text;
  for (int i = 0; i < 40; ++i) text += "this is a text file, not a label volume\n";
  test::writeBytes(p, std::vector<uint8_t>(text.begin(), text.end()));
  expectError(readNiftiLabels(p), p, "not a NIfTI file");
}

TEST_F(NiftiLabelsTest, ShortTextFile) {
  const std::string p = dir.file("short.nii");
  test::writeBytes(p, {'h', 'i', '\n'});
  expectError(readNiftiLabels(p), p, "not a NIfTI file");
}

TEST_F(NiftiLabelsTest, WrongExtension) {
  const std::string p = dir.file("labels.raw");
  test::writeBytes(p, validBytes());
  expectError(readNiftiLabels(p), p, "expected .nii or .nii.gz");
}

TEST_F(NiftiLabelsTest, TruncatedUncompressed) {
  std::vector<uint8_t> bytes = validBytes();
  bytes.resize(bytes.size() - 7);  // the last 7 voxels are missing
  const std::string p = dir.file("cut.nii");
  test::writeBytes(p, bytes);
  expectError(readNiftiLabels(p), p, "truncated");
}

TEST_F(NiftiLabelsTest, TruncatedHeader) {
  std::vector<uint8_t> bytes = validBytes();
  bytes.resize(200);
  const std::string p = dir.file("cuthdr.nii");
  test::writeBytes(p, bytes);
  expectError(readNiftiLabels(p), p, "truncated");
}

TEST_F(NiftiLabelsTest, TruncatedGzip) {
  // A volume big enough that its compressed stream has a middle to cut.
  LabelImage im;
  im.dims = {40, 40, 40};
  im.pitch_mm = {1, 1, 1};
  im.scanner_from_voxel = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  im.labels.resize(64000);
  uint32_t state = 12345;  // incompressible-ish content: labels 0..3 from a fixed LCG
  for (Label& l : im.labels) {
    state = state * 1664525u + 1013904223u;
    l = Label(state >> 30);
  }
  const std::string whole = dir.file("whole.nii.gz");
  ASSERT_TRUE(writeNiftiLabels(whole, im).ok());
  std::vector<uint8_t> bytes = readBytes(whole);
  bytes.resize(bytes.size() / 2);
  const std::string p = dir.file("cut.nii.gz");
  test::writeBytes(p, bytes);
  expectError(readNiftiLabels(p), p, "truncated");
}

TEST_F(NiftiLabelsTest, FloatLabelsMustBeWholeNumbers) {
  std::vector<uint8_t> bytes = validBytes();
  bytes.resize(kHeaderAndExt);
  poke<int16_t>(bytes, kDatatype, 16);  // DT_FLOAT32
  poke<int16_t>(bytes, kBitpix, 32);
  const LabelImage im = smallImage();
  std::vector<float> values(im.labels.begin(), im.labels.end());
  std::vector<uint8_t> whole = bytes;
  whole.resize(kHeaderAndExt + values.size() * 4);
  std::memcpy(whole.data() + kHeaderAndExt, values.data(), values.size() * 4);
  const std::string ok_path = dir.file("float_ok.nii");
  test::writeBytes(ok_path, whole);
  Result<LabelImage> ok = readNiftiLabels(ok_path);
  ASSERT_TRUE(ok.ok()) << ok.message();
  EXPECT_EQ(ok->labels, im.labels);

  values[17] = 2.5f;
  std::memcpy(whole.data() + kHeaderAndExt, values.data(), values.size() * 4);
  const std::string bad = dir.file("float_bad.nii");
  test::writeBytes(bad, whole);
  expectError(readNiftiLabels(bad), bad, "whole numbers");
}

TEST_F(NiftiLabelsTest, UnsupportedDatatype) {
  std::vector<uint8_t> bytes = validBytes();
  poke<int16_t>(bytes, kDatatype, 32);  // DT_COMPLEX64
  poke<int16_t>(bytes, kBitpix, 64);
  const std::string p = dir.file("complex.nii");
  test::writeBytes(p, bytes);
  expectError(readNiftiLabels(p), p, "unsupported datatype");
}

TEST_F(NiftiLabelsTest, FourDimensional) {
  std::vector<uint8_t> bytes = validBytes();
  poke<int16_t>(bytes, kDim, 4);
  poke<int16_t>(bytes, kDim + 8, 1);  // t = 1: still one 3D volume
  const std::string one = dir.file("t1.nii");
  test::writeBytes(one, bytes);
  Result<LabelImage> r = readNiftiLabels(one);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->labels, smallImage().labels);

  poke<int16_t>(bytes, kDim + 8, 2);  // t = 2: a time series
  bytes.resize(kHeaderAndExt + 120);
  const std::string two = dir.file("t2.nii");
  test::writeBytes(two, bytes);
  expectError(readNiftiLabels(two), two, "wrong dimensionality");
}

TEST_F(NiftiLabelsTest, TwoDimensional) {
  std::vector<uint8_t> bytes = validBytes();
  poke<int16_t>(bytes, kDim, 2);
  const std::string p = dir.file("flat.nii");
  test::writeBytes(p, bytes);
  expectError(readNiftiLabels(p), p, "wrong dimensionality");
}

TEST_F(NiftiLabelsTest, AbsurdDimensions) {
  // NIfTI-1 dims are int16: 30000^3 = 2.7e13 voxels, far past the limit; nothing may be allocated.
  std::vector<uint8_t> bytes = validBytes();
  for (size_t a = 1; a <= 3; ++a) poke<int16_t>(bytes, kDim + 2 * a, 30000);
  const std::string p = dir.file("huge.nii");
  test::writeBytes(p, bytes);
  expectError(readNiftiLabels(p), p, "oversized dimensions");
}

TEST_F(NiftiLabelsTest, DimensionsWithinVoxelLimitButPastFileSize) {
  std::vector<uint8_t> bytes = validBytes();
  for (size_t a = 1; a <= 3; ++a) poke<int16_t>(bytes, kDim + 2 * a, 500);
  const std::string p = dir.file("promise.nii");
  test::writeBytes(p, bytes);
  expectError(readNiftiLabels(p), p, "truncated");
}

TEST_F(NiftiLabelsTest, NegativeDimension) {
  std::vector<uint8_t> bytes = validBytes();
  poke<int16_t>(bytes, kDim + 4, -4);
  const std::string p = dir.file("neg.nii");
  test::writeBytes(p, bytes);
  Result<LabelImage> r = readNiftiLabels(p);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message().rfind(p + ": ", 0), 0u) << r.message();
}

TEST_F(NiftiLabelsTest, ScaledLabelsAreRefused) {
  std::vector<uint8_t> bytes = validBytes();
  poke<float>(bytes, kSclSlope, 2.0f);
  const std::string p = dir.file("scaled.nii");
  test::writeBytes(p, bytes);
  expectError(readNiftiLabels(p), p, "scaled");
}

TEST_F(NiftiLabelsTest, LimitsAreHonoured) {
  const std::string p = dir.file("small.nii");
  test::writeBytes(p, validBytes());
  NiftiReadLimits limits;
  limits.max_voxels = 59;  // one fewer than the 60 voxels of the file
  expectError(readNiftiLabels(p, limits), p, "exceed the limit");
  limits = {};
  limits.max_bytes = 59;
  expectError(readNiftiLabels(p, limits), p, "exceeds the limit");
}

TEST_F(NiftiLabelsTest, WideLabelsOutsideInt16AreRefused) {
  std::vector<uint8_t> bytes = validBytes();
  bytes.resize(kHeaderAndExt);
  poke<int16_t>(bytes, kDatatype, 768);  // DT_UINT32
  poke<int16_t>(bytes, kBitpix, 32);
  std::vector<uint32_t> values(60, 0);
  values[5] = 40000;
  bytes.resize(kHeaderAndExt + 240);
  std::memcpy(bytes.data() + kHeaderAndExt, values.data(), 240);
  const std::string p = dir.file("wide.nii");
  test::writeBytes(p, bytes);
  expectError(readNiftiLabels(p), p, "label 40000");
}

TEST_F(NiftiLabelsTest, AVolumeOfZerosHoldsNoTooth) {
  // Before, a volume of zeros became an empty tooth with exit 0.
  LabelImage im = smallImage();
  std::fill(im.labels.begin(), im.labels.end(), Label{0});
  for (const char* name : {"zeros.nii", "zeros.nii.gz"}) {
    const std::string p = dir.file(name);
    ASSERT_TRUE(writeNiftiLabels(p, im).ok());
    const Result<LabelImage> r = readNiftiLabels(p);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.message(), p + ": holds no tooth: every voxel is 0");
  }
}

TEST_F(NiftiLabelsTest, IntegerLabelsStreamIntoInt16WithTheirValues) {
  // An int32 file of the small image, its values written by hand: the reader converts it slab by
  // slab, never holding the int32 copy whole.
  std::vector<uint8_t> bytes = validBytes();
  bytes.resize(kHeaderAndExt);
  poke<int16_t>(bytes, kDatatype, 8);  // DT_INT32
  poke<int16_t>(bytes, kBitpix, 32);
  const LabelImage im = smallImage();
  std::vector<int32_t> values(im.labels.begin(), im.labels.end());
  values[59] = -7;
  bytes.resize(kHeaderAndExt + 240);
  std::memcpy(bytes.data() + kHeaderAndExt, values.data(), 240);
  const std::string p = dir.file("int32.nii");
  test::writeBytes(p, bytes);
  const Result<LabelImage> r = readNiftiLabels(p);
  ASSERT_TRUE(r.ok()) << r.message();
  std::vector<Label> expected = im.labels;
  expected[59] = -7;
  EXPECT_EQ(r->labels, expected);
}

TEST_F(NiftiLabelsTest, VolumesLargerThanOneSlabReadWhole) {
  // 128^3 = 2 MiB voxels, two of the reader's 1 MiB slabs: labels on both sides of the seam and at
  // the ends survive, compressed or not.
  LabelImage im;
  im.dims = {128, 128, 128};
  im.scanner_from_voxel = {0.1, 0, 0, 0, 0, 0.1, 0, 0, 0, 0, 0.1, 0};
  im.pitch_mm = {0.1, 0.1, 0.1};
  im.labels.assign(size_t(im.voxelCount()), 0);
  for (size_t at : {size_t{0}, (size_t{1} << 20) - 1, size_t{1} << 20, (size_t{2} << 20) - 1}) im.labels[at] = 4;
  for (const char* name : {"big.nii", "big.nii.gz"}) {
    const std::string p = dir.file(name);
    ASSERT_TRUE(writeNiftiLabels(p, im).ok());
    const Result<LabelImage> r = readNiftiLabels(p);
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(r->labels, im.labels) << name;
  }
}

TEST_F(NiftiLabelsTest, LabelsOverTheBudgetAreRefusedBeforeTheyAreRead) {
  const std::string p = dir.file("small.nii");
  test::writeBytes(p, validBytes());
  NiftiReadLimits limits;
  limits.max_label_bytes = 119;  // 60 voxels of int16 take 120
  expectError(readNiftiLabels(p, limits), p, "labels of 60 voxels (120 bytes) exceeds the limit of 119 bytes");
  // The budget in force is what the default limits take, and the message names its flag.
  setInputBudget({100});
  const Result<LabelImage> r = readNiftiLabels(p);
  setInputBudget({});
  expectError(r, p, "exceeds the limit of 100 bytes (the input budget; raise it with --max-input-mb N, in MiB)");
}

// A .nii.gz of `header` then `noise_bytes` of incompressible bytes, so that the file is as large as a
// real bomb of zeros would be (deflate's best ratio is about 1032:1) without inflating gigabytes.
void writeGzipBomb(const std::string& path, const std::vector<uint8_t>& header, size_t noise_bytes) {
  gzFile gz = gzopen(path.c_str(), "wb1");
  ASSERT_NE(gz, nullptr);
  gzwrite(gz, header.data(), unsigned(header.size()));
  std::mt19937 rng(27);
  std::vector<uint8_t> noise(noise_bytes);
  for (uint8_t& b : noise) b = uint8_t(rng());
  gzwrite(gz, noise.data(), unsigned(noise.size()));
  gzclose(gz);
}

TEST_F(NiftiLabelsTest, AGzipBombIsRefusedFromItsHeader) {
  // The 1 MB .nii.gz: a header claiming 1024^3 uint8 voxels, then a megabyte of compressed
  // data. Before, it cost 3.1 GB; now its 2 GiB of labels are refused before a voxel is read.
  std::vector<uint8_t> header = validBytes();
  header.resize(kHeaderAndExt);
  for (int i = 1; i <= 3; ++i) poke<int16_t>(header, kDim + 2 * size_t(i), 1024);
  const std::string p = dir.file("bomb.nii.gz");
  writeGzipBomb(p, header, size_t{1} << 20);
  expectError(readNiftiLabels(p), p,
              "labels of 1073741824 voxels (2147483648 bytes) exceeds the limit of 536870912 bytes (the input budget; "
              "raise it with --max-input-mb N, in MiB)");
  // The int32 one (it cost 6.2 GB): 1024 x 1024 x 512 int32 is 2 GiB stored, 1 GiB of labels.
  poke<int16_t>(header, kDim + 6, 512);
  poke<int16_t>(header, kDatatype, 8);  // DT_INT32
  poke<int16_t>(header, kBitpix, 32);
  const std::string p32 = dir.file("bomb32.nii.gz");
  writeGzipBomb(p32, header, size_t{2} << 20);
  expectError(readNiftiLabels(p32), p32,
              "labels of 536870912 voxels (1073741824 bytes) exceeds the limit of 536870912 bytes (the input budget; "
              "raise it with --max-input-mb N, in MiB)");
}

}  // namespace
}  // namespace dentsim
