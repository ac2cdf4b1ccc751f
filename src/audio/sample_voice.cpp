// A recorded WAV played in place of a synthesized voice: looped with a cross-faded seam, pitch-shifted by the rotor's speed or made louder by the removal.
#include <algorithm>
#include <cmath>
#include <vector>

#include "audio/voices.h"
#include "io/wav_file.h"

namespace dentsim::audio {
namespace {

constexpr size_t kMinFrames = 64;        // shorter than this, a loop is a buzz, not a sound
constexpr double kMaxCrossFadeS = 0.05;  // the seam's cross-fade [s], at most a quarter of the sample

// The sample made periodic: its last `fade` frames are faded out over its first `fade` frames,
// which fade in, so that the loop runs s[0 .. L) with P[L - 1] = s[L - 1] followed by
// P[0] = s[L]: neighbours in the recording, hence no step at the seam. A linear fade keeps a
// correlated (tonal) recording's level through the fade, which is what turbine samples are.
std::vector<float> makeLoop(const WavAudio& wav) {
  const size_t frames = wav.samples.size() / size_t(wav.channels);
  const auto fade = size_t(std::min(double(frames / 4), std::round(kMaxCrossFadeS * wav.sample_rate)));
  const size_t length = frames - fade;
  std::vector<float> loop(length);
  const auto at = [&](size_t i) { return double(wav.samples[i * size_t(wav.channels)]); };
  for (size_t i = 0; i < length; ++i) {
    if (i < fade) {
      const double w = double(i) / double(fade);
      loop[i] = float((1.0 - w) * at(length + i) + w * at(i));
    } else {
      loop[i] = float(at(i));
    }
  }
  return loop;
}

class SampleVoice final : public Voice {
 public:
  SampleVoice(std::vector<float> loop, double wav_rate, SampleRole role, double recorded_rpm, const SynthParams& params)
      : params_(params),
        role_(role),
        recorded_rpm_(recorded_rpm),
        step_(wav_rate / params.sample_rate),
        loop_(std::move(loop)),
        rotor_(params) {}

  void render(const SoundInput& from, const SoundInput& to, std::span<float> out) override {
    const double n_samples = double(out.size());
    const double length = double(loop_.size());
    for (size_t n = 0; n < out.size(); ++n) {
      const double u = double(n + 1) / n_samples;
      const internal::Glide g = internal::glide(from, to, u);
      double ratio = 1.0, level = 0.0;
      if (role_ == SampleRole::Turbine) {
        // Pitch and level both follow the rotor, which glides, so neither steps.
        const double rpm = rotor_.step(loadedRotorRpm(g.rpm, g.force_n, g.contact, params_));
        ratio = rpm / recorded_rpm_;
        level = std::min(ratio, 1.0);
      } else {
        level = std::sqrt(cuttingPower(g.removal_mm3_per_s, g.force_n, g.contact, params_));
      }
      out[n] = level == 0.0 ? 0.0f : softLimit(level * interpolate(position_));
      position_ += step_ * ratio;
      if (position_ >= length) position_ = std::fmod(position_, length);
    }
  }

 private:

  // Catmull-Rom cubic through the four loop samples around `x`, wrapping at the seam.
  double interpolate(double x) const {
    const size_t len = loop_.size();
    const auto i = size_t(x);
    const double t = x - double(i);
    const double p0 = loop_[(i + len - 1) % len], p1 = loop_[i % len];
    const double p2 = loop_[(i + 1) % len], p3 = loop_[(i + 2) % len];
    return p1 + 0.5 * t * (p2 - p0 + t * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + t * (3.0 * (p1 - p2) + p3 - p0)));
  }

  SynthParams params_;
  SampleRole role_;
  double recorded_rpm_;     // the rotor speed the recording was made at [1/min]
  double step_;             // loop samples per output sample at a ratio of 1
  std::vector<float> loop_;
  RotorSpeed rotor_;
  double position_ = 0.0;  // in the loop [samples], in [0, loop size)
};

}  // namespace

Result<std::unique_ptr<Voice>> makeSampleVoice(const std::string& wav_file, SampleRole role, double recorded_rpm,
                                               const SynthParams& params) {
  if (role == SampleRole::Turbine && !(recorded_rpm > 0 && recorded_rpm <= kMaxRpm))
    return makeError(wav_file, "the turbine sample's recorded speed must be within (0, " +
                                   std::to_string(int(kMaxRpm)) + "] rpm, not " + std::to_string(recorded_rpm));
  Result<WavAudio> wav = readWav(wav_file);
  if (!wav.ok()) return wav.error();
  const size_t frames = wav->samples.size() / size_t(wav->channels);
  if (frames < kMinFrames)
    return makeError(wav_file, "too short to loop (" + std::to_string(frames) + " frames, at least " +
                                   std::to_string(kMinFrames) + ")");
  return std::unique_ptr<Voice>(
      std::make_unique<SampleVoice>(makeLoop(*wav), double(wav->sample_rate), role, recorded_rpm, params));
}

}  // namespace dentsim::audio
