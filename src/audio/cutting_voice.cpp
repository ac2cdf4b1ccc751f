// The bur cutting tissue: band-limited noise per tissue, mixed by what is being removed, rattling at the rotation's harmonics, its power following the removal rate.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "audio/voices.h"

namespace dentsim::audio {
namespace {

// The band noise's RMS at full removal before cutting_gain: leaves headroom for the rattle's peaks.
constexpr double kBandRms = 0.3;

// The rattle: the bur's envelope over one revolution, zero mean and within [-1, 1]. The 6th
// harmonic is the flutes of a six-bladed carbide bur striking the tissue.
double rattle(double revolution_phase) {
  const double a = 2.0 * std::numbers::pi * revolution_phase;
  return 0.5 * std::cos(a) + 0.3 * std::cos(2.0 * a + 1.0) + 0.2 * std::cos(6.0 * a);
}
// The mean of rattle()^2 over a revolution: (0.5^2 + 0.3^2 + 0.2^2) / 2.
constexpr double kRattleMeanSquare = 0.19;

class CuttingVoice final : public Voice {
 public:
  CuttingVoice(const SynthParams& params, uint32_t seed) : params_(params), rotor_(params), noise_(seed) {
    for (size_t t = 0; t < kTissueCount; ++t) {
      const TissueTimbre& timbre = params.timbre[t];
      Band& band = bands_[t];
      // Two sections in cascade: a band with steeper skirts than one section's 6 dB/octave.
      band.first = internal::Biquad::bandPass(timbre.centre_hz, timbre.bandwidth_hz, params.sample_rate);
      band.second = band.first;
      // Unit-variance noise through the filter has variance sum(h^2); scale to unit RMS.
      internal::Biquad a = band.first, b = band.second;
      double energy = 0.0;
      for (int i = 0; i < (1 << 16); ++i) {
        const double h = b.process(a.process(i == 0 ? 1.0 : 0.0));
        energy += h * h;
      }
      const double roughness = std::clamp(timbre.roughness, 0.0, 1.0);
      band.roughness = roughness;
      // The rattle raises the mean power by 1 + r^2 * mean(m^2); divided out, so roughness changes
      // the texture and not the loudness.
      band.scale = timbre.gain / std::sqrt(std::max(energy, 1e-30) * (1.0 + roughness * roughness * kRattleMeanSquare));
    }
  }

  void render(const SoundInput& from, const SoundInput& to, std::span<float> out) override {
    const double n_samples = double(out.size());
    const double fs = params_.sample_rate;
    for (size_t n = 0; n < out.size(); ++n) {
      const double u = double(n + 1) / n_samples;
      const internal::Glide g = internal::glide(from, to, u);
      // The bur turns with the rotor, so the rattle follows the same spin and load as the whine.
      const double rpm = rotor_.step(loadedRotorRpm(g.rpm, g.force_n, g.contact, params_));
      revolution_ += rpm / 60.0 / fs;
      revolution_ -= std::floor(revolution_);
      // Every band filters the same noise each sample, cutting or not, so that the filters are
      // settled when cutting starts and the output never depends on how the blocks were cut.
      const double white = noise_.next();
      std::array<double, kTissueCount> band{};
      for (size_t t = 0; t < kTissueCount; ++t) band[t] = bands_[t].second.process(bands_[t].first.process(white));
      const double power = cuttingPower(g.removal_mm3_per_s, g.force_n, g.contact, params_);
      if (power == 0.0) {
        out[n] = 0.0f;
        continue;
      }
      const double m = rattle(revolution_);
      double mix = 0.0;
      for (size_t t = 0; t < kTissueCount; ++t) {
        const double share = std::clamp(g.share(from, to, t), 0.0, 1.0);
        mix += share * bands_[t].scale * (1.0 + bands_[t].roughness * m) * band[t];
      }
      out[n] = softLimit(params_.cutting_gain * kBandRms * std::sqrt(power) * mix);
    }
  }

 private:

  struct Band {
    internal::Biquad first, second;
    double scale = 0.0;      // to unit RMS, times the tissue's gain
    double roughness = 0.0;  // depth of the rattle's modulation, [0, 1]
  };

  SynthParams params_;
  RotorSpeed rotor_;
  double revolution_ = 0.0;  // the bur's rotation [cycles], in [0, 1)
  internal::WhiteNoise noise_;
  std::array<Band, kTissueCount> bands_{};
};

}  // namespace

std::unique_ptr<Voice> makeCuttingVoice(const SynthParams& params, uint32_t seed) {
  return std::make_unique<CuttingVoice>(params, seed);
}

}  // namespace dentsim::audio
