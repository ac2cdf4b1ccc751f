// The synthesized voices: the air turbine's whine and the bur cutting tissue; and WAV samples played in their place.
//
// Contents: TissueTimbre, SynthParams and their defaults; the loudness laws the voices share
// (turbine level, cutting level); RotorSpeed, the turbine's spin dynamics that every voice follows
// the same way; the voice factories.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "audio/sound_input.h"
#include "core/result.h"

namespace dentsim::audio {

// How one tissue sounds under the bur: enamel harsh and high, dentin duller, caries soft.
struct TissueTimbre {
  double centre_hz = 6000.0;   // centre of the noise band [Hz]
  double bandwidth_hz = 4000;  // its width [Hz]
  double gain = 1.0;           // loudness relative to the others
  double roughness = 0.5;      // [0, 1]: how much the rotation's harmonics rattle through it
};

struct SynthParams {
  double sample_rate = 48000.0;      // [Hz]
  int turbine_blades = 8;            // the whine's fundamental is rpm / 60 * blades [Hz]
  double spin_up_s = 0.3;            // time constant of the rotor speeding up [s]
  double spin_down_s = 1.0;          // ... and of coasting down [s]
  double load_slowdown = 0.12;       // fraction of speed lost at full load
  double full_load_n = 3.0;          // contact force that counts as full load [N]
  double turbine_gain = 0.25;        // the whine's amplitude at full speed
  double cutting_gain = 0.5;         // the cutting noise's amplitude at full_removal
  double full_removal_mm3_per_s = 1.0;  // removal rate at which the cutting noise reaches its gain
  std::array<TissueTimbre, kTissueCount> timbre{};  // by tissue table row; defaults set by defaultSynthParams()
  double force_loudness = 0.5;       // extra cutting POWER at full load, as a fraction (0.5: +1.8 dB)
  double air_noise = 0.06;           // the turbine's air hiss, relative to the whine, at full speed
};
SynthParams defaultSynthParams();

// The speed at which the whine reaches turbine_gain, and the top of the pedal's range [1/min].
inline constexpr double kFullSpeedRpm = 40000.0;
// Commanded speeds are clamped to this, so a bad input cannot push the whine past Nyquist [1/min].
inline constexpr double kMaxRpm = 60000.0;

// The whine's fundamental at a rotor speed [Hz].
double turbineFundamentalHz(double rpm, const SynthParams& params);

// The speed the rotor settles at under a commanded speed and a contact force [1/min]:
// rpm * (1 - load_slowdown * min(force / full_load_n, 1)), with force counted only in contact
// (contact_weight in [0, 1] is the contact flag moved across a block).
double loadedRotorRpm(double commanded_rpm, double force_n, double contact_weight, const SynthParams& params);

// The cutting sound's POWER relative to its power at full removal and no force:
//   x = removal / full_removal; p(x) = x up to 1, then 1 + ln x (same slope at 1) capped at 2.5;
//   times (1 + force_loudness * min(force / full_load_n, 1)), times contact_weight^2.
// Power is linear in the removal rate up to full removal; the amplitude is its square root.
double cuttingPower(double removal_mm3_per_s, double force_n, double contact_weight, const SynthParams& params);

// Bounds a voice's output to (-1.5, 1.5) without touching anything within [-1, 1].
inline float softLimit(double x) {
  if (x >= -1.0 && x <= 1.0) return float(x);
  const double over = (x > 0 ? x : -x) - 1.0;
  const double limited = 1.0 + 0.5 * (over / (0.5 + over));  // slope 1 at the knee, tends to 1.5
  return float(x > 0 ? limited : -limited);
}

// The rotor's speed following the commanded speed: first order, time constant spin_up_s while
// speeding up and spin_down_s while slowing. Exact for a constant target: after one time constant
// the gap has closed to 1/e. Snaps to exactly 0 once below half a revolution a minute with a target
// of 0, so a stopped turbine is exactly silent.
class RotorSpeed {
 public:
  explicit RotorSpeed(const SynthParams& params);
  // Advances one sample towards `target_rpm` and returns the new speed [1/min].
  double step(double target_rpm);
  double rpm() const { return rpm_; }

 private:
  double rpm_ = 0.0;
  double keep_up_ = 0.0;    // exp(-dt / spin_up_s): the part of the gap left after one sample
  double keep_down_ = 0.0;  // exp(-dt / spin_down_s)
};

std::unique_ptr<Voice> makeTurbineVoice(const SynthParams& params);
std::unique_ptr<Voice> makeCuttingVoice(const SynthParams& params, uint32_t seed = 1);

// A recorded sound in place of a voice: the turbine's sample is pitch-shifted by rpm / recorded_rpm
// and cross-faded in loudness; the cutting sample is looped, its loudness following the removal.
// The sample plays at its recorded level at recorded_rpm (turbine) or at full removal (cutting);
// its loop's end is cross-faded into its start (up to 50 ms), so the seam does not click.
enum class SampleRole { Turbine, Cutting };
Result<std::unique_ptr<Voice>> makeSampleVoice(const std::string& wav_file, SampleRole role, double recorded_rpm,
                                               const SynthParams& params);

// ---- Internals shared by the voices ------------------------------------------------------------
namespace internal {

// What a voice sees at sample n of a block of N: its inputs u = (n + 1) / N of the way from the
// block's first state to its last; contact as a weight in [0, 1], so it fades rather than clicks.
struct Glide {
  double rpm = 0.0;       // commanded turbine speed [1/min]
  double force_n = 0.0;
  double contact = 0.0;
  double removal_mm3_per_s = 0.0;
  double share(const SoundInput& from, const SoundInput& to, size_t tissue) const {
    return from.removal_share[tissue] + (to.removal_share[tissue] - from.removal_share[tissue]) * u;
  }
  double u = 0.0;
};
inline Glide glide(const SoundInput& from, const SoundInput& to, double u) {
  const auto mix = [u](double a, double b) { return a + (b - a) * u; };
  return {mix(from.turbine_rpm, to.turbine_rpm), mix(from.force_n, to.force_n),
          mix(from.contact ? 1.0 : 0.0, to.contact ? 1.0 : 0.0), mix(from.removal_mm3_per_s, to.removal_mm3_per_s), u};
}

// White noise from a 32-bit xorshift (Marsaglia's shifts 13, 17, 5): deterministic for a seed,
// uniform in [-sqrt 3, sqrt 3), so of unit variance.
class WhiteNoise {
 public:
  explicit WhiteNoise(uint32_t seed) : state_(seed == 0 ? 0x9e3779b9u : seed) {}
  double next() {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 17;
    state_ ^= state_ << 5;
    return (double(state_) * (1.0 / 4294967296.0) * 2.0 - 1.0) * 1.7320508075688772;
  }

 private:
  uint32_t state_;
};

// A second-order section, direct form I. The coefficient formulas are the textbook bilinear
// transform of the analog prototypes with the centre frequency pre-warped (as tabulated in Robert
// Bristow-Johnson's "Audio EQ Cookbook").
class Biquad {
 public:
  // Band-pass with 0 dB gain at centre_hz and Q = centre_hz / bandwidth_hz.
  static Biquad bandPass(double centre_hz, double bandwidth_hz, double sample_rate);
  // High-pass at cutoff_hz with the given Q (0.7071: Butterworth).
  static Biquad highPass(double cutoff_hz, double q, double sample_rate);
  double process(double x) {
    const double y = b0_ * x + b1_ * x1_ + b2_ * x2_ - a1_ * y1_ - a2_ * y2_;
    x2_ = x1_;
    x1_ = x;
    y2_ = y1_;
    y1_ = y;
    return y;
  }

 private:
  double b0_ = 1, b1_ = 0, b2_ = 0, a1_ = 0, a2_ = 0;  // normalised by a0
  double x1_ = 0, x2_ = 0, y1_ = 0, y2_ = 0;
};

}  // namespace internal

}  // namespace dentsim::audio
