// WAV files: a reader for RIFF WAVE (PCM 8/16/24/32-bit, IEEE float, WAVE_FORMAT_EXTENSIBLE) and a streaming 16-bit writer that only ever shows a finished file.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"

namespace dentsim {

struct WavAudio {
  int sample_rate = 0;         // [Hz]
  int channels = 0;            // interleaved in `samples`
  std::vector<float> samples;  // (frames x channels), within [-1, 1]
};

// What a reader refuses to take in.
struct WavReadLimits {
  uint64_t max_bytes = uint64_t{1} << 30;    // size of the file [bytes]
  uint64_t max_samples = uint64_t{1} << 27;  // samples over all channels (512 MiB of floats)
};
inline constexpr int kWavMaxChannels = 64;
inline constexpr int kWavMinRate = 1000;    // [Hz]
inline constexpr int kWavMaxRate = 768000;  // [Hz]

// RIFF chunks in any order (unknown ones skipped, odd sizes padded); PCM 8-bit unsigned and
// 16/24/32-bit signed, 32/64-bit IEEE float (clamped to [-1, 1]; NaN or infinity refused),
// and either as WAVE_FORMAT_EXTENSIBLE. Errors are one line naming the file and the problem.
Result<WavAudio> readWav(const std::string& path, const WavReadLimits& limits = {});
Result<WavAudio> parseWav(std::span<const uint8_t> bytes, const std::string& where, const WavReadLimits& limits = {});

// 16-bit PCM, streamed to PATH.part, renamed to PATH by finish() (atomic: a crash never leaves a
// half file under PATH). Two writers must not write the same PATH at once.
class WavWriter {
 public:
  static Result<WavWriter> create(const std::string& path, int channels, int sample_rate);
  // Appends whole frames (size a multiple of channels); clamps to [-1, 1], NaN written as 0.
  Status append(std::span<const float> interleaved);
  // Patches the RIFF sizes, fsyncs, renames. The writer is spent afterwards.
  Status finish();
  uint64_t frames() const;

  WavWriter(WavWriter&&) noexcept;
  WavWriter& operator=(WavWriter&&) noexcept;
  WavWriter(const WavWriter&) = delete;
  WavWriter& operator=(const WavWriter&) = delete;
  // An unfinished writer removes PATH.part.
  ~WavWriter();

 private:
  struct State;
  explicit WavWriter(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace dentsim
