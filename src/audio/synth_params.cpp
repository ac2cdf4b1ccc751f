// The voices' default parameters and the laws they share: the whine's pitch, the rotor's spin and load, the cutting loudness, the filters.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "audio/voices.h"

namespace dentsim::audio {

SynthParams defaultSynthParams() {
  SynthParams p;
  // Enamel: hard, brittle, the bur chatters on it: a bright high band with a strong rattle.
  p.timbre[size_t(tissueIndex(Material::Enamel))] = {8000.0, 5000.0, 1.0, 0.8};
  // Dentin: softer and wetter, the sound is duller and lower.
  p.timbre[size_t(tissueIndex(Material::Dentin))] = {3500.0, 2500.0, 0.8, 0.4};
  // Pulp and caries: soft tissue, little more than a low, quiet swish.
  p.timbre[size_t(tissueIndex(Material::Pulp))] = {1200.0, 1000.0, 0.3, 0.1};
  p.timbre[size_t(tissueIndex(Material::Caries))] = {1500.0, 1200.0, 0.35, 0.15};
  // A neighbour's surface is enamel: the student hears the same chatter as on the tooth's own.
  p.timbre[size_t(tissueIndex(Material::Neighbour))] = p.timbre[size_t(tissueIndex(Material::Enamel))];
  return p;
}

double turbineFundamentalHz(double rpm, const SynthParams& params) {
  return std::max(rpm, 0.0) / 60.0 * double(params.turbine_blades);
}

double loadedRotorRpm(double commanded_rpm, double force_n, double contact_weight, const SynthParams& params) {
  const double rpm = std::clamp(commanded_rpm, 0.0, kMaxRpm);
  if (!(params.full_load_n > 0)) return rpm;
  const double load = std::clamp(force_n / params.full_load_n, 0.0, 1.0) * std::clamp(contact_weight, 0.0, 1.0);
  return rpm * (1.0 - std::clamp(params.load_slowdown, 0.0, 1.0) * load);
}

double cuttingPower(double removal_mm3_per_s, double force_n, double contact_weight, const SynthParams& params) {
  const double c = std::clamp(contact_weight, 0.0, 1.0);
  if (c == 0.0 || !(removal_mm3_per_s > 0) || !(params.full_removal_mm3_per_s > 0)) return 0.0;
  const double x = removal_mm3_per_s / params.full_removal_mm3_per_s;
  // Linear up to full removal; beyond it, the log keeps rising but slower, and stops at 2.5.
  const double removal = x <= 1.0 ? x : std::min(1.0 + std::log(x), 2.5);
  const double load = params.full_load_n > 0 ? std::clamp(force_n / params.full_load_n, 0.0, 1.0) : 0.0;
  return removal * (1.0 + std::max(params.force_loudness, 0.0) * load) * c * c;
}

RotorSpeed::RotorSpeed(const SynthParams& params) {
  const double dt = 1.0 / params.sample_rate;
  keep_up_ = params.spin_up_s > 0 ? std::exp(-dt / params.spin_up_s) : 0.0;
  keep_down_ = params.spin_down_s > 0 ? std::exp(-dt / params.spin_down_s) : 0.0;
}

double RotorSpeed::step(double target_rpm) {
  const double target = std::clamp(target_rpm, 0.0, kMaxRpm);
  const double keep = target > rpm_ ? keep_up_ : keep_down_;
  rpm_ = target + (rpm_ - target) * keep;
  if (target == 0.0 && rpm_ < 0.5) rpm_ = 0.0;
  return rpm_;
}

namespace internal {

Biquad Biquad::bandPass(double centre_hz, double bandwidth_hz, double sample_rate) {
  const double f = std::clamp(centre_hz, 1.0, 0.49 * sample_rate);
  const double q = f / std::max(bandwidth_hz, 1.0);
  const double w = 2.0 * std::numbers::pi * f / sample_rate;
  const double alpha = std::sin(w) / (2.0 * q);
  const double a0 = 1.0 + alpha;
  Biquad b;
  b.b0_ = alpha / a0;
  b.b1_ = 0.0;
  b.b2_ = -alpha / a0;
  b.a1_ = -2.0 * std::cos(w) / a0;
  b.a2_ = (1.0 - alpha) / a0;
  return b;
}

Biquad Biquad::highPass(double cutoff_hz, double q, double sample_rate) {
  const double f = std::clamp(cutoff_hz, 1.0, 0.49 * sample_rate);
  const double w = 2.0 * std::numbers::pi * f / sample_rate;
  const double alpha = std::sin(w) / (2.0 * q);
  const double cw = std::cos(w);
  const double a0 = 1.0 + alpha;
  Biquad b;
  b.b0_ = (1.0 + cw) / 2.0 / a0;
  b.b1_ = -(1.0 + cw) / a0;
  b.b2_ = b.b0_;
  b.a1_ = -2.0 * cw / a0;
  b.a2_ = (1.0 - alpha) / a0;
  return b;
}

}  // namespace internal

}  // namespace dentsim::audio
