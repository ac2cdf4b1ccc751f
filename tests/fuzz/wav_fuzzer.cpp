// libFuzzer entry for the WAV reader: the input is parsed in memory, and accepted audio must be whole frames of finite samples within [-1, 1].
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "io/wav_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dentsim::WavReadLimits limits;
  limits.max_samples = uint64_t{1} << 20;  // a lying size must not make the fuzzer run out of memory
  const auto wav = dentsim::parseWav(std::span(data, size), "fuzz.wav", limits);
  if (!wav.ok()) {
    if (wav.message().rfind("fuzz.wav: ", 0) != 0) std::abort();
    for (char c : wav.message())
      if (c == '\n' || c == '\r') std::abort();
    return 0;
  }
  if (wav->channels < 1 || wav->channels > dentsim::kWavMaxChannels) std::abort();
  if (wav->sample_rate < dentsim::kWavMinRate || wav->sample_rate > dentsim::kWavMaxRate) std::abort();
  if (wav->samples.size() % size_t(wav->channels) != 0 || wav->samples.size() > limits.max_samples) std::abort();
  for (float s : wav->samples)
    if (!std::isfinite(s) || s < -1.0f || s > 1.0f) std::abort();
  return 0;
}
