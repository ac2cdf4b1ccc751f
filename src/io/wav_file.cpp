// WAV reading (chunk walk, format checks, sample decoding) and the streaming 16-bit writer behind a .part file.
#include "io/wav_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "io/atomic_file.h"
#include "io/file_kind.h"
#include "io/input_budget.h"
#include "io/parse_guard.h"

namespace dentsim {
namespace {

constexpr uint16_t kFormatPcm = 0x0001;
constexpr uint16_t kFormatFloat = 0x0003;
constexpr uint16_t kFormatExtensible = 0xFFFE;
// WAVE_FORMAT_EXTENSIBLE's sub-format GUID is the format tag followed by these 14 bytes
// (KSDATAFORMAT_SUBTYPE_* in Microsoft's mmreg.h).
constexpr uint8_t kGuidTail[14] = {0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80, 0x00, 0x00, 0xAA, 0x00, 0x38, 0x9B, 0x71};
constexpr size_t kHeaderBytes = 44;  // what WavWriter writes before the samples

uint16_t u16(const uint8_t* p) { return uint16_t(p[0] | (p[1] << 8)); }
uint32_t u32(const uint8_t* p) { return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24); }

std::string chunkName(const uint8_t* p) { return quoteToken(std::string_view(reinterpret_cast<const char*>(p), 4)); }

struct Format {
  uint16_t tag = 0;  // PCM or float, after EXTENSIBLE is unwrapped
  int channels = 0;
  int sample_rate = 0;
  int block_align = 0;
  int bits = 0;  // container bits per sample
};

Result<Format> parseFormat(std::span<const uint8_t> fmt, const std::string& where) {
  if (fmt.size() < 16)
    return makeError(where, "'fmt ' chunk of " + std::to_string(fmt.size()) + " bytes is too short (16 needed)");
  const uint8_t* p = fmt.data();
  Format f;
  f.tag = u16(p);
  f.channels = u16(p + 2);
  const uint32_t rate = u32(p + 4);
  // p + 8 is the byte rate: redundant with rate * block_align, read by nothing, often wrong in
  // files written by careless tools, so it is not checked.
  f.block_align = u16(p + 12);
  f.bits = u16(p + 14);
  if (f.tag == kFormatExtensible) {
    if (fmt.size() < 40 || u16(p + 16) < 22)
      return makeError(where, "WAVE_FORMAT_EXTENSIBLE 'fmt ' chunk of " + std::to_string(fmt.size()) +
                                  " bytes is too short (40 needed)");
    const int valid_bits = u16(p + 18);
    if (valid_bits > f.bits)
      return makeError(where, std::to_string(valid_bits) + " valid bits in a " + std::to_string(f.bits) + "-bit sample");
    if (!std::equal(std::begin(kGuidTail), std::end(kGuidTail), p + 26))
      return makeError(where, "unknown WAVE_FORMAT_EXTENSIBLE sub-format");
    f.tag = u16(p + 24);
  }
  char tag_text[8];
  std::snprintf(tag_text, sizeof tag_text, "0x%04x", unsigned(f.tag));
  if (f.tag == kFormatPcm) {
    if (f.bits != 8 && f.bits != 16 && f.bits != 24 && f.bits != 32)
      return makeError(where, "unsupported PCM sample size of " + std::to_string(f.bits) + " bits (8, 16, 24, 32 read)");
  } else if (f.tag == kFormatFloat) {
    if (f.bits != 32 && f.bits != 64)
      return makeError(where, "unsupported float sample size of " + std::to_string(f.bits) + " bits (32, 64 read)");
  } else {
    return makeError(where, std::string("unsupported format tag ") + tag_text + " (only PCM and IEEE float are read)");
  }
  if (f.channels == 0) return makeError(where, "0 channels");
  if (f.channels > kWavMaxChannels)
    return makeError(where, std::to_string(f.channels) + " channels (at most " + std::to_string(kWavMaxChannels) + ")");
  if (rate < uint32_t(kWavMinRate) || rate > uint32_t(kWavMaxRate))
    return makeError(where, "absurd sample rate of " + std::to_string(rate) + " Hz (" + std::to_string(kWavMinRate) +
                                " to " + std::to_string(kWavMaxRate) + " read)");
  f.sample_rate = int(rate);
  if (f.block_align != f.channels * f.bits / 8)
    return makeError(where, "block align of " + std::to_string(f.block_align) + " bytes does not match " +
                                std::to_string(f.channels) + " channels of " + std::to_string(f.bits) + " bits");
  return f;
}

// Decodes little-endian samples into [-1, 1]. Integers scale by the full range of their container,
// so a 20-in-24-bit sample (left-justified, as the format requires) reads the same way.
Status decode(std::span<const uint8_t> data, const Format& f, std::vector<float>& out, const std::string& where) {
  const size_t bytes_per = size_t(f.bits / 8);
  const size_t count = data.size() / bytes_per;
  out.resize(count);
  const uint8_t* p = data.data();
  for (size_t i = 0; i < count; ++i, p += bytes_per) {
    double v = 0.0;
    if (f.tag == kFormatPcm) {
      switch (f.bits) {
        case 8: v = (double(p[0]) - 128.0) / 128.0; break;
        case 16: v = double(int16_t(u16(p))) / 32768.0; break;
        case 24: {
          int32_t s = int32_t(uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16));
          if (s & 0x800000) s -= 0x1000000;
          v = double(s) / 8388608.0;
          break;
        }
        default: v = double(int32_t(u32(p))) / 2147483648.0; break;
      }
    } else {
      if (f.bits == 32) {
        float x;
        const uint32_t raw = u32(p);
        std::memcpy(&x, &raw, 4);
        v = double(x);
      } else {
        const uint64_t raw = uint64_t(u32(p)) | (uint64_t(u32(p + 4)) << 32);
        std::memcpy(&v, &raw, 8);
      }
      if (!std::isfinite(v))
        return makeError(where, "sample " + std::to_string(i) + " is not a finite number");
    }
    out[i] = float(std::clamp(v, -1.0, 1.0));
  }
  return Ok{};
}

Result<WavAudio> parseWavUnguarded(std::span<const uint8_t> bytes, const std::string& where, const WavReadLimits& limits) {
  const uint64_t size = bytes.size();
  if (size > limits.max_bytes)
    return makeError(where, "file of " + std::to_string(size) + " bytes exceeds the limit of " +
                                std::to_string(limits.max_bytes) + " bytes");
  if (size < 12) return makeError(where, "truncated: " + std::to_string(size) + " bytes, a WAV header needs 12");
  const uint8_t* b = bytes.data();
  if (std::memcmp(b, "RIFX", 4) == 0) return makeError(where, "big-endian (RIFX) WAV files are not supported");
  if (std::memcmp(b, "RF64", 4) == 0) return makeError(where, "RF64 WAV files are not supported");
  if (std::memcmp(b, "RIFF", 4) != 0) {
    if (auto other = refuseOtherKind(bytes, FileKind::Wav, where, "a WAV sound")) return *other;
    return makeError(where, "not a WAV file (no RIFF header)");
  }
  if (std::memcmp(b + 8, "WAVE", 4) != 0) return makeError(where, "a RIFF file of type " + chunkName(b + 8) + ", not WAVE");
  const uint64_t riff_size = u32(b + 4);
  if (riff_size < 4) return makeError(where, "RIFF size of " + std::to_string(riff_size) + " bytes is too small");
  if (riff_size + 8 > size)
    return makeError(where, "truncated: the RIFF header promises " + std::to_string(riff_size + 8) +
                                " bytes, the file has " + std::to_string(size));
  const uint64_t end = riff_size + 8;  // bytes after the RIFF data are not ours to read

  // Walk the chunks, remembering where 'fmt ' and 'data' are; everything else is skipped.
  std::span<const uint8_t> fmt, data;
  bool have_fmt = false, have_data = false;
  uint64_t pos = 12;
  while (pos + 8 <= end) {
    const uint8_t* head = b + pos;
    const uint64_t chunk = u32(head + 4);
    const uint64_t body = pos + 8;
    if (chunk > end - body)
      return makeError(where, "truncated: chunk " + chunkName(head) + " of " + std::to_string(chunk) + " bytes at byte " +
                                  std::to_string(pos) + " runs past the end (" + std::to_string(end - body) + " bytes left)");
    const std::span<const uint8_t> content = bytes.subspan(size_t(body), size_t(chunk));
    if (std::memcmp(head, "fmt ", 4) == 0) {
      if (have_fmt) return makeError(where, "two 'fmt ' chunks");
      fmt = content;
      have_fmt = true;
    } else if (std::memcmp(head, "data", 4) == 0) {
      if (have_data) return makeError(where, "two 'data' chunks");
      data = content;
      have_data = true;
    }
    pos = body + chunk + (chunk & 1);  // odd chunks are padded to even; a last one may lack its pad
  }
  if (pos < end)
    return makeError(where, "truncated: " + std::to_string(end - pos) + " bytes at byte " + std::to_string(pos) +
                                " are too few for a chunk header");
  if (!have_fmt) return makeError(where, "no 'fmt ' chunk");
  if (!have_data) return makeError(where, "no 'data' chunk");

  Result<Format> format = parseFormat(fmt, where);
  if (!format.ok()) return format.error();
  const Format& f = *format;
  if (data.size() % size_t(f.block_align) != 0)
    return makeError(where, "'data' chunk of " + std::to_string(data.size()) + " bytes is not a whole number of " +
                                std::to_string(f.block_align) + "-byte frames");
  const uint64_t samples = data.size() / size_t(f.bits / 8);
  if (samples > limits.max_samples)
    return makeError(where, std::to_string(samples) + " samples exceed the limit of " + std::to_string(limits.max_samples));

  WavAudio audio;
  audio.sample_rate = f.sample_rate;
  audio.channels = f.channels;
  Status decoded = decode(data, f, audio.samples, where);
  if (!decoded.ok()) return decoded.error();
  return audio;
}

void putU16(uint8_t* p, uint32_t v) {
  p[0] = uint8_t(v);
  p[1] = uint8_t(v >> 8);
}
void putU32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = uint8_t(v >> (8 * i));
}

std::string errnoText() { return std::strerror(errno); }

}  // namespace

Result<WavAudio> parseWav(std::span<const uint8_t> bytes, const std::string& where, const WavReadLimits& limits) {
  return guardParse<WavAudio>(where, bytes.size(), [&] { return parseWavUnguarded(bytes, where, limits); }, "the WAV file");
}

Result<WavAudio> readWav(const std::string& path, const WavReadLimits& limits) {
  Result<std::vector<uint8_t>> bytes = readFileBytes(path, std::min(limits.max_bytes, inputBudget().max_bytes));
  if (!bytes.ok()) return bytes.error();
  return parseWav(*bytes, path, limits);
}

// ---- WavWriter ----------------------------------------------------------------------------------

struct WavWriter::State {
  std::string path;
  std::string part;           // path + ".part", where the samples go until finish()
  std::FILE* file = nullptr;  // open until finish() or the destructor
  int channels = 0;
  int sample_rate = 0;
  uint64_t frames = 0;
  std::vector<uint8_t> buffer;  // one batch of converted samples
};

WavWriter::WavWriter(std::unique_ptr<State> state) : state_(std::move(state)) {}
WavWriter::WavWriter(WavWriter&&) noexcept = default;

// An unfinished writer's .part is removed: what it held was never a complete file.
static void abandon(std::FILE*& file, const std::string& part) {
  if (file == nullptr) return;
  std::fclose(file);
  file = nullptr;
  discardTemporary(part);
}

WavWriter& WavWriter::operator=(WavWriter&& other) noexcept {
  if (this != &other) {
    if (state_) abandon(state_->file, state_->part);
    state_ = std::move(other.state_);
  }
  return *this;
}

WavWriter::~WavWriter() {
  if (state_) abandon(state_->file, state_->part);
}

Result<WavWriter> WavWriter::create(const std::string& path, int channels, int sample_rate) {
  if (channels < 1 || channels > kWavMaxChannels)
    return makeError(path, "cannot write a WAV file of " + std::to_string(channels) + " channels");
  if (sample_rate < kWavMinRate || sample_rate > kWavMaxRate)
    return makeError(path, "cannot write a WAV file at " + std::to_string(sample_rate) + " Hz");
  auto state = std::make_unique<State>();
  state->path = path;
  state->part = path + ".part";
  state->channels = channels;
  state->sample_rate = sample_rate;
  state->file = std::fopen(state->part.c_str(), "wb");
  if (state->file == nullptr) return makeError(path, "cannot create " + state->part + ": " + errnoText());
  // The sizes stay 0 until finish() knows them.
  uint8_t h[kHeaderBytes] = {};
  std::memcpy(h, "RIFF", 4);
  std::memcpy(h + 8, "WAVEfmt ", 8);
  putU32(h + 16, 16);
  putU16(h + 20, kFormatPcm);
  putU16(h + 22, uint32_t(channels));
  putU32(h + 24, uint32_t(sample_rate));
  putU32(h + 28, uint32_t(sample_rate * channels * 2));
  putU16(h + 32, uint32_t(channels * 2));
  putU16(h + 34, 16);
  std::memcpy(h + 36, "data", 4);
  WavWriter writer(std::move(state));
  if (std::fwrite(h, 1, sizeof h, writer.state_->file) != sizeof h)
    return makeError(path, "cannot write " + shownPath(writer.state_->part) + ": " + errnoText());
  return writer;
}

Status WavWriter::append(std::span<const float> interleaved) {
  if (!state_ || state_->file == nullptr) return makeError(state_ ? state_->path : "", "WAV writer already finished");
  State& s = *state_;
  if (interleaved.size() % size_t(s.channels) != 0)
    return makeError(s.path, std::to_string(interleaved.size()) + " samples are not whole frames of " +
                                 std::to_string(s.channels) + " channels");
  // RIFF sizes are 32-bit: the data must fit under 4 GiB with the header.
  const uint64_t data_bytes = (s.frames * uint64_t(s.channels) + interleaved.size()) * 2;
  if (data_bytes > 0xFFFFFFFFull - (kHeaderBytes - 8))
    return makeError(s.path, "WAV data would exceed the format's 4 GiB limit");
  constexpr size_t kBatch = 4096;
  s.buffer.resize(kBatch * 2);
  for (size_t start = 0; start < interleaved.size(); start += kBatch) {
    const size_t n = std::min(kBatch, interleaved.size() - start);
    for (size_t i = 0; i < n; ++i) {
      const float x = interleaved[start + i];
      const double clamped = std::isnan(x) ? 0.0 : std::clamp(double(x), -1.0, 1.0);
      // Rounded to nearest, with +1 mapping to 32767 so that the scale stays that of the reader.
      const auto q = int16_t(std::clamp(std::lround(clamped * 32768.0), -32768L, 32767L));
      putU16(s.buffer.data() + 2 * i, uint16_t(q));
    }
    if (std::fwrite(s.buffer.data(), 2, n, s.file) != n) return makeError(s.path, "cannot write " + shownPath(s.part) + ": " + errnoText());
  }
  s.frames += interleaved.size() / size_t(s.channels);
  return Ok{};
}

Status WavWriter::finish() {
  if (!state_ || state_->file == nullptr) return makeError(state_ ? state_->path : "", "WAV writer already finished");
  State& s = *state_;
  const auto data_bytes = uint32_t(s.frames * uint64_t(s.channels) * 2);
  uint8_t size[4];
  bool ok = true;
  putU32(size, uint32_t(kHeaderBytes - 8) + data_bytes);
  ok = ok && std::fseek(s.file, 4, SEEK_SET) == 0 && std::fwrite(size, 1, 4, s.file) == 4;
  putU32(size, data_bytes);
  ok = ok && std::fseek(s.file, 40, SEEK_SET) == 0 && std::fwrite(size, 1, 4, s.file) == 4;
  ok = ok && std::fflush(s.file) == 0;
  const std::string why = ok ? "" : errnoText();
  const bool closed = std::fclose(s.file) == 0;
  s.file = nullptr;
  if (!ok || !closed) {
    discardTemporary(s.part);
    return makeError(s.path, "cannot finish " + s.part + ": " + (ok ? errnoText() : why));
  }
  // fsync, then rename over PATH.
  return commitTemporary(s.part, s.path);
}

uint64_t WavWriter::frames() const { return state_ ? state_->frames : 0; }

}  // namespace dentsim
