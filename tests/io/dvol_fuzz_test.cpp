// Bounded, deterministic mutation fuzzing of parseVolumeFile: forged counts, zstd bombs, absurd frames and foreign files never cost more than the limit, and every failure is one line.
#include <gtest/gtest.h>

#include <xxhash.h>
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "io/dvol_file.h"

#include "fuzz_mutations.h"

namespace dentsim {
namespace {

const std::string kWhere = "fuzz.dvol";
constexpr uint64_t kLimit = uint64_t{1} << 20;  // raw payload limit of every case [B]: a bomb can cost no more
constexpr size_t kHeader = 352;

using test::pick;

VolumeFileData sample(int level) {
  VolumeFileData d;
  d.frame = VolumeFrame::axisAligned(level, 0.05, {0.5, -1.0, 2.0});
  const size_t chunks = level > 6 ? size_t{1} << (3 * (level - 6)) : 1;
  d.chunks.assign(chunks, 0x80000000u);
  d.chunks[chunks - 1] = 0;  // one block
  d.blocks.assign(512, 0x80000000u | 0x3fu);
  d.blocks[9] = 0;  // one brick
  d.bricks.assign(128, 0x3f3f2122u);
  return d;
}

// 4 MiB of zeros as one zstd frame of a few hundred bytes: what a bomb appends or puts in place.
const std::vector<uint8_t>& bombFrame() {
  static const std::vector<uint8_t> frame = [] {
    const std::vector<uint8_t> zeros(size_t{4} << 20, 0);
    std::vector<uint8_t> out(ZSTD_compressBound(zeros.size()));
    out.resize(ZSTD_compress(out.data(), out.size(), zeros.data(), zeros.size(), 1));
    return out;
  }();
  return frame;
}

// Keeps both header checksums valid, so that a mutation reaches the checks behind them.
void rehash(std::vector<uint8_t>& b) {
  if (b.size() < kHeader) return;
  const uint64_t h = XXH64(b.data(), 216, 0);
  std::memcpy(b.data() + 216, &h, 8);
  const uint64_t t = XXH64(b.data() + 224, 344 - 224, 0);
  std::memcpy(b.data() + 344, &t, 8);
}

template <class T>
void put(std::vector<uint8_t>& b, size_t at, T v) {
  if (b.size() >= at + sizeof(T)) std::memcpy(b.data() + at, &v, sizeof(T));
}

// One .dvol-aware change: a word count, the level, the voxel size or a matrix entry forged; the
// payload swapped for a bomb or a bomb appended (with the size field to match); a foreign magic.
void mutateDvol(std::vector<uint8_t>& b, std::mt19937& rng) {
  static const uint64_t kCounts[] = {0, 1, 127, 128, 512, 4096, uint64_t{1} << 18, uint64_t{1} << 30,
                                     uint64_t{1} << 62, ~uint64_t{0}, (uint64_t{4} << 20) / 4};
  static const double kDoubles[] = {0.0, -1.0, 1e-300, 1e300, 1e-7, 1e-6, 100.0, 100.1, NAN, INFINITY, -0.0};
  switch (rng() % 6) {
    case 0: put<uint64_t>(b, 176 + 8 * pick(rng, 3), kCounts[pick(rng, std::size(kCounts))]); break;
    case 1: put<int32_t>(b, 16, int32_t(pick(rng, 16))); break;
    case 2: put<double>(b, rng() % 2 ? 24 : 80 + 8 * pick(rng, 12), kDoubles[pick(rng, std::size(kDoubles))]); break;
    case 3: {  // the payload becomes a bomb, or a bomb follows it
      if (b.size() < kHeader) break;
      if (rng() % 2) b.resize(kHeader);
      b.insert(b.end(), bombFrame().begin(), bombFrame().end());
      put<uint64_t>(b, 200, uint64_t(b.size() - kHeader));
      break;
    }
    case 4: test::overwriteWithForeignMagic(b, rng); break;
    default: put<uint64_t>(b, 200, uint64_t(b.size() >= kHeader ? b.size() - kHeader : 0) + pick(rng, 3) - 1); break;
  }
}

void fuzzDvol(uint32_t seed, int iterations) {
  const std::vector<std::vector<uint8_t>> originals = {encodeVolumeFile(sample(6)), encodeVolumeFile(sample(7))};
  for (const auto& o : originals) ASSERT_TRUE(parseVolumeFile(o, kWhere, kLimit).ok());
  std::mt19937 rng(seed);
  int accepted = 0, rejected = 0;
  for (int it = 0; it < iterations; ++it) {
    std::vector<uint8_t> bytes = originals[pick(rng, originals.size())];
    const int edits = 1 + int(rng() % 3);
    for (int e = 0; e < edits; ++e)
      if (!test::mutateBytesGeneric(bytes, rng)) mutateDvol(bytes, rng);
    if (rng() % 4 != 0) rehash(bytes);
    const Result<VolumeFileData> r = parseVolumeFile(bytes, kWhere, kLimit);
    if (!r.ok()) {
      ++rejected;
      test::assertOneLineRejection(r.message(), kWhere, it);
      continue;
    }
    ++accepted;
    // What is accepted fits the limit and keeps a sane frame.
    const uint64_t raw = (r->chunks.size() + r->blocks.size() + r->bricks.size()) * 4;
    ASSERT_LE(raw, kLimit) << "iteration " << it;
    ASSERT_TRUE(r->frame.voxel_mm >= kMinVoxelMm && r->frame.voxel_mm <= kMaxVoxelMm) << "iteration " << it;
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

TEST(DvolFuzzTest, MutatedHeadersPayloadsAndBombs) { fuzzDvol(27u, 4000); }
TEST(DvolFuzzTest, MutatedHeadersPayloadsAndBombsOtherSeed) { fuzzDvol(20261127u, 4000); }

}  // namespace
}  // namespace dentsim
