// Tests for src/io/dvol_file.cpp and atomic_file.cpp: round trip, corruption, limits, atomic replacement.
#include "io/dvol_file.h"

#include <gtest/gtest.h>

#include <xxhash.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "io/atomic_file.h"
#include "test_support.h"

namespace dentsim {
namespace {

VolumeFileData sample() {
  VolumeFileData d;
  d.frame = VolumeFrame::axisAligned(7, 0.034, {1.0, -2.0, 3.5});
  d.frame.source_offset = {0, 1, 2};
  d.frame.source_dims = {100, 90, 80};
  d.chunks.assign(8, 0x80000000u);
  d.chunks[3] = 0;  // one block
  d.blocks.assign(512, 0x80000000u | 0x3fu);
  d.blocks[7] = 0;  // one brick
  d.bricks.assign(128, 0x3f3f2122u);
  return d;
}

std::vector<uint8_t> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void rehashHeader(std::vector<uint8_t>& bytes) {  // keeps the header checksum valid after an edit
  const uint64_t h = XXH64(bytes.data(), 216, 0);
  std::memcpy(bytes.data() + 216, &h, 8);
}

TEST(DvolFile, RoundTripKeepsFrameAndWords) {
  test::TempDir dir;
  const VolumeFileData d = sample();
  ASSERT_TRUE(writeVolumeFile(dir.file("a.dvol"), d).ok());
  auto r = readVolumeFile(dir.file("a.dvol"));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->frame.level, 7);
  EXPECT_DOUBLE_EQ(r->frame.voxel_mm, 0.034);
  EXPECT_EQ(r->frame.origin_mm, d.frame.origin_mm);
  EXPECT_EQ(r->frame.source_dims, d.frame.source_dims);
  EXPECT_EQ(r->frame.source_offset, d.frame.source_offset);
  EXPECT_EQ(r->frame.scanner_from_grid, d.frame.scanner_from_grid);
  EXPECT_EQ(r->chunks, d.chunks);
  EXPECT_EQ(r->blocks, d.blocks);
  EXPECT_EQ(r->bricks, d.bricks);
}

TEST(DvolFile, EveryTruncationIsAnErrorNamingTheFile) {
  const std::vector<uint8_t> bytes = encodeVolumeFile(sample());
  for (size_t len = 0; len < bytes.size(); len += len < 300 ? 1 : 7) {
    auto r = parseVolumeFile(std::span(bytes.data(), len), "cut.dvol");
    ASSERT_FALSE(r.ok()) << "length " << len;
    EXPECT_EQ(r.message().rfind("cut.dvol: ", 0), 0u) << r.message();
    EXPECT_EQ(r.message().find('\n'), std::string::npos);
  }
  auto r = parseVolumeFile(std::span(bytes.data(), bytes.size() - 3), "cut.dvol");
  EXPECT_NE(r.message().find("truncated"), std::string::npos) << r.message();
}

TEST(DvolFile, CorruptionIsCaughtByTheChecksums) {
  std::vector<uint8_t> bytes = encodeVolumeFile(sample());
  auto header = bytes;
  header[40] ^= 0x10;  // inside the origin
  EXPECT_NE(parseVolumeFile(header, "x").message().find("header checksum mismatch"), std::string::npos);
  auto magic = bytes;
  magic[0] = 'X';
  EXPECT_NE(parseVolumeFile(magic, "x").message().find("not a dentsim volume file"), std::string::npos);
  auto payload = bytes;
  payload.back() ^= 0x01;
  EXPECT_FALSE(parseVolumeFile(payload, "x").ok());
}

TEST(DvolFile, VersionAndLimitsAreChecked) {
  std::vector<uint8_t> bytes = encodeVolumeFile(sample());
  auto future = bytes;
  const uint32_t v3 = 3;
  std::memcpy(future.data() + 8, &v3, 4);
  rehashHeader(future);
  EXPECT_NE(parseVolumeFile(future, "x").message().find("unsupported volume file version 3"), std::string::npos);

  auto huge = bytes;
  const uint64_t words = uint64_t{1} << 40;  // 4 TiB of bricks
  std::memcpy(huge.data() + 192, &words, 8);
  rehashHeader(huge);
  EXPECT_NE(parseVolumeFile(huge, "x").message().find("exceeds the limit"), std::string::npos);

  auto level = bytes;
  const int32_t l = 40;
  std::memcpy(level.data() + 16, &l, 4);
  rehashHeader(level);
  EXPECT_NE(parseVolumeFile(level, "x").message().find("grid level 40"), std::string::npos);

  EXPECT_NE(parseVolumeFile(bytes, "x", 100).message().find("exceeds the limit"), std::string::npos);
}

// A version 1 file: the 224-byte header of before the tooth frame, then the same payload.
std::vector<uint8_t> asVersion1(const std::vector<uint8_t>& v2) {
  std::vector<uint8_t> v1(v2.begin(), v2.begin() + 224);
  v1.insert(v1.end(), v2.begin() + 352, v2.end());
  const uint32_t version = 1, header = 224;
  std::memcpy(v1.data() + 8, &version, 4);
  std::memcpy(v1.data() + 12, &header, 4);
  rehashHeader(v1);
  return v1;
}

void rehashTooth(std::vector<uint8_t>& bytes) {
  const uint64_t h = XXH64(bytes.data() + 224, 120, 0);
  std::memcpy(bytes.data() + 344, &h, 8);
}

TEST(DvolFile, TheToothFrameRoundTripsAndOldFilesLoadWithTheDefault) {
  VolumeFileData d = sample();
  ToothAxes& t = d.frame.tooth;
  t.crown = {0, -1, 0};
  t.mesial = {0, 0, 1};
  t.buccal = {-1, 0, 0};
  t.crown_source = AxisSource::Found;
  t.mesial_source = AxisSource::Given;
  t.has_occlusal_centre = true;
  t.occlusal_centre_mm = {1.5, -2.25, 7.0};
  t.turn = {1, 0, 0, 0, 0, -1, 0, 1, 0};
  const std::vector<uint8_t> bytes = encodeVolumeFile(d);
  auto r = parseVolumeFile(bytes, "t.dvol");
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->frame.tooth.crown, t.crown);
  EXPECT_EQ(r->frame.tooth.mesial, t.mesial);
  EXPECT_EQ(r->frame.tooth.buccal, t.buccal);
  EXPECT_EQ(r->frame.tooth.crown_source, AxisSource::Found);
  EXPECT_EQ(r->frame.tooth.mesial_source, AxisSource::Given);
  EXPECT_EQ(r->frame.tooth.buccal_source, AxisSource::Assumed);
  EXPECT_TRUE(r->frame.tooth.has_occlusal_centre);
  EXPECT_EQ(r->frame.tooth.occlusal_centre_mm, t.occlusal_centre_mm);
  EXPECT_EQ(r->frame.tooth.turn, t.turn);

  auto old = parseVolumeFile(asVersion1(bytes), "old.dvol");
  ASSERT_TRUE(old.ok()) << old.message();
  EXPECT_EQ(old->frame.tooth.crown, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(old->frame.tooth.crown_source, AxisSource::Assumed);
  EXPECT_FALSE(old->frame.tooth.has_occlusal_centre);
  EXPECT_FALSE(old->frame.tooth.turned());
  EXPECT_EQ(old->bricks, d.bricks);
}

TEST(DvolFile, ABadToothFrameIsOneLineNamingIt) {
  const std::vector<uint8_t> bytes = encodeVolumeFile(sample());
  const auto withDouble = [&](size_t at, double v) {
    auto b = bytes;
    std::memcpy(b.data() + at, &v, 8);
    rehashTooth(b);
    return parseVolumeFile(b, "t.dvol").message();
  };
  EXPECT_EQ(withDouble(224, 2.0), "t.dvol: tooth frame: crown axis: not a unit vector");
  EXPECT_EQ(withDouble(248 + 16, 0.5), "t.dvol: tooth frame: mesial axis: not a unit vector");
  EXPECT_EQ(withDouble(296, std::nan("")), "t.dvol: tooth frame: occlusal centre: not finite");
  auto skew = bytes;  // mesial along the crown
  const double up[3] = {0, 0, 1};
  std::memcpy(skew.data() + 248, up, 24);
  rehashTooth(skew);
  EXPECT_EQ(parseVolumeFile(skew, "t.dvol").message(), "t.dvol: tooth frame: axes: crown, mesial and buccal are not at right angles");
  auto mirror = bytes;  // a reflection is not a turn
  mirror[324] = uint8_t(-1);
  rehashTooth(mirror);
  EXPECT_EQ(parseVolumeFile(mirror, "t.dvol").message(), "t.dvol: tooth frame: quarter turn: not a rotation by quarter turns");
  auto source = bytes;
  source[320] = 7;
  rehashTooth(source);
  EXPECT_EQ(parseVolumeFile(source, "t.dvol").message(), "t.dvol: tooth frame: axis source: unknown value 7");
  auto flipped = bytes;  // without the rehash
  flipped[230] ^= 0x40;
  EXPECT_EQ(parseVolumeFile(flipped, "t.dvol").message(), "t.dvol: tooth frame checksum mismatch: the file is corrupt");
}

TEST(DvolFile, MissingFileAndDirectoryAreErrors) {
  auto r = readVolumeFile("/nonexistent/dir/t.dvol");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), "/nonexistent/dir/t.dvol: cannot open: No such file or directory");
  auto w = writeVolumeFile("/nonexistent/dir/t.dvol", sample());
  EXPECT_FALSE(w.ok());
}

TEST(AtomicFile, ReplacingKeepsNoTemporaryAndAFailedWriteKeepsTheOldFile) {
  test::TempDir dir;
  const std::string path = dir.file("tooth.dvol");
  ASSERT_TRUE(writeFileAtomic(path, std::vector<uint8_t>{1, 2, 3}).ok());
  ASSERT_TRUE(writeFileAtomic(path, std::vector<uint8_t>{4, 5}).ok());
  EXPECT_EQ(slurp(path), (std::vector<uint8_t>{4, 5}));
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
  // A directory in the way of the rename: the write fails and the old file survives.
  std::filesystem::create_directory(dir.file("busy.dvol"));
  std::filesystem::create_directory(dir.file("busy.dvol/keep"));
  EXPECT_FALSE(writeFileAtomic(dir.file("busy.dvol"), std::vector<uint8_t>{9}).ok());
  EXPECT_TRUE(std::filesystem::is_directory(dir.file("busy.dvol/keep")));
  EXPECT_EQ(temporarySibling("a/b/labels.nii.gz").rfind("a/b/labels.tmp-", 0), 0u);
  EXPECT_TRUE(temporarySibling("a/b/labels.nii.gz").ends_with(".nii.gz"));
}

TEST(AtomicFile, ReadRefusesFilesOverTheLimit) {
  test::TempDir dir;
  ASSERT_TRUE(writeFileAtomic(dir.file("big"), std::vector<uint8_t>(100, 7)).ok());
  auto r = readFileBytes(dir.file("big"), 99);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("exceeds the limit of 99 bytes"), std::string::npos);
  EXPECT_TRUE(readFileBytes(dir.file("big"), 100).ok());
  EXPECT_FALSE(readFileBytes(dir.path().string(), 100).ok());  // a directory
}

}  // namespace
}  // namespace dentsim
