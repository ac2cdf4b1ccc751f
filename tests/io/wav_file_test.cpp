// Tests of the WAV reader on hand-built files of every format variant and of bad files, and of the streaming writer's bytes and its .part semantics.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "io/wav_file.h"
#include "test_support.h"

namespace dentsim {
namespace {

using Bytes = std::vector<uint8_t>;

void le16(Bytes& b, uint32_t v) {
  b.push_back(uint8_t(v));
  b.push_back(uint8_t(v >> 8));
}
void le32(Bytes& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(uint8_t(v >> (8 * i)));
}

Bytes chunk(const char* id, const Bytes& body, bool pad = true) {
  Bytes b(id, id + 4);
  le32(b, uint32_t(body.size()));
  b.insert(b.end(), body.begin(), body.end());
  if (pad && body.size() % 2) b.push_back(0);
  return b;
}

Bytes riff(const std::vector<Bytes>& chunks) {
  Bytes body = {'W', 'A', 'V', 'E'};
  for (const Bytes& c : chunks) body.insert(body.end(), c.begin(), c.end());
  Bytes b = {'R', 'I', 'F', 'F'};
  le32(b, uint32_t(body.size()));
  b.insert(b.end(), body.begin(), body.end());
  return b;
}

Bytes fmt(uint16_t tag, int channels, uint32_t rate, int bits, int block_align = -1) {
  Bytes b;
  le16(b, tag);
  le16(b, uint32_t(channels));
  le32(b, rate);
  const int align = block_align >= 0 ? block_align : channels * bits / 8;
  le32(b, rate * uint32_t(align));
  le16(b, uint32_t(align));
  le16(b, uint32_t(bits));
  return b;
}

// WAVE_FORMAT_EXTENSIBLE: the plain 16 bytes, cbSize 22, valid bits, channel mask, sub-format GUID.
Bytes fmtExtensible(uint16_t sub_tag, int channels, uint32_t rate, int bits, int valid_bits) {
  Bytes b = fmt(0xFFFE, channels, rate, bits);
  le16(b, 22);
  le16(b, uint32_t(valid_bits));
  le32(b, channels == 1 ? 0x4 : 0x3);
  le16(b, sub_tag);
  const uint8_t tail[14] = {0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80, 0x00, 0x00, 0xAA, 0x00, 0x38, 0x9B, 0x71};
  b.insert(b.end(), tail, tail + 14);
  return b;
}

Bytes floats(std::initializer_list<float> values) {
  Bytes b;
  for (float v : values) {
    uint32_t raw;
    std::memcpy(&raw, &v, 4);
    le32(b, raw);
  }
  return b;
}

WavAudio parsed(const Bytes& bytes) {
  Result<WavAudio> r = parseWav(bytes, "test.wav");
  EXPECT_TRUE(r.ok()) << r.message();
  return r.ok() ? *r : WavAudio{};
}

// ---- Format variants ----------------------------------------------------------------------------

TEST(WavReadTest, Pcm8IsUnsignedAroundMidScale) {
  const WavAudio a = parsed(riff({chunk("fmt ", fmt(1, 1, 8000, 8)), chunk("data", {0, 128, 255, 64})}));
  EXPECT_EQ(a.sample_rate, 8000);
  EXPECT_EQ(a.channels, 1);
  EXPECT_EQ(a.samples, (std::vector<float>{-1.0f, 0.0f, 127.0f / 128, -0.5f}));
}

TEST(WavReadTest, Pcm16Stereo) {
  Bytes data;
  for (uint32_t v : {0x8000u, 0x7fffu, 0x4000u, 0xc000u}) le16(data, v);
  const WavAudio a = parsed(riff({chunk("fmt ", fmt(1, 2, 44100, 16)), chunk("data", data)}));
  EXPECT_EQ(a.channels, 2);
  EXPECT_EQ(a.samples, (std::vector<float>{-1.0f, 32767.0f / 32768, 0.5f, -0.5f}));
}

TEST(WavReadTest, Pcm24And32) {
  const Bytes d24 = {0x00, 0x00, 0x80, 0x00, 0x00, 0x40, 0xff, 0xff, 0xff};  // -2^23, 2^22, -1
  EXPECT_EQ(parsed(riff({chunk("fmt ", fmt(1, 1, 96000, 24)), chunk("data", d24)})).samples,
            (std::vector<float>{-1.0f, 0.5f, float(-1.0 / 8388608)}));
  Bytes d32;
  le32(d32, 0x80000000u);
  le32(d32, 0x40000000u);
  EXPECT_EQ(parsed(riff({chunk("fmt ", fmt(1, 1, 48000, 32)), chunk("data", d32)})).samples,
            (std::vector<float>{-1.0f, 0.5f}));
}

TEST(WavReadTest, Float32And64ClampedToUnitRange) {
  EXPECT_EQ(parsed(riff({chunk("fmt ", fmt(3, 1, 48000, 32)), chunk("data", floats({0.25f, -0.5f, 2.0f, -3.0f}))})).samples,
            (std::vector<float>{0.25f, -0.5f, 1.0f, -1.0f}));
  Bytes d64;
  for (double v : {0.125, -0.75}) {
    uint64_t raw;
    std::memcpy(&raw, &v, 8);
    le32(d64, uint32_t(raw));
    le32(d64, uint32_t(raw >> 32));
  }
  EXPECT_EQ(parsed(riff({chunk("fmt ", fmt(3, 1, 48000, 64)), chunk("data", d64)})).samples,
            (std::vector<float>{0.125f, -0.75f}));
}

TEST(WavReadTest, ExtensiblePcmAndFloat) {
  // 20 valid bits in a 24-bit container, left-justified: 0x400000 is still half scale.
  const Bytes d24 = {0x00, 0x00, 0x40, 0x00, 0x00, 0xc0};
  const WavAudio pcm = parsed(riff({chunk("fmt ", fmtExtensible(1, 2, 48000, 24, 20)), chunk("data", d24)}));
  EXPECT_EQ(pcm.channels, 2);
  EXPECT_EQ(pcm.samples, (std::vector<float>{0.5f, -0.5f}));
  EXPECT_EQ(parsed(riff({chunk("fmt ", fmtExtensible(3, 1, 22050, 32, 32)), chunk("data", floats({-0.25f}))})).samples,
            (std::vector<float>{-0.25f}));
}

TEST(WavReadTest, ChunksInAnyOrderUnknownOnesSkippedOddSizesPadded) {
  const Bytes list = {'I', 'N', 'F', 'O', 'a', 'b', 'c'};  // 7 bytes: padded to 8
  Bytes data;
  le16(data, 0x4000);
  // data before fmt, an odd LIST between, a 'fact' chunk after.
  const Bytes bytes = riff({chunk("data", data), chunk("LIST", list), chunk("fmt ", fmt(1, 1, 16000, 16)),
                            chunk("fact", {1, 0, 0, 0})});
  const WavAudio a = parsed(bytes);
  EXPECT_EQ(a.sample_rate, 16000);
  EXPECT_EQ(a.samples, (std::vector<float>{0.5f}));
  // The last chunk may lack its pad byte; bytes after the RIFF data are not read.
  Bytes last_odd = riff({chunk("fmt ", fmt(1, 1, 16000, 16)), chunk("data", data), chunk("junk", {1, 2, 3}, false)});
  EXPECT_EQ(parsed(last_odd).samples.size(), 1u);
  last_odd.insert(last_odd.end(), {'g', 'a', 'r', 'b', 'a', 'g', 'e'});
  EXPECT_EQ(parsed(last_odd).samples.size(), 1u);
  // An empty data chunk is a valid, empty sound.
  EXPECT_TRUE(parsed(riff({chunk("fmt ", fmt(1, 1, 16000, 16)), chunk("data", {})})).samples.empty());
}

// ---- Bad files ----------------------------------------------------------------------------------

void expectRejected(const Bytes& bytes, const std::string& problem, const WavReadLimits& limits = {}) {
  const Result<WavAudio> r = parseWav(bytes, "bad.wav", limits);
  ASSERT_FALSE(r.ok()) << "accepted; expected: " << problem;
  EXPECT_EQ(r.message().rfind("bad.wav: ", 0), 0u) << r.message();
  EXPECT_NE(r.message().find(problem), std::string::npos) << r.message();
  EXPECT_EQ(r.message().find('\n'), std::string::npos) << r.message();
}

TEST(WavReadTest, BadFilesAreOneLineErrors) {
  const Bytes data16 = {0, 0, 0, 0};
  const Bytes good_fmt = chunk("fmt ", fmt(1, 1, 48000, 16));
  expectRejected({}, "truncated");
  expectRejected({'R', 'I', 'F', 'F'}, "truncated");
  expectRejected(Bytes{'R', 'I', 'F', 'X', 4, 0, 0, 0, 'W', 'A', 'V', 'E'}, "RIFX");
  expectRejected(Bytes{'O', 'g', 'g', 'S', 4, 0, 0, 0, 'W', 'A', 'V', 'E'}, "not a WAV file");
  expectRejected(Bytes{'R', 'I', 'F', 'F', 4, 0, 0, 0, 'A', 'V', 'I', ' '}, "not WAVE");
  // The RIFF size promises more than the file holds.
  Bytes cut = riff({good_fmt, chunk("data", data16)});
  cut.resize(cut.size() - 2);
  expectRejected(cut, "truncated: the RIFF header promises");
  // A chunk's size runs past the RIFF data.
  Bytes lying = riff({good_fmt, chunk("data", data16)});
  lying[lying.size() - 8] = 0xff;  // the data chunk's size, low byte: 255 bytes in a 4-byte chunk
  expectRejected(lying, "chunk \"data\" of 255 bytes");
  Bytes stray = riff({good_fmt, chunk("data", data16)});
  stray.insert(stray.end(), {1, 2, 3});
  stray[4] = uint8_t(stray[4] + 3);
  expectRejected(stray, "too few for a chunk header");
  expectRejected(riff({chunk("data", data16)}), "no 'fmt ' chunk");
  expectRejected(riff({good_fmt}), "no 'data' chunk");
  expectRejected(riff({good_fmt, good_fmt, chunk("data", data16)}), "two 'fmt ' chunks");
  expectRejected(riff({good_fmt, chunk("data", data16), chunk("data", data16)}), "two 'data' chunks");
  expectRejected(riff({chunk("fmt ", Bytes(14, 1)), chunk("data", data16)}), "too short");
  expectRejected(riff({chunk("fmt ", fmt(1, 0, 48000, 16)), chunk("data", data16)}), "0 channels");
  expectRejected(riff({chunk("fmt ", fmt(1, 100, 48000, 16)), chunk("data", data16)}), "100 channels");
  expectRejected(riff({chunk("fmt ", fmt(1, 1, 0, 16)), chunk("data", data16)}), "absurd sample rate of 0 Hz");
  expectRejected(riff({chunk("fmt ", fmt(1, 1, 5000000, 16)), chunk("data", data16)}), "absurd sample rate");
  expectRejected(riff({chunk("fmt ", fmt(1, 1, 48000, 12, 2)), chunk("data", data16)}), "12 bits");
  expectRejected(riff({chunk("fmt ", fmt(2, 1, 48000, 4, 0)), chunk("data", data16)}), "format tag 0x0002");
  expectRejected(riff({chunk("fmt ", fmt(3, 1, 48000, 16)), chunk("data", data16)}), "float sample size");
  expectRejected(riff({chunk("fmt ", fmt(1, 2, 48000, 16, 2)), chunk("data", data16)}), "block align");
  Bytes ext = fmtExtensible(1, 1, 48000, 16, 16);
  ext.back() ^= 1;
  expectRejected(riff({chunk("fmt ", ext), chunk("data", data16)}), "sub-format");
  Bytes short_ext = fmtExtensible(1, 1, 48000, 16, 16);
  short_ext.resize(30);
  expectRejected(riff({chunk("fmt ", short_ext), chunk("data", data16)}), "EXTENSIBLE");
  expectRejected(riff({chunk("fmt ", fmtExtensible(1, 1, 48000, 16, 24)), chunk("data", data16)}), "24 valid bits");
  expectRejected(riff({chunk("fmt ", fmt(1, 2, 48000, 16)), chunk("data", {0, 0, 0, 0, 0, 0})}), "whole number");
  expectRejected(riff({chunk("fmt ", fmt(3, 1, 48000, 32)),
                       chunk("data", floats({0.5f, std::numeric_limits<float>::quiet_NaN()}))}),
                 "sample 1 is not a finite number");
  WavReadLimits small;
  small.max_samples = 1;
  expectRejected(riff({good_fmt, chunk("data", data16)}), "2 samples exceed the limit of 1", small);
  small.max_bytes = 10;
  expectRejected(riff({good_fmt, chunk("data", data16)}), "exceeds the limit of 10 bytes", small);
}

// ---- Files and the writer -----------------------------------------------------------------------

class WavFileTest : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return dir_.file(name); }
  test::TempDir dir_;
};

TEST_F(WavFileTest, RoundTripWithin16BitQuantization) {
  const std::string out = path("round.wav");
  Result<WavWriter> w = WavWriter::create(out, 2, 44100);
  ASSERT_TRUE(w.ok()) << w.message();
  std::vector<float> all;
  for (int part = 0; part < 3; ++part) {  // three appends of different lengths
    std::vector<float> x(size_t(2 * (100 + 37 * part)));
    for (size_t i = 0; i < x.size(); ++i) x[i] = float(0.9 * std::sin(0.01 * double(all.size() + i)));
    ASSERT_TRUE(w->append(x).ok());
    all.insert(all.end(), x.begin(), x.end());
  }
  const std::vector<float> edges = {1.0f, -1.0f, 0.0f, 2.0f, -7.0f, std::numeric_limits<float>::quiet_NaN()};
  ASSERT_TRUE(w->append(edges).ok());
  EXPECT_EQ(w->frames(), all.size() / 2 + 3);
  ASSERT_TRUE(w->finish().ok());
  EXPECT_FALSE(std::filesystem::exists(out + ".part"));

  // The header, byte by byte: 44 bytes, RIFF size 36 + data, 16-bit PCM.
  const Bytes bytes = test::readBytes(out);
  const uint32_t data_bytes = uint32_t((all.size() + edges.size()) * 2);
  ASSERT_EQ(bytes.size(), 44u + data_bytes);
  const auto u32 = [&](size_t at) { return uint32_t(bytes[at] | bytes[at + 1] << 8 | bytes[at + 2] << 16 | bytes[at + 3] << 24); };
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "RIFF");
  EXPECT_EQ(u32(4), 36 + data_bytes);
  EXPECT_EQ(u32(24), 44100u);
  EXPECT_EQ(u32(28), 44100u * 4);
  EXPECT_EQ(u32(40), data_bytes);

  Result<WavAudio> back = readWav(out);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->channels, 2);
  EXPECT_EQ(back->sample_rate, 44100);
  ASSERT_EQ(back->samples.size(), all.size() + edges.size());
  for (size_t i = 0; i < all.size(); ++i) ASSERT_NEAR(back->samples[i], all[i], 0.5 / 32768 + 1e-9) << i;
  const size_t e = all.size();
  EXPECT_EQ(back->samples[e + 0], 32767.0f / 32768);  // +1 clamps to the largest code
  EXPECT_EQ(back->samples[e + 1], -1.0f);
  EXPECT_EQ(back->samples[e + 2], 0.0f);
  EXPECT_EQ(back->samples[e + 3], 32767.0f / 32768);
  EXPECT_EQ(back->samples[e + 4], -1.0f);
  EXPECT_EQ(back->samples[e + 5], 0.0f);  // NaN is written as silence
}

TEST_F(WavFileTest, UnfinishedWriterLeavesNoFileAndKeepsTheOldOne) {
  const std::string out = path("part.wav");
  {
    Result<WavWriter> w = WavWriter::create(out, 1, 48000);
    ASSERT_TRUE(w.ok());
    ASSERT_TRUE(w->append(std::vector<float>(100, 0.5f)).ok());
    EXPECT_TRUE(std::filesystem::exists(out + ".part"));
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  EXPECT_FALSE(std::filesystem::exists(out + ".part"));
  EXPECT_FALSE(std::filesystem::exists(out));

  // A finished file is not touched by a later writer that never finishes.
  {
    Result<WavWriter> w = WavWriter::create(out, 1, 48000);
    ASSERT_TRUE(w.ok());
    ASSERT_TRUE(w->append(std::vector<float>(10, 0.25f)).ok());
    ASSERT_TRUE(w->finish().ok());
  }
  const Bytes finished = test::readBytes(out);
  {
    Result<WavWriter> w = WavWriter::create(out, 1, 48000);
    ASSERT_TRUE(w.ok());
    ASSERT_TRUE(w->append(std::vector<float>(1000, -0.25f)).ok());
  }
  EXPECT_EQ(test::readBytes(out), finished);
  EXPECT_FALSE(std::filesystem::exists(out + ".part"));
}

TEST_F(WavFileTest, MovedWritersCleanUpOnce) {
  const std::string a = path("a.wav"), b = path("b.wav");
  Result<WavWriter> wa = WavWriter::create(a, 1, 48000);
  Result<WavWriter> wb = WavWriter::create(b, 1, 48000);
  ASSERT_TRUE(wa.ok() && wb.ok());
  WavWriter moved = std::move(*wa);
  ASSERT_TRUE(moved.append(std::vector<float>(4, 0.1f)).ok());
  EXPECT_EQ(moved.frames(), 4u);
  EXPECT_EQ(wa->frames(), 0u);
  EXPECT_FALSE(wa->append(std::vector<float>(1, 0.f)).ok());  // the moved-from writer is spent
  // Assigning over a writer abandons what it was writing.
  moved = std::move(*wb);
  EXPECT_FALSE(std::filesystem::exists(a + ".part"));
  EXPECT_TRUE(std::filesystem::exists(b + ".part"));
  ASSERT_TRUE(moved.finish().ok());
  EXPECT_TRUE(std::filesystem::exists(b));
  EXPECT_FALSE(std::filesystem::exists(a));
}

TEST_F(WavFileTest, WriterErrors) {
  EXPECT_FALSE(WavWriter::create(path("x.wav"), 0, 48000).ok());
  EXPECT_FALSE(WavWriter::create(path("x.wav"), 1, 10).ok());
  const std::string nowhere = path("no/such/dir/x.wav");
  Result<WavWriter> bad = WavWriter::create(nowhere, 1, 48000);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.message().rfind(nowhere + ": cannot create", 0), 0u) << bad.message();
  Result<WavWriter> w = WavWriter::create(path("y.wav"), 2, 48000);
  ASSERT_TRUE(w.ok());
  EXPECT_FALSE(w->append(std::vector<float>(3, 0.f)).ok());  // not whole stereo frames
  ASSERT_TRUE(w->finish().ok());
  EXPECT_FALSE(w->finish().ok());
  EXPECT_FALSE(w->append(std::vector<float>(2, 0.f)).ok());
  // An empty finished file is a valid, empty WAV.
  Result<WavAudio> empty = readWav(path("y.wav"));
  ASSERT_TRUE(empty.ok()) << empty.message();
  EXPECT_TRUE(empty->samples.empty());
}

TEST_F(WavFileTest, ReadErrorsNameThePath) {
  const std::string missing = path("missing.wav");
  Result<WavAudio> r = readWav(missing);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message().rfind(missing + ": cannot open", 0), 0u) << r.message();
  const std::string text = path("text.wav");
  std::ofstream(text) << "hello";
  r = readWav(text);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), text + ": truncated: 5 bytes, a WAV header needs 12");
}

}  // namespace
}  // namespace dentsim
