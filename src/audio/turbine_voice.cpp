// The air turbine's whine: a blade-pass tone and its harmonics on a spinning rotor, brighter and louder as it speeds up, with a little air hiss.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "audio/voices.h"

namespace dentsim::audio {
namespace {

// Where the hiss starts: air rushing through the head is heard above the low rumble [Hz].
constexpr double kHissHighPassHz = 1500.0;

class TurbineVoice final : public Voice {
 public:
  explicit TurbineVoice(const SynthParams& params)
      : params_(params),
        rotor_(params),
        noise_(0x7a5b1c3du),
        hiss_filter_(internal::Biquad::highPass(kHissHighPassHz, 0.7071, params.sample_rate)) {}

  void render(const SoundInput& from, const SoundInput& to, std::span<float> out) override {
    const double n_samples = double(out.size());
    const double fs = params_.sample_rate;
    for (size_t n = 0; n < out.size(); ++n) {
      // The block's inputs glide: sample n sees them (n + 1) / N of the way from `from` to `to`.
      const double u = double(n + 1) / n_samples;
      const internal::Glide g = internal::glide(from, to, u);
      const double rpm = rotor_.step(loadedRotorRpm(g.rpm, g.force_n, g.contact, params_));
      const double hiss = hiss_filter_.process(noise_.next());
      if (rpm == 0.0) {
        out[n] = 0.0f;
        continue;
      }
      // The phase only ever accumulates, so a gliding pitch never jumps.
      const double f0 = turbineFundamentalHz(rpm, params_);
      phase_ += f0 / fs;
      phase_ -= std::floor(phase_);
      const double speed = rpm / kFullSpeedRpm;
      out[n] = softLimit(params_.turbine_gain * std::min(speed, 1.25) * (whine(f0, std::min(speed, 1.0)) +
                                                                        params_.air_noise * std::min(speed, 1.0) * hiss));
    }
  }

 private:

  // A harmonic fades out as it nears Nyquist instead of aliasing or vanishing with a click.
  double nyquistTaper(double f) const {
    const double fs = params_.sample_rate;
    return std::clamp((0.45 * fs - f) / (0.05 * fs), 0.0, 1.0);
  }

  // Fundamental and three harmonics; the harmonics grow with speed, so the timbre brightens as the
  // rotor spins up (a slow turbine hums, a fast one screams). Peak at most 1.
  double whine(double f0, double speed) const {
    const double w2 = 0.15 + 0.35 * speed, w3 = 0.05 + 0.25 * speed, w4 = 0.12 * speed;
    const double norm = 1.0 / (1.0 + w2 + w3 + w4);
    const double angle = 2.0 * std::numbers::pi * phase_;
    // sin(k angle) by the angle-sum recurrence, from one sine and one cosine.
    const double s1 = std::sin(angle), c1 = std::cos(angle);
    const double s2 = 2.0 * s1 * c1, c2 = c1 * c1 - s1 * s1;
    const double s3 = s2 * c1 + c2 * s1, c3 = c2 * c1 - s2 * s1;
    const double s4 = s3 * c1 + c3 * s1;
    return norm * (nyquistTaper(f0) * s1 + w2 * nyquistTaper(2 * f0) * s2 + w3 * nyquistTaper(3 * f0) * s3 +
                   w4 * nyquistTaper(4 * f0) * s4);
  }

  SynthParams params_;
  RotorSpeed rotor_;
  double phase_ = 0.0;  // of the fundamental [cycles], in [0, 1)
  internal::WhiteNoise noise_;
  internal::Biquad hiss_filter_;
};

}  // namespace

std::unique_ptr<Voice> makeTurbineVoice(const SynthParams& params) { return std::make_unique<TurbineVoice>(params); }

}  // namespace dentsim::audio
