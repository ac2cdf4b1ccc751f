// Tests for src/io/dvol_file.cpp and atomic_file.cpp: round trip, corruption, limits, atomic replacement.
#include "io/dvol_file.h"

#include <gtest/gtest.h>

#include <xxhash.h>
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "io/atomic_file.h"
#include "io/input_budget.h"
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
  const uint32_t v5 = kVolumeFileVersion + 1;
  std::memcpy(future.data() + 8, &v5, 4);
  rehashHeader(future);
  EXPECT_NE(parseVolumeFile(future, "x").message().find("unsupported volume file version 5"), std::string::npos);

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

// A source note makes a version 3 file; without one the file is version 2 and byte for byte as before.
TEST(DvolFile, ASourceNoteRoundTripsAndOnlyItMakesVersion3) {
  VolumeFileData d = sample();
  const std::vector<uint8_t> plain = encodeVolumeFile(d);
  uint32_t version = 0;
  std::memcpy(&version, plain.data() + 8, 4);
  EXPECT_EQ(version, 2u);
  d.source_note = "scan: tooth_2 (400 DICOM files)\nthresholds (automatic): dentin from 850 HU, enamel from 2300 HU";
  const std::vector<uint8_t> noted = encodeVolumeFile(d);
  std::memcpy(&version, noted.data() + 8, 4);
  EXPECT_EQ(version, 3u);
  // The payload and header are those of the plain file; the note follows: 16 + text + 8 bytes.
  ASSERT_EQ(noted.size(), plain.size() + 16 + d.source_note.size() + 8);
  EXPECT_TRUE(std::equal(plain.begin() + 352, plain.end(), noted.begin() + 352));
  Result<VolumeFileData> back = parseVolumeFile(noted, "x");
  ASSERT_TRUE(back) << back.message();
  EXPECT_EQ(back->source_note, d.source_note);
  EXPECT_EQ(back->bricks, d.bricks);
  // Damage to the note: its text, its length, its end.
  auto flipped = noted;
  flipped[plain.size() + 20] ^= 1;
  EXPECT_NE(parseVolumeFile(flipped, "x").message().find("source note checksum mismatch"), std::string::npos);
  auto cut = noted;
  cut.resize(cut.size() - 3);
  EXPECT_NE(parseVolumeFile(cut, "x").message().find("source note"), std::string::npos);
  auto bare = noted;
  bare.resize(plain.size());
  EXPECT_NE(parseVolumeFile(bare, "x").message().find("source note after the payload is missing"), std::string::npos);
  d.source_note = "bell\a";
  EXPECT_NE(parseVolumeFile(encodeVolumeFile(d), "x").message().find("control character"), std::string::npos);
}

// Synthesized layers make a version 4 file, its note present even when empty; a measured tooth's
// file is version 2 or 3 as before, and such a file loads as measured.
TEST(DvolFile, SynthesizedLayersRoundTripAsVersion4AndOldFilesLoadAsMeasured) {
  test::TempDir dir;
  VolumeFileData d = sample();
  const std::vector<uint8_t> measured = encodeVolumeFile(d);
  uint32_t version = 0;
  std::memcpy(&version, measured.data() + 8, 4);
  EXPECT_EQ(version, 2u);
  Result<VolumeFileData> old = parseVolumeFile(measured, "old.dvol");
  ASSERT_TRUE(old.ok()) << old.message();
  EXPECT_FALSE(old->layers_synthesized);
  EXPECT_EQ(old->layer_type, 0);

  d.layers_synthesized = true;
  d.layer_type = 1;  // molar
  ASSERT_TRUE(writeVolumeFile(dir.file("s.dvol"), d).ok());
  const std::vector<uint8_t> bytes = slurp(dir.file("s.dvol"));
  std::memcpy(&version, bytes.data() + 8, 4);
  EXPECT_EQ(version, 4u);
  EXPECT_EQ(bytes[333], 1);
  EXPECT_EQ(bytes[334], 1);
  ASSERT_EQ(bytes.size(), measured.size() + 16 + 0 + 8);  // an empty note: magic, length, checksum
  Result<VolumeFileData> back = readVolumeFile(dir.file("s.dvol"));
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(back->layers_synthesized);
  EXPECT_EQ(back->layer_type, 1);
  EXPECT_EQ(back->source_note, "");
  EXPECT_EQ(back->bricks, d.bricks);

  d.source_note = "layers synthesized from one surface";
  back = parseVolumeFile(encodeVolumeFile(d), "x");
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->source_note, d.source_note);
  EXPECT_TRUE(back->layers_synthesized);

  // A forged provenance byte or type is one line naming the file.
  auto forged = bytes;
  forged[333] = 2;
  rehashTooth(forged);
  EXPECT_EQ(parseVolumeFile(forged, "f.dvol").message(), "f.dvol: layer provenance is not 0 or 1");
  forged = bytes;
  forged[334] = kMaxLayerTypeCode + 1;
  rehashTooth(forged);
  EXPECT_EQ(parseVolumeFile(forged, "f.dvol").message(), "f.dvol: unknown synthesized tooth type 5");
  // The picker's look at the header alone agrees, and refuses what is no volume.
  Result<bool> seen = readLayersSynthesized(dir.file("s.dvol"));
  ASSERT_TRUE(seen.ok()) << seen.message();
  EXPECT_TRUE(*seen);
  test::writeBytes(dir.file("m.dvol"), measured);
  seen = readLayersSynthesized(dir.file("m.dvol"));
  ASSERT_TRUE(seen.ok()) << seen.message();
  EXPECT_FALSE(*seen);
  test::writeBytes(dir.file("x.dvol"), {'n', 'o', 't'});
  EXPECT_EQ(readLayersSynthesized(dir.file("x.dvol")).message(), dir.file("x.dvol") + ": not a dentsim volume file");
  EXPECT_FALSE(readLayersSynthesized(dir.file("missing.dvol")).ok());
  // Version 3 ignores the spare bytes: a version 3 file with them set still loads as measured.
  d.layers_synthesized = false;
  auto v3 = encodeVolumeFile(d);
  v3[333] = 1;
  rehashTooth(v3);
  back = parseVolumeFile(v3, "x");
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_FALSE(back->layers_synthesized);
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

// ---- hostile payloads and frames ----------------------------------------------------------------

// Offsets of the header fields these tests forge [B].
constexpr size_t kLevelAt = 16, kVoxelAt = 24, kScannerAt = 80, kBrickWordsAt = 192, kPackedAt = 200, kHeader = 352;

// Replaces the payload after the header and its size field, keeping the header checksum valid.
std::vector<uint8_t> withPayload(std::vector<uint8_t> bytes, const std::vector<uint8_t>& payload) {
  bytes.resize(kHeader);
  bytes.insert(bytes.end(), payload.begin(), payload.end());
  const uint64_t packed = payload.size();
  std::memcpy(bytes.data() + kPackedAt, &packed, 8);
  rehashHeader(bytes);
  return bytes;
}

// The sample's raw payload: chunk, block and brick words back to back.
std::vector<uint8_t> rawPayload(const VolumeFileData& d) {
  std::vector<uint8_t> raw;
  for (const auto* words : {&d.chunks, &d.blocks, &d.bricks}) {
    const auto* b = reinterpret_cast<const uint8_t*>(words->data());
    raw.insert(raw.end(), b, b + words->size() * 4);
  }
  return raw;
}

// `zeros` bytes of 0 as one zstd frame, compressed 1 MiB at a time so that the test never holds them.
std::vector<uint8_t> zeroFrame(size_t zeros, bool declare_size) {
  std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> cctx(ZSTD_createCCtx(), &ZSTD_freeCCtx);
  ZSTD_CCtx_setParameter(cctx.get(), ZSTD_c_contentSizeFlag, declare_size ? 1 : 0);
  if (declare_size) ZSTD_CCtx_setPledgedSrcSize(cctx.get(), zeros);
  const std::vector<uint8_t> block(size_t{1} << 20, 0);
  std::vector<uint8_t> out;
  std::vector<uint8_t> buf(ZSTD_CStreamOutSize());
  for (size_t done = 0; done < zeros || zeros == 0;) {
    const size_t n = std::min(block.size(), zeros - done);
    done += n;
    ZSTD_inBuffer in{block.data(), n, 0};
    const ZSTD_EndDirective mode = done == zeros ? ZSTD_e_end : ZSTD_e_continue;
    for (;;) {
      ZSTD_outBuffer o{buf.data(), buf.size(), 0};
      const size_t left = ZSTD_compressStream2(cctx.get(), &o, &in, mode);
      out.insert(out.end(), buf.begin(), buf.begin() + std::ptrdiff_t(o.pos));
      if (mode == ZSTD_e_end ? left == 0 : in.pos == in.size) break;
    }
    if (zeros == 0) break;
  }
  return out;
}

TEST(DvolFile, ABombsCountsAreRefusedOnTheBudgetBeforeAnythingIsAllocated) {
  // The 269 KB file: a level-13 header whose brick pool claims 7.9 GB. Before the budget it
  // cost 7.6 GB; the counts alone now refuse it, naming the flag that would allow it.
  std::vector<uint8_t> bytes = encodeVolumeFile(sample());
  const int32_t level = 13;
  std::memcpy(bytes.data() + kLevelAt, &level, 4);
  const uint64_t chunk_words = uint64_t{128} * 128 * 128;
  std::memcpy(bytes.data() + 176, &chunk_words, 8);
  const uint64_t brick_words = uint64_t{7'900'000'000} / 512 * 128;
  std::memcpy(bytes.data() + kBrickWordsAt, &brick_words, 8);
  bytes = withPayload(bytes, std::vector<uint8_t>(269'000, 0));
  const std::string m = parseVolumeFile(bytes, "bomb.dvol").message();
  EXPECT_EQ(m, "bomb.dvol: payload of 7899999744 bytes exceeds the limit of 536870912 bytes (the input budget; "
               "raise it with --max-input-mb N, in MiB)");
}

TEST(DvolFile, AFrameThatInflatesPastTheCountsIsStoppedThere) {
  // The counts and the first frame are right; a second frame of 16 MiB of zeros follows. The reader
  // fills the arrays the counts allow and stops at the first byte beyond them.
  const VolumeFileData d = sample();
  const std::vector<uint8_t> good = encodeVolumeFile(d);
  std::vector<uint8_t> payload(good.begin() + kHeader, good.end());
  const std::vector<uint8_t> extra = zeroFrame(size_t{16} << 20, true);
  EXPECT_LT(extra.size(), 2000u);  // a bomb: 16 MiB in under 2 KB
  payload.insert(payload.end(), extra.begin(), extra.end());
  EXPECT_EQ(parseVolumeFile(withPayload(good, payload), "x").message(),
            "x: compressed payload is corrupt (it inflates past the size the header gives)");
}

TEST(DvolFile, AFrameWithNoDeclaredSizeOrTooShortIsRefused) {
  const VolumeFileData d = sample();
  const std::vector<uint8_t> good = encodeVolumeFile(d);
  const std::vector<uint8_t> raw = rawPayload(d);
  std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> cctx(ZSTD_createCCtx(), &ZSTD_freeCCtx);
  ZSTD_CCtx_setParameter(cctx.get(), ZSTD_c_contentSizeFlag, 0);
  std::vector<uint8_t> unsized(ZSTD_compressBound(raw.size()));
  unsized.resize(ZSTD_compress2(cctx.get(), unsized.data(), unsized.size(), raw.data(), raw.size()));
  EXPECT_EQ(parseVolumeFile(withPayload(good, unsized), "x").message(), "x: compressed payload is corrupt (size mismatch)");
  // A frame of zeros that declares the right size but is cut short ends before the counts are met.
  std::vector<uint8_t> cut = zeroFrame(raw.size(), true);
  cut.resize(cut.size() - 4);
  EXPECT_EQ(parseVolumeFile(withPayload(good, cut), "x").message().rfind("x: compressed payload is corrupt (", 0), 0u);
}

TEST(DvolFile, AbsurdVoxelSizesAreRefusedInOneShortLine) {
  const std::vector<uint8_t> good = encodeVolumeFile(sample());
  const auto withVoxel = [&](double mm) {
    std::vector<uint8_t> b = good;
    std::memcpy(b.data() + kVoxelAt, &mm, 8);
    rehashHeader(b);
    auto r = parseVolumeFile(b, "x");
    return r.ok() ? std::string() : r.message();
  };
  EXPECT_EQ(withVoxel(1e-300), "x: voxel size 1e-300 mm is outside 1e-06 .. 100 mm");
  EXPECT_EQ(withVoxel(1e300), "x: voxel size 1e+300 mm is outside 1e-06 .. 100 mm");
  EXPECT_EQ(withVoxel(0.0), "x: voxel size 0 mm is outside 1e-06 .. 100 mm");
  EXPECT_EQ(withVoxel(-0.034), "x: voxel size -0.034 mm is outside 1e-06 .. 100 mm");
  EXPECT_EQ(withVoxel(std::nan("")), "x: voxel size nan mm is outside 1e-06 .. 100 mm");
  // The bounds themselves are sizes a file may give.
  for (double mm : {1e-6, 100.0}) {
    std::vector<uint8_t> b = good;
    std::memcpy(b.data() + kVoxelAt, &mm, 8);
    rehashHeader(b);
    EXPECT_TRUE(parseVolumeFile(b, "x").ok()) << mm;
  }
}

TEST(DvolFile, ASingularScannerMatrixIsRefused) {
  const std::vector<uint8_t> good = encodeVolumeFile(sample());
  const auto withScanner = [&](const std::array<double, 12>& m) {
    std::vector<uint8_t> b = good;
    std::memcpy(b.data() + kScannerAt, m.data(), 96);
    rehashHeader(b);
    auto r = parseVolumeFile(b, "x");
    return r.ok() ? std::string() : r.message();
  };
  const std::string singular = "x: scanner matrix is singular (its axes are zero or lie in one plane)";
  EXPECT_EQ(withScanner({}), singular);                                                // all zero
  EXPECT_EQ(withScanner({0.1, 0, 0, 0, 0, 0.1, 0, 0, 0, 0, 0, 0}), singular);          // one axis zero
  EXPECT_EQ(withScanner({0.1, 0.1, 0, 0, 0, 0, 0.1, 0, 0, 0, 0, 1}), singular);        // grid axes i and j the same
  EXPECT_EQ(withScanner({0.1, 0, 0, 0, 0, 0.1, 0, 0, 0, 0, 0.1, std::nan("")}), "x: origin or scanner matrix is not finite");
  // A flipped frame, as the CT files have, is fine.
  EXPECT_TRUE(withScanner({-0.034, 0, 0, 1, 0, -0.034, 0, 2, 0, 0, 0.034, 3}).empty());
}

}  // namespace
}  // namespace dentsim
