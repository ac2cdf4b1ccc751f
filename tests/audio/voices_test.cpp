// Tests of the synthesized voices and the sample voice, measured on their output: pitch, spin times, load, band power, centroids, silence, continuity, bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "audio/voices.h"
#include "io/wav_file.h"

#include "audio/spectrum.h"
#include "test_support.h"

namespace dentsim::audio {
namespace {

constexpr double kFs = 48000.0;

SoundInput turbineAt(double rpm, double force = 0.0, bool contact = false) {
  SoundInput in;
  in.turbine_rpm = rpm;
  in.force_n = force;
  in.contact = contact;
  return in;
}

SoundInput cutting(double removal, Material tissue, double force = 1.5, double rpm = 30000) {
  SoundInput in = turbineAt(rpm, force, true);
  in.removal_mm3_per_s = removal;
  in.removal_share[size_t(tissueIndex(tissue))] = 1.0;
  return in;
}

// Renders `seconds` of constant input in frame-rate blocks of 800 samples (60 Hz at 48 kHz).
std::vector<float> renderConstant(Voice& voice, const SoundInput& in, double seconds, size_t block = 800) {
  std::vector<float> out(size_t(seconds * kFs));
  for (size_t start = 0; start < out.size(); start += block) {
    const size_t n = std::min(block, out.size() - start);
    voice.render(in, in, std::span(out).subspan(start, n));
  }
  return out;
}

// Frequency of the strongest peak in a 2048-sample window centred on each time [Hz].
std::vector<double> frequencyTrack(const std::vector<float>& x, const std::vector<double>& times_s) {
  std::vector<double> f;
  for (double t : times_s) {
    const auto centre = size_t(t * kFs);
    f.push_back(test::peakFrequency(std::span(x).subspan(centre - 1024, 2048), kFs, 50.0, 20000.0));
  }
  return f;
}

// The first time the track crosses `level` (upwards if rising), by linear interpolation [s].
double crossingTime(const std::vector<double>& times, const std::vector<double>& f, double level, bool rising) {
  for (size_t i = 1; i < f.size(); ++i) {
    const bool crossed = rising ? (f[i - 1] < level && f[i] >= level) : (f[i - 1] > level && f[i] <= level);
    if (crossed) return times[i - 1] + (times[i] - times[i - 1]) * (level - f[i - 1]) / (f[i] - f[i - 1]);
  }
  return -1.0;
}

// ---- Turbine ------------------------------------------------------------------------------------

TEST(TurbineVoiceTest, FundamentalIsRpmOver60TimesBladesAtSteadySpeeds) {
  const SynthParams p = defaultSynthParams();
  EXPECT_DOUBLE_EQ(turbineFundamentalHz(30000, p), 4000.0);  // 30 000 / 60 * 8
  for (double rpm : {6000.0, 15000.0, 25000.0, 40000.0}) {
    auto voice = makeTurbineVoice(p);
    // 3 s is ten spin-up time constants: the rotor is within 5e-5 of its speed.
    const std::vector<float> settled = renderConstant(*voice, turbineAt(rpm), 3.0);
    const std::vector<float> x = renderConstant(*voice, turbineAt(rpm), 16384 / kFs + 0.01);
    const double expected = rpm / 60.0 * p.turbine_blades;
    // The search runs over the whole audible band, so a harmonic would be found if it dominated.
    const double measured = test::peakFrequency(std::span(x).first(16384), kFs, 50.0, 22000.0);
    std::printf("turbine %.0f rpm: fundamental %.2f Hz, expected %.2f Hz\n", rpm, measured, expected);
    EXPECT_NEAR(measured / expected, 1.0, 0.005) << rpm << " rpm: " << measured << " Hz vs " << expected;
  }
}

TEST(TurbineVoiceTest, SpinUpReaches63PercentAtOneTimeConstant) {
  SynthParams p = defaultSynthParams();
  auto voice = makeTurbineVoice(p);
  const std::vector<float> x = renderConstant(*voice, turbineAt(30000), 1.0);
  std::vector<double> times;
  for (double t = 0.1; t <= 0.8; t += 0.01) times.push_back(t);
  const std::vector<double> f = frequencyTrack(x, times);
  const double target = turbineFundamentalHz(30000, p);
  const double t63 = crossingTime(times, f, (1.0 - std::exp(-1.0)) * target, true);
  std::printf("spin-up: 63%% at %.4f s (tau %.3f s)\n", t63, p.spin_up_s);
  EXPECT_NEAR(t63, p.spin_up_s, 0.03 * p.spin_up_s) << "measured 63% point at " << t63 << " s";
  // And at two time constants, 86.5%.
  const double t86 = crossingTime(times, f, (1.0 - std::exp(-2.0)) * target, true);
  EXPECT_NEAR(t86, 2 * p.spin_up_s, 0.03 * 2 * p.spin_up_s);
}

TEST(TurbineVoiceTest, SpinDownFallsTo37PercentAtOneTimeConstant) {
  SynthParams p = defaultSynthParams();
  auto voice = makeTurbineVoice(p);
  renderConstant(*voice, turbineAt(30000), 4.0);
  const std::vector<float> x = renderConstant(*voice, turbineAt(0), 2.0);
  std::vector<double> times;
  for (double t = 0.5; t <= 1.6; t += 0.01) times.push_back(t);
  const std::vector<double> f = frequencyTrack(x, times);
  const double start = turbineFundamentalHz(30000, p);
  const double t37 = crossingTime(times, f, std::exp(-1.0) * start, false);
  std::printf("spin-down: 37%% at %.4f s (tau %.3f s)\n", t37, p.spin_down_s);
  EXPECT_NEAR(t37, p.spin_down_s, 0.03 * p.spin_down_s) << "measured 37% point at " << t37 << " s";
}

TEST(TurbineVoiceTest, ExactlySilentAtZeroRpm) {
  const SynthParams p = defaultSynthParams();
  auto voice = makeTurbineVoice(p);
  // Pressing on the tooth with the turbine off makes no whine either.
  for (float s : renderConstant(*voice, turbineAt(0, 2.0, true), 1.0)) ASSERT_EQ(s, 0.0f);
  // After coasting down, the rotor stops and the output is exact zeros again: 20 000 rpm decays
  // below 0.5 rpm after ln(40 000) = 10.6 spin-down time constants.
  renderConstant(*voice, turbineAt(20000), 1.0);
  const std::vector<float> coasting = renderConstant(*voice, turbineAt(0), 12.0);
  EXPECT_GT(test::rms(std::span(coasting).first(4800)), 0.01);
  for (float s : std::span(coasting).last(4800)) ASSERT_EQ(s, 0.0f);
}

TEST(TurbineVoiceTest, LoadSlowsTheFundamentalByTheDocumentedFraction) {
  const SynthParams p = defaultSynthParams();
  const auto measure = [&](double force) {
    auto voice = makeTurbineVoice(p);
    renderConstant(*voice, turbineAt(30000, force, true), 3.0);
    const std::vector<float> x = renderConstant(*voice, turbineAt(30000, force, true), 0.35);
    return test::peakFrequency(std::span(x).first(16384), kFs, 50.0, 22000.0);
  };
  const double free_hz = measure(0.0);
  const double half_load = measure(0.5 * p.full_load_n);
  const double over_load = measure(3.0 * p.full_load_n);  // capped at full load
  std::printf("load: %.2f Hz free, %.2f Hz at half load, %.2f Hz over full load\n", free_hz, half_load, over_load);
  EXPECT_NEAR(half_load / free_hz, 1.0 - 0.5 * p.load_slowdown, 0.002);  // 0.94
  EXPECT_NEAR(over_load / free_hz, 1.0 - p.load_slowdown, 0.002);         // 0.88
  EXPECT_DOUBLE_EQ(loadedRotorRpm(30000, 1.5, 1.0, p), 30000 * 0.94);
  EXPECT_DOUBLE_EQ(loadedRotorRpm(30000, 1.5, 0.0, p), 30000);  // no contact, no load
}

TEST(TurbineVoiceTest, TimbreBrightensAndLevelRisesWithSpeed) {
  const SynthParams p = defaultSynthParams();
  const auto measure = [&](double rpm, double* second_over_first, double* level) {
    auto voice = makeTurbineVoice(p);
    renderConstant(*voice, turbineAt(rpm), 3.0);
    const std::vector<float> x = renderConstant(*voice, turbineAt(rpm), 1.0);
    const test::PowerSpectrum s = test::welch(x, kFs);
    const double f0 = turbineFundamentalHz(rpm, p);
    *second_over_first = test::bandEnergy(s, 1.9 * f0, 2.1 * f0) / test::bandEnergy(s, 0.9 * f0, 1.1 * f0);
    *level = test::rms(x);
  };
  double slow_ratio, fast_ratio, slow_level, fast_level;
  measure(10000, &slow_ratio, &slow_level);
  measure(40000, &fast_ratio, &fast_level);
  // Weights 0.2375 and 0.5 of the fundamental's: power ratios 0.056 and 0.25.
  EXPECT_NEAR(slow_ratio, 0.2375 * 0.2375, 0.01);
  EXPECT_NEAR(fast_ratio, 0.25, 0.02);
  EXPECT_GT(fast_level, 2.5 * slow_level);
}

TEST(TurbineVoiceTest, GlidingRpmHasNoClicks) {
  SynthParams p = defaultSynthParams();
  p.air_noise = 0.0;  // steps of noise would hide a step of the tone
  p.spin_up_s = 0.01;  // let the commanded glide through almost as it is
  auto voice = makeTurbineVoice(p);
  // A glide from 3000 to 6000 rpm in 60 Hz frames, each a new target for the voice.
  std::vector<float> glide;
  std::vector<float> block(800);
  SoundInput from = turbineAt(3000);
  renderConstant(*voice, from, 1.0);
  for (int frame = 1; frame <= 60; ++frame) {
    const SoundInput to = turbineAt(3000 + 3000.0 * frame / 60.0);
    voice->render(from, to, block);
    glide.insert(glide.end(), block.begin(), block.end());
    from = to;
  }
  auto steady = makeTurbineVoice(p);
  renderConstant(*steady, turbineAt(6000), 1.0);
  const std::vector<float> top = renderConstant(*steady, turbineAt(6000), 0.5);
  // A phase reset would step by up to twice the amplitude (0.075); the tone itself steps by ~0.01.
  std::printf("glide: max step %.5f, steady %.5f\n", test::maxStep(glide), test::maxStep(top));
  EXPECT_LE(test::maxStep(glide), 1.01 * test::maxStep(top));
  EXPECT_GT(test::maxStep(top), 0.0);
}

// ---- Cutting ------------------------------------------------------------------------------------

TEST(CuttingVoiceTest, HighBandPowerIsProportionalToRemovalRate) {
  const SynthParams p = defaultSynthParams();
  const std::vector<double> rates = {0.1, 0.25, 0.5, 0.75, 1.0};
  std::vector<double> energy;
  for (size_t i = 0; i < rates.size(); ++i) {
    // A different noise seed for each rate: the proportionality must hold statistically, not
    // only because the same noise was scaled.
    auto voice = makeCuttingVoice(p, uint32_t(11 + 7 * i));
    const std::vector<float> x = renderConstant(*voice, cutting(rates[i], Material::Enamel), 2.0);
    energy.push_back(test::bandEnergy(test::welch(x, kFs), 4000.0, kFs / 2));
  }
  // Least-squares line E = a + b r and its R^2.
  double mr = 0, me = 0;
  for (size_t i = 0; i < rates.size(); ++i) mr += rates[i] / double(rates.size()), me += energy[i] / double(rates.size());
  double srr = 0, sre = 0, see = 0;
  for (size_t i = 0; i < rates.size(); ++i) {
    srr += (rates[i] - mr) * (rates[i] - mr);
    sre += (rates[i] - mr) * (energy[i] - me);
    see += (energy[i] - me) * (energy[i] - me);
  }
  const double slope = sre / srr, intercept = me - slope * mr;
  const double r2 = sre * sre / (srr * see);
  std::printf("cutting high band: R^2 %.5f, E(1)/E(0.25) %.3f, E(0.5)/E(0.1) %.3f, intercept/E(1) %.4f\n", r2,
              energy[4] / energy[1], energy[2] / energy[0], intercept / energy.back());
  EXPECT_GT(r2, 0.98);
  // Proportional, not merely linear: the line passes through the origin.
  EXPECT_LT(std::abs(intercept), 0.03 * energy.back());
  EXPECT_NEAR(energy[4] / energy[1], 4.0, 0.2);  // 1.0 / 0.25
  EXPECT_NEAR(energy[2] / energy[0], 5.0, 0.25);  // 0.5 / 0.1
}

TEST(CuttingVoiceTest, ForceAddsTheDocumentedPowerAndRemovalSaturatesAboveFull) {
  const SynthParams p = defaultSynthParams();
  const auto power = [&](double removal, double force) {
    auto voice = makeCuttingVoice(p, 5);
    return std::pow(test::rms(renderConstant(*voice, cutting(removal, Material::Dentin, force), 1.0)), 2);
  };
  // Same seed, so the ratios are of one noise: (1 + 0.5 * 1) at full load.
  EXPECT_NEAR(power(0.5, p.full_load_n) / power(0.5, 0.0), 1.0 + p.force_loudness, 0.02);
  EXPECT_NEAR(power(0.5, 0.5 * p.full_load_n) / power(0.5, 0.0), 1.0 + 0.5 * p.force_loudness, 0.02);
  // Beyond full removal the power grows as 1 + ln x: 2.386 at four times full.
  EXPECT_NEAR(power(4.0, 0.0) / power(1.0, 0.0), 1.0 + std::log(4.0), 0.05);
  EXPECT_NEAR(power(50.0, 0.0) / power(1.0, 0.0), 2.5, 0.08);
}

TEST(CuttingVoiceTest, EnamelIsBrighterThanDentinWhichIsBrighterThanCaries) {
  const SynthParams p = defaultSynthParams();
  const auto centroid = [&](Material t) {
    auto voice = makeCuttingVoice(p, 3);
    return test::spectralCentroid(test::welch(renderConstant(*voice, cutting(1.0, t), 1.0), kFs));
  };
  const double enamel = centroid(Material::Enamel), dentin = centroid(Material::Dentin), caries = centroid(Material::Caries);
  std::printf("centroids: enamel %.0f Hz, dentin %.0f Hz, caries %.0f Hz\n", enamel, dentin, caries);
  EXPECT_GT(enamel, 1.3 * dentin) << enamel << " Hz vs " << dentin << " Hz";
  EXPECT_GT(dentin, 1.3 * caries) << dentin << " Hz vs " << caries << " Hz";
  // Each near its band's centre (the skirts of a 4th-order band pass pull it towards mid-band).
  EXPECT_NEAR(enamel, 8000.0, 2000.0);
  EXPECT_NEAR(dentin, 3500.0, 1000.0);
}

TEST(CuttingVoiceTest, SharesMixTheTissuesLinearly) {
  const SynthParams p = defaultSynthParams();
  const auto render = [&](std::array<double, kTissueCount> shares) {
    SoundInput in = cutting(0.5, Material::Enamel);
    in.removal_share = shares;
    auto voice = makeCuttingVoice(p, 9);
    return renderConstant(*voice, in, 0.25);
  };
  // The same noise through each tissue's band, weighted by its share: the mix is the weighted sum.
  const std::vector<float> enamel = render({1, 0, 0, 0}), caries = render({0, 0, 0, 1});
  const std::vector<float> mix = render({0.3, 0, 0, 0.7});
  for (size_t i = 0; i < mix.size(); ++i) ASSERT_NEAR(mix[i], 0.3 * enamel[i] + 0.7 * caries[i], 1e-6) << i;
  // Caries is the quieter tissue: its gain is 0.35 of enamel's.
  EXPECT_NEAR(test::rms(caries) / test::rms(enamel), 0.35, 0.02);
}

TEST(CuttingVoiceTest, RattleModulatesAtTheRotationFrequency) {
  const SynthParams p = defaultSynthParams();
  auto voice = makeCuttingVoice(p, 2);
  const double rpm = 24000;  // 400 revolutions a second
  renderConstant(*voice, cutting(1.0, Material::Enamel, 0.0, rpm), 3.0);
  const std::vector<float> x = renderConstant(*voice, cutting(1.0, Material::Enamel, 0.0, rpm), 1.0);
  // The envelope (the squared signal) carries the rattle's lines.
  std::vector<float> envelope(x.size());
  for (size_t i = 0; i < x.size(); ++i) envelope[i] = x[i] * x[i];
  const double measured = test::peakFrequency(std::span(envelope).first(32768), kFs, 100.0, 2000.0);
  EXPECT_NEAR(measured, rpm / 60.0, 0.01 * rpm / 60.0);
}

TEST(CuttingVoiceTest, ExactlySilentWithoutContactOrRemoval) {
  const SynthParams p = defaultSynthParams();
  SoundInput no_contact = cutting(1.0, Material::Enamel, 2.0);
  no_contact.contact = false;
  const SoundInput no_removal = cutting(0.0, Material::Enamel, 0.0);
  const SoundInput pressing = cutting(0.0, Material::Enamel, 2.0);  // force alone removes nothing
  for (const SoundInput& in : {no_contact, no_removal, pressing}) {
    auto voice = makeCuttingVoice(p);
    for (float s : renderConstant(*voice, in, 0.5)) ASSERT_EQ(s, 0.0f);
  }
  // And cutting, once it starts, is heard at once.
  auto voice = makeCuttingVoice(p);
  EXPECT_GT(test::rms(renderConstant(*voice, cutting(1.0, Material::Enamel), 0.1)), 0.05);
}

TEST(CuttingVoiceTest, ContactFadesInWithinTheBlock) {
  const SynthParams p = defaultSynthParams();
  auto voice = makeCuttingVoice(p);
  SoundInput off = cutting(1.0, Material::Enamel);
  off.contact = false;
  std::vector<float> block(800);
  voice->render(off, cutting(1.0, Material::Enamel), block);
  // The level is the contact weight times the rest: the first 80 samples are at most 10% of the way.
  EXPECT_LT(test::rms(std::span(block).first(80)), 0.25 * test::rms(std::span(block).last(80)));
}

// ---- Both ---------------------------------------------------------------------------------------

// Constant inputs must render the same samples however the stream is cut into blocks.
void expectBlockInvariance(Voice& one, Voice& many, const SoundInput& in) {
  std::vector<float> whole(9600);
  one.render(in, in, whole);
  std::vector<float> pieces(9600);
  const size_t sizes[] = {1, 7, 480, 1000, 33, 2048};
  for (size_t start = 0, i = 0; start < pieces.size(); ++i) {
    const size_t n = std::min(sizes[i % std::size(sizes)], pieces.size() - start);
    many.render(in, in, std::span(pieces).subspan(start, n));
    start += n;
  }
  for (size_t i = 0; i < whole.size(); ++i) ASSERT_EQ(whole[i], pieces[i]) << "sample " << i;
  EXPECT_GT(test::rms(whole), 0.01);
}

TEST(VoicesTest, BlockSizesDoNotChangeTheOutput) {
  const SynthParams p = defaultSynthParams();
  expectBlockInvariance(*makeTurbineVoice(p), *makeTurbineVoice(p), turbineAt(25000, 1.0, true));
  expectBlockInvariance(*makeCuttingVoice(p, 4), *makeCuttingVoice(p, 4), cutting(0.7, Material::Dentin));
}

TEST(VoicesTest, StayWithinBoundsAtEverythingMaximal) {
  const SynthParams p = defaultSynthParams();
  SoundInput in = turbineAt(1e6, 100.0, true);  // far past the pedal's range and full load
  in.removal_mm3_per_s = 1000.0;
  in.removal_share = {1, 1, 1, 1};  // even shares that do not sum to 1
  std::unique_ptr<Voice> voices[] = {makeTurbineVoice(p), makeCuttingVoice(p)};
  for (std::unique_ptr<Voice>& voice : voices) {
    const std::vector<float> x = renderConstant(*voice, in, 2.0);
    double peak = 0;
    for (float s : x) {
      ASSERT_TRUE(std::isfinite(s));
      peak = std::max(peak, std::abs(double(s)));
    }
    EXPECT_LE(peak, 1.5);
    EXPECT_GT(peak, 0.1);
  }
}

// ---- Sample voice -------------------------------------------------------------------------------

class SampleVoiceTest : public ::testing::Test {
 protected:
  std::string writeSine(const std::string& name, double hz, double seconds, int rate, double amplitude = 0.8) {
    const std::string path = dir_.file(name);
    Result<WavWriter> w = WavWriter::create(path, 1, rate);
    EXPECT_TRUE(w.ok()) << w.message();
    std::vector<float> x(size_t(seconds * rate));
    for (size_t i = 0; i < x.size(); ++i) x[i] = float(amplitude * std::sin(2 * std::numbers::pi * hz * double(i) / rate));
    EXPECT_TRUE(w->append(x).ok());
    EXPECT_TRUE(w->finish().ok());
    return path;
  }

  dentsim::test::TempDir dir_;
};

TEST_F(SampleVoiceTest, TurbineSamplePitchFollowsRpmOverRecordedRpm) {
  const SynthParams p = defaultSynthParams();
  const double f0 = 441.0;
  // Recorded at 44.1 kHz, played at 48 kHz: the rate conversion must keep the pitch.
  const std::string path = writeSine("turbine.wav", f0, 1.0, 44100);
  for (double rpm : {20000.0, 40000.0, 10000.0}) {
    Result<std::unique_ptr<Voice>> voice = makeSampleVoice(path, SampleRole::Turbine, 20000.0, p);
    ASSERT_TRUE(voice.ok()) << voice.message();
    renderConstant(**voice, turbineAt(rpm), 3.0);
    const std::vector<float> x = renderConstant(**voice, turbineAt(rpm), 0.5);
    const double measured = test::peakFrequency(std::span(x).first(16384), kFs, 50.0, 20000.0);
    std::printf("sample at %.0f rpm: %.2f Hz, expected %.2f Hz\n", rpm, measured, f0 * rpm / 20000.0);
    EXPECT_NEAR(measured / (f0 * rpm / 20000.0), 1.0, 0.01) << rpm << " rpm: " << measured << " Hz";
    // Full level at or above the recorded speed, half at half of it.
    EXPECT_NEAR(test::rms(x) / (0.8 / std::sqrt(2.0)), std::min(rpm / 20000.0, 1.0), 0.03);
  }
}

TEST_F(SampleVoiceTest, LoopSeamHasNoStepLargerThanTheRecordingsOwn) {
  const SynthParams p = defaultSynthParams();
  // 0.3 s of 440.3 Hz is 132.09 periods: looped raw, the seam would jump by most of the amplitude.
  const std::string path = writeSine("cutting.wav", 440.3, 0.3, 48000);
  Result<WavAudio> wav = readWav(path);
  ASSERT_TRUE(wav.ok());
  const double own_step = test::maxStep(wav->samples);
  const double raw_seam = std::abs(double(wav->samples.front()) - double(wav->samples.back()));
  ASSERT_GT(raw_seam, 5 * own_step);  // the test would see a click if there were no cross-fade
  Result<std::unique_ptr<Voice>> voice = makeSampleVoice(path, SampleRole::Cutting, 0.0, p);
  ASSERT_TRUE(voice.ok()) << voice.message();
  // Full removal, no force: the sample at its own level, over several loops.
  const std::vector<float> x = renderConstant(**voice, cutting(p.full_removal_mm3_per_s, Material::Enamel, 0.0), 1.5);
  std::printf("loop: max step %.5f, recording's own %.5f, raw seam %.5f\n", test::maxStep(x), own_step, raw_seam);
  EXPECT_LE(test::maxStep(x), own_step * 1.01);
  EXPECT_GT(test::rms(x), 0.4);
}

TEST_F(SampleVoiceTest, CuttingSampleLoudnessFollowsRemoval) {
  const SynthParams p = defaultSynthParams();
  const std::string path = writeSine("cut.wav", 1000.0, 0.5, 48000);
  const auto level = [&](double removal) {
    Result<std::unique_ptr<Voice>> voice = makeSampleVoice(path, SampleRole::Cutting, 0.0, p);
    EXPECT_TRUE(voice.ok());
    return test::rms(renderConstant(**voice, cutting(removal, Material::Enamel, 0.0), 1.0));
  };
  EXPECT_NEAR(std::pow(level(0.25) / level(1.0), 2), 0.25, 0.01);  // power proportional to removal
  EXPECT_EQ(level(0.0), 0.0);
}

TEST_F(SampleVoiceTest, SilentAtRestAndBounded) {
  const SynthParams p = defaultSynthParams();
  const std::string path = writeSine("t.wav", 300.0, 0.5, 48000, 1.0);
  Result<std::unique_ptr<Voice>> voice = makeSampleVoice(path, SampleRole::Turbine, 20000.0, p);
  ASSERT_TRUE(voice.ok());
  for (float s : renderConstant(**voice, turbineAt(0), 0.5)) ASSERT_EQ(s, 0.0f);
  Result<std::unique_ptr<Voice>> cut = makeSampleVoice(path, SampleRole::Cutting, 0.0, p);
  ASSERT_TRUE(cut.ok());
  SoundInput max = cutting(1000.0, Material::Enamel, 100.0, 1e6);
  for (float s : renderConstant(**cut, max, 0.5)) ASSERT_LE(std::abs(s), 1.5f);
}

TEST_F(SampleVoiceTest, BadSamplesAreOneLineErrorsNamingTheFile) {
  const SynthParams p = defaultSynthParams();
  const std::string missing = dir_.file("missing.wav");
  Result<std::unique_ptr<Voice>> r = makeSampleVoice(missing, SampleRole::Cutting, 0.0, p);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message().rfind(missing + ": ", 0), 0u) << r.message();
  const std::string tiny = writeSine("tiny.wav", 440.0, 40.0 / 48000.0, 48000);  // 40 frames
  r = makeSampleVoice(tiny, SampleRole::Cutting, 0.0, p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("too short"), std::string::npos) << r.message();
  const std::string good = writeSine("good.wav", 440.0, 0.1, 48000);
  r = makeSampleVoice(good, SampleRole::Turbine, 0.0, p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("recorded speed"), std::string::npos) << r.message();
  EXPECT_EQ(r.message().find('\n'), std::string::npos);
}

}  // namespace
}  // namespace dentsim::audio
