// Bounded, deterministic mutation fuzzing of the WAV reader: hostile bytes never crash it, accepted audio is valid, and every failure is one line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "io/wav_file.h"

#include "fuzz_mutations.h"

namespace dentsim {
namespace {

using test::pick;
using Bytes = std::vector<uint8_t>;

const std::string kWhere = "fuzz.wav";

// Tight, so that a mutated size could not make a case allocate much.
WavReadLimits fuzzLimits() {
  WavReadLimits limits;
  limits.max_bytes = 1 << 16;
  limits.max_samples = 4096;
  return limits;
}

void le16(Bytes& b, uint32_t v) {
  b.push_back(uint8_t(v));
  b.push_back(uint8_t(v >> 8));
}
void le32(Bytes& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(uint8_t(v >> (8 * i)));
}

Bytes chunk(const char* id, const Bytes& body) {
  Bytes b(id, id + 4);
  le32(b, uint32_t(body.size()));
  b.insert(b.end(), body.begin(), body.end());
  if (body.size() % 2) b.push_back(0);
  return b;
}

Bytes riff(const std::vector<Bytes>& chunks) {
  Bytes b = {'R', 'I', 'F', 'F', 0, 0, 0, 0, 'W', 'A', 'V', 'E'};
  for (const Bytes& c : chunks) b.insert(b.end(), c.begin(), c.end());
  const auto size = uint32_t(b.size() - 8);
  for (int i = 0; i < 4; ++i) b[size_t(4 + i)] = uint8_t(size >> (8 * i));
  return b;
}

Bytes fmt(uint16_t tag, int channels, uint32_t rate, int bits, bool extensible = false) {
  Bytes b;
  le16(b, extensible ? 0xFFFE : tag);
  le16(b, uint32_t(channels));
  le32(b, rate);
  le32(b, rate * uint32_t(channels * bits / 8));
  le16(b, uint32_t(channels * bits / 8));
  le16(b, uint32_t(bits));
  if (extensible) {
    le16(b, 22);
    le16(b, uint32_t(bits));
    le32(b, 0x3);
    le16(b, tag);
    const uint8_t tail[14] = {0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80, 0x00, 0x00, 0xAA, 0x00, 0x38, 0x9B, 0x71};
    b.insert(b.end(), tail, tail + 14);
  }
  return b;
}

// Three seeds: 16-bit stereo behind a LIST chunk, float mono with data first, and 24-bit
// extensible stereo with a trailing odd chunk.
std::vector<Bytes> seeds() {
  Bytes pcm16, f32, pcm24;
  for (int i = 0; i < 24; ++i) le16(pcm16, uint32_t(int16_t(i * 1000 - 12000)));
  for (int i = 0; i < 12; ++i) {
    const float v = 0.1f * float(i) - 0.6f;
    uint32_t raw;
    std::memcpy(&raw, &v, 4);
    le32(f32, raw);
  }
  for (int i = 0; i < 36; ++i) pcm24.push_back(uint8_t(i * 37));
  return {riff({chunk("LIST", {'I', 'N', 'F', 'O', 'x'}), chunk("fmt ", fmt(1, 2, 44100, 16)), chunk("data", pcm16)}),
          riff({chunk("data", f32), chunk("fmt ", fmt(3, 1, 48000, 32))}),
          riff({chunk("fmt ", fmt(1, 2, 96000, 24, true)), chunk("data", pcm24), chunk("note", {1, 2, 3})})};
}

// Offsets where a 32-bit size or a format field sits in a seed: the RIFF size, and every chunk's
// size and (for 'fmt ') its fields, found by walking the seed's chunks.
std::vector<size_t> fieldOffsets(const Bytes& seed) {
  std::vector<size_t> at = {4};
  for (size_t pos = 12; pos + 8 <= seed.size();) {
    const uint32_t size = uint32_t(seed[pos + 4] | seed[pos + 5] << 8 | seed[pos + 6] << 16 | seed[pos + 7] << 24);
    at.push_back(pos + 4);
    if (std::memcmp(&seed[pos], "fmt ", 4) == 0)
      for (size_t f : {0, 2, 4, 8, 12, 14, 16, 18, 24}) at.push_back(pos + 8 + f);
    pos += 8 + size + (size & 1);
  }
  return at;
}

// One WAV-aware change: a size or field set to an edge value, or two chunks' ids swapped.
void mutateWav(Bytes& bytes, const std::vector<size_t>& fields, std::mt19937& rng) {
  static const uint32_t kValues[] = {0, 1, 2, 3, 7, 8, 16, 22, 40, 0x7fff, 0x8000, 0xffff, 0x10000,
                                     0x7fffffff, 0x80000000, 0xfffffffe, 0xffffffff, 44100, 768001, 0xFFFE};
  const size_t at = fields[pick(rng, fields.size())];
  if (rng() % 16 == 0) return test::overwriteWithForeignMagic(bytes, rng);  // a PNG, .dses ... as WAV
  if (rng() % 5 == 0) {  // rename a chunk: 'data' to 'fmt ' and the like
    static const char* const kIds[] = {"fmt ", "data", "LIST", "RIFF", "WAVE", "\0\0\0\0"};
    if (at >= 4 && at + 4 <= bytes.size()) std::memcpy(&bytes[at - 4], kIds[rng() % std::size(kIds)], 4);
    return;
  }
  const uint32_t v = kValues[rng() % std::size(kValues)];
  const size_t width = rng() % 2 ? 4 : 2;
  for (size_t i = 0; i < width && at + i < bytes.size(); ++i) bytes[at + i] = uint8_t(v >> (8 * i));
}

void fuzzWav(uint32_t seed, int iterations) {
  const std::vector<Bytes> originals = seeds();
  for (const Bytes& s : originals) ASSERT_TRUE(parseWav(s, kWhere, fuzzLimits()).ok());
  std::mt19937 rng(seed);
  int accepted = 0, rejected = 0;
  for (int it = 0; it < iterations; ++it) {
    const Bytes& original = originals[pick(rng, originals.size())];
    const std::vector<size_t> fields = fieldOffsets(original);
    Bytes bytes = original;
    const int edits = 1 + int(rng() % 3);
    for (int e = 0; e < edits; ++e)
      if (!test::mutateBytesGeneric(bytes, rng)) mutateWav(bytes, fields, rng);
    const Result<WavAudio> r = parseWav(bytes, kWhere, fuzzLimits());
    if (!r.ok()) {
      ++rejected;
      test::assertOneLineRejection(r.message(), kWhere, it);
      if (::testing::Test::HasFatalFailure()) return;
      continue;
    }
    ++accepted;
    // What is accepted must be usable: a sane format, whole frames, samples within [-1, 1].
    ASSERT_GE(r->channels, 1) << "iteration " << it;
    ASSERT_LE(r->channels, kWavMaxChannels) << "iteration " << it;
    ASSERT_GE(r->sample_rate, kWavMinRate) << "iteration " << it;
    ASSERT_LE(r->sample_rate, kWavMaxRate) << "iteration " << it;
    ASSERT_EQ(r->samples.size() % size_t(r->channels), 0u) << "iteration " << it;
    ASSERT_LE(r->samples.size(), fuzzLimits().max_samples) << "iteration " << it;
    for (float s : r->samples) ASSERT_TRUE(std::isfinite(s) && s >= -1.0f && s <= 1.0f) << "iteration " << it;
  }
  std::printf("wav fuzz seed %u: %d accepted, %d rejected\n", seed, accepted, rejected);
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

TEST(WavFuzzTest, MutatedBytesAndFields) { fuzzWav(20240917u, 20000); }

TEST(WavFuzzTest, MutatedBytesAndFieldsOtherSeed) { fuzzWav(77u, 20000); }

}  // namespace
}  // namespace dentsim
