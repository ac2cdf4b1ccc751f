// Tests for SoundEngine: sessions rendered through OpenAL's loopback device into a WAV, read back and measured (pitch, loudness, colour, placement).
//
// Contents
//   1. Measuring: the spectrum toolkit (spectrum.h), channels, the excess over a baseline
//   2. Rendering a scripted session offline
//   3. Tests: pitch, silence, cutting loudness, tissue colour, placement, mute and volume, time
//      keeping, the live path on OpenAL's null backend, the silent engine, bad options
#include "audio/sound_engine.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <numbers>
#include <numeric>
#include <span>
#include <thread>
#include <vector>

#include "audio/spectrum.h"
#include "io/wav_file.h"
#include "test_support.h"

namespace dentsim::audio {
namespace {

// The live test runs on OpenAL Soft's "null" backend: real mixing on a real-time thread, nothing
// played on the developer's speakers, the same on a CI box without a sound card. OpenAL Soft reads
// ALSOFT_DRIVERS once, on its first call, so this is set before any test runs.
const bool kNullBackend = [] { return ::setenv("ALSOFT_DRIVERS", "null", 1) == 0; }();

constexpr int kRate = 48000;  // [Hz]

// ---------------------------------------------------------------------------------------------
// 1. Measuring (the shared toolkit in spectrum.h, plus what only these tests need)

using test::PowerSpectrum;

// The spectrum of what `s` adds to `baseline` (negative differences, noise, count as nothing),
// within [lo, hi).
PowerSpectrum excessOver(const PowerSpectrum& s, const PowerSpectrum& baseline, double lo_hz, double hi_hz) {
  PowerSpectrum excess = s;
  for (size_t k = 0; k < excess.power.size(); ++k) {
    const double f = double(k) * s.bin_hz;
    excess.power[k] = (f >= lo_hz && f < hi_hz) ? std::max(s.power[k] - baseline.power[k], 0.0) : 0.0;
  }
  return excess;
}

double meanSquare(std::span<const float> x) { return test::rms(x) * test::rms(x); }

// One channel (0 left, 1 right) or, with -1, their mean; frames [first, last).
std::vector<float> channel(const WavAudio& audio, int which, size_t first, size_t last) {
  const size_t frames = audio.samples.size() / size_t(audio.channels);
  last = std::min(last, frames);
  std::vector<float> x;
  for (size_t i = first; i < last; ++i) {
    const float l = audio.samples[2 * i], r = audio.samples[2 * i + 1];
    x.push_back(which == 0 ? l : which == 1 ? r : 0.5f * (l + r));
  }
  return x;
}

// ---------------------------------------------------------------------------------------------
// 2. Rendering

#define REQUIRE_LOOPBACK()                                                                          \
  if (!SoundEngine::offlineAvailable()) GTEST_SKIP() << "this OpenAL has no ALC_SOFT_loopback: offline rendering cannot be tested"

using dentsim::test::TempDir;

// A steady state: the turbine at `rpm`, cutting `removal` of one tissue when removal > 0.
SoundInput steady(double rpm, double removal = 0.0, Material tissue = Material::Enamel, bool contact = false,
                  double force_n = 0.0) {
  SoundInput in;
  in.turbine_rpm = rpm;
  in.removal_mm3_per_s = removal;
  in.removal_share[size_t(tissueIndex(tissue))] = 1.0;
  in.contact = contact || removal > 0;
  in.force_n = force_n;
  in.handpiece_mm = Vec3{0, 0, 0};
  return in;
}

// Renders `seconds` of the session `at(t)` offline, updated at 60 Hz, and reads the file back.
// `setup` runs on the engine before the first update.
WavAudio renderOffline(const std::string& path, double seconds, const std::function<SoundInput(double)>& at,
                       const std::function<void(SoundEngine&)>& setup = {}) {
  EngineOptions options;
  options.audio_out = path;
  options.sample_rate = kRate;
  auto engine = SoundEngine::create(options);
  EXPECT_TRUE(engine.ok()) << (engine.ok() ? "" : engine.message());
  if (!engine.ok()) return {};
  SoundEngine& e = **engine;
  EXPECT_FALSE(e.silent());
  EXPECT_TRUE(e.offline());
  if (setup) setup(e);
  const int updates = int(std::lround(seconds * 60.0));
  for (int k = 0; k <= updates; ++k) {
    SoundInput in = at(k / 60.0);
    in.t_s = k / 60.0;
    e.update(in);
  }
  // File time starts at the first input: round(t_last * rate) frames in all.
  EXPECT_EQ(e.framesRendered(), uint64_t(std::llround(updates / 60.0 * kRate)));
  const Status finished = e.finish();
  EXPECT_TRUE(finished.ok()) << (finished.ok() ? "" : finished.message());
  auto wav = readWav(path);
  EXPECT_TRUE(wav.ok()) << (wav.ok() ? "" : wav.message());
  if (!wav.ok()) return {};
  EXPECT_EQ(wav->channels, 2);
  EXPECT_EQ(wav->sample_rate, kRate);
  EXPECT_EQ(wav->samples.size(), 2 * e.framesRendered());
  return std::move(wav).value();
}

// ---------------------------------------------------------------------------------------------
// 3. Tests

// The whine's fundamental is rpm / 60 * blades (8 by default): 1333.3 Hz at 10 000 rpm ... 5333.3 Hz
// at 40 000 rpm. After 2.5 s the rotor (spin-up time constant 0.3 s) is within e^-8 of its speed;
// the last second is measured (peak of a 4x zero-padded spectrum, refined on the DTFT).
TEST(SoundEngine, TurbineFundamentalFollowsRpm) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  const SynthParams params = defaultSynthParams();
  for (double rpm : {10000.0, 20000.0, 30000.0, 40000.0}) {
    const WavAudio wav = renderOffline(dir.file("pitch.wav"), 3.5, [&](double) { return steady(rpm); });
    ASSERT_FALSE(wav.samples.empty());
    const std::vector<float> x = channel(wav, -1, size_t(2.5 * kRate), size_t(3.5 * kRate));
    const double expected = rpm / 60.0 * double(params.turbine_blades);
    const double measured = test::peakFrequency(x, kRate, 50.0, 20000.0);
    RecordProperty("f0_at_" + std::to_string(int(rpm)) + "_rpm", std::to_string(measured));
    EXPECT_NEAR(measured / expected, 1.0, 0.02) << rpm << " rpm: expected " << expected << " Hz, measured " << measured;
  }
}

// Spin-down is slower than spin-up, and the pitch moves with the rotor: half a second after the
// pedal drops from 40 000 to 20 000 rpm the rotor (time constant 1 s) is at
// 20 000 + 20 000 e^-0.5 = 32 131 rpm, a whine of 4284 Hz.
TEST(SoundEngine, PitchGlidesWithTheRotorAfterThePedalDrops) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  const WavAudio wav =
      renderOffline(dir.file("glide.wav"), 3.5, [](double t) { return steady(t < 3.0 ? 40000.0 : 20000.0); });
  ASSERT_FALSE(wav.samples.empty());
  // The 4096 frames (85 ms) that end half a second after the drop; the pitch falls about 3% across
  // them, and their middle sees the rotor 43 ms earlier, a little faster.
  const size_t end = size_t(3.5 * kRate);
  const std::vector<float> x = channel(wav, -1, end - 4096, end);
  const double expected = (20000.0 + 20000.0 * std::exp(-0.5)) / 60.0 * 8.0;
  const double expected_mid = (20000.0 + 20000.0 * std::exp(-(0.5 - 0.0427))) / 60.0 * 8.0;
  const double measured = test::peakFrequency(x, kRate, 50.0, 20000.0);
  RecordProperty("f0_half_second_after_drop", std::to_string(measured));
  EXPECT_GT(measured, expected * 0.98);
  EXPECT_NEAR(measured / expected_mid, 1.0, 0.03) << "measured " << measured << " Hz";
}

// A stopped turbine without contact renders exact zeros from the file's first frame.
TEST(SoundEngine, SilentAtZeroRpmWithoutContact) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  const WavAudio wav = renderOffline(dir.file("quiet.wav"), 1.0, [](double) { return steady(0.0); });
  ASSERT_EQ(wav.samples.size(), size_t(2 * kRate));
  float peak = 0.0f;
  for (float v : wav.samples) peak = std::max(peak, std::fabs(v));
  EXPECT_LT(peak, 1e-6f);
}

// The cutting noise's power is linear in the removal rate up to full removal (1 mm^3/s): the
// high band's energy above the turbine-only baseline (same speed, same contact and force, nothing
// removed) must be a line through the origin.
TEST(SoundEngine, CuttingRaisesHighBandEnergyInProportionToRemoval) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  constexpr double kRpm = 20000.0, kForce = 1.0;
  auto highBand = [&](double removal) {
    const WavAudio wav = renderOffline(dir.file("cut.wav"), 2.5, [&](double) {
      return steady(kRpm, removal, Material::Enamel, /*contact=*/true, kForce);
    });
    return test::bandEnergy(test::welch(channel(wav, -1, size_t(1.5 * kRate), size_t(2.5 * kRate)), kRate), 5000.0,
                            16000.0);
  };
  const double baseline = highBand(0.0);
  const std::vector<double> rates = {0.2, 0.4, 0.6, 0.8, 1.0};
  std::vector<double> excess;
  for (double r : rates) excess.push_back(highBand(r) - baseline);

  // Least-squares line e = a + b r, and its R^2.
  const double n = double(rates.size());
  const double mr = std::accumulate(rates.begin(), rates.end(), 0.0) / n;
  const double me = std::accumulate(excess.begin(), excess.end(), 0.0) / n;
  double srr = 0, sre = 0, see = 0;
  for (size_t i = 0; i < rates.size(); ++i) {
    srr += (rates[i] - mr) * (rates[i] - mr);
    sre += (rates[i] - mr) * (excess[i] - me);
    see += (excess[i] - me) * (excess[i] - me);
  }
  const double slope = sre / srr, intercept = me - slope * mr;
  const double r2 = sre * sre / (srr * see);
  std::string table = "slope " + std::to_string(slope) + " intercept " + std::to_string(intercept) + " R2 " +
                      std::to_string(r2) + " baseline " + std::to_string(baseline) + "; excess by rate";
  for (size_t i = 0; i < rates.size(); ++i) table += " " + std::to_string(rates[i]) + ":" + std::to_string(excess[i]);
  RecordProperty("high_band", table);
  EXPECT_GT(slope, 0.0) << table;
  EXPECT_GT(r2, 0.95) << table;
  // Through the origin: the intercept is small against the excess at full removal, and doubling
  // the rate doubles the excess.
  EXPECT_LT(std::fabs(intercept), 0.15 * (intercept + slope * 1.0)) << "baseline " << baseline << table;
  EXPECT_NEAR(excess[4] / excess[1], 1.0 / 0.4, 0.15 * 2.5) << table;
  EXPECT_NEAR(excess[3] / excess[1], 2.0, 0.15 * 2.0) << table;
}

// Enamel is voiced around 8 kHz, dentin around 3.5 kHz (defaultSynthParams): the centroid of what
// cutting adds to the turbine's spectrum must tell them apart by more than 20%.
TEST(SoundEngine, EnamelAndDentinHaveDifferentCentroids) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  constexpr double kRpm = 30000.0, kForce = 1.0;
  auto spectrum = [&](double removal, Material tissue) {
    const WavAudio wav = renderOffline(dir.file("tissue.wav"), 2.5, [&](double) {
      return steady(kRpm, removal, tissue, /*contact=*/true, kForce);
    });
    return test::welch(channel(wav, -1, size_t(1.5 * kRate), size_t(2.5 * kRate)), kRate);
  };
  const PowerSpectrum turbine = spectrum(0.0, Material::Enamel);
  const double enamel = test::spectralCentroid(excessOver(spectrum(0.8, Material::Enamel), turbine, 100.0, 20000.0));
  const double dentin = test::spectralCentroid(excessOver(spectrum(0.8, Material::Dentin), turbine, 100.0, 20000.0));
  RecordProperty("centroids", "enamel " + std::to_string(enamel) + " dentin " + std::to_string(dentin));
  EXPECT_GT(enamel, 1.2 * dentin) << "enamel " << enamel << " Hz, dentin " << dentin << " Hz";
  // Each lies near its own band (a band-pass's centroid sits above its centre: the upper skirt is
  // wider in hertz).
  EXPECT_GT(enamel, 6000.0);
  EXPECT_LT(enamel, 11000.0);
  EXPECT_GT(dentin, 2500.0);
  EXPECT_LT(dentin, 6000.0);
}

// The listener 200 mm in front of the tooth looks down -z with +y up, so +x is on its right. A
// handpiece 100 mm to the left must be louder in the left channel, and the mirror image the
// mirror ratio.
TEST(SoundEngine, SourcesArePlacedAtTheHandpiece) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  auto leftOverRight = [&](double x_mm) {
    const WavAudio wav = renderOffline(
        dir.file("pan.wav"), 1.5,
        [&](double) {
          SoundInput in = steady(30000.0);
          in.handpiece_mm = Vec3{x_mm, 0, 0};
          return in;
        },
        [](SoundEngine& e) { e.setListener(Vec3{0, 0, 200}, Vec3{0, 0, -1}, Vec3{0, 1, 0}); });
    const size_t a = size_t(0.5 * kRate), b = size_t(1.5 * kRate);
    return meanSquare(channel(wav, 0, a, b)) / meanSquare(channel(wav, 1, a, b));
  };
  const double left = leftOverRight(-100.0);
  const double right = leftOverRight(+100.0);
  RecordProperty("left_over_right", std::to_string(left) + " / " + std::to_string(right));
  EXPECT_GT(left, 1.5) << "handpiece on the left: L/R energy " << left;
  EXPECT_LT(right, 1.0 / 1.5) << "handpiece on the right: L/R energy " << right;
  EXPECT_NEAR(left * right, 1.0, 0.05) << "mirror positions, mirror ratios";
  // Turning the listener round swaps the sides.
  const WavAudio turned = renderOffline(
      dir.file("turned.wav"), 1.5,
      [](double) {
        SoundInput in = steady(30000.0);
        in.handpiece_mm = Vec3{-100, 0, 0};
        return in;
      },
      [](SoundEngine& e) { e.setListener(Vec3{0, 0, -200}, Vec3{0, 0, 1}, Vec3{0, 1, 0}); });
  const size_t a = size_t(0.5 * kRate), b = size_t(1.5 * kRate);
  EXPECT_LT(meanSquare(channel(turned, 0, a, b)) / meanSquare(channel(turned, 1, a, b)), 1.0 / 1.5);
}

// Muted, the file keeps its clock (its length grows frame for frame) but holds zeros once the
// gain's ramp (one mix, at most 1024 frames) is over; unmuted, the sound returns.
TEST(SoundEngine, MuteSilencesTheFileWhileTimeAdvances) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  const std::string path = dir.file("mute.wav");
  EngineOptions options;
  options.audio_out = path;
  auto engine = SoundEngine::create(options);
  ASSERT_TRUE(engine.ok()) << engine.message();
  SoundEngine& e = **engine;
  auto run = [&](int from, int to) {
    for (int k = from; k <= to; ++k) {
      SoundInput in = steady(30000.0);
      in.t_s = k / 60.0;
      e.update(in);
    }
  };
  run(0, 120);  // 2 s: the rotor (spin-up time constant 0.3 s) reaches speed
  EXPECT_EQ(e.framesRendered(), uint64_t(2 * kRate));
  e.setMute(true);
  run(121, 180);  // muted: the third second
  EXPECT_EQ(e.framesRendered(), uint64_t(3 * kRate));
  e.setMute(false);
  run(181, 240);
  EXPECT_EQ(e.framesRendered(), uint64_t(4 * kRate));
  ASSERT_TRUE(e.finish().ok());
  auto wav = readWav(path);
  ASSERT_TRUE(wav.ok()) << wav.message();
  ASSERT_EQ(wav->samples.size(), size_t(2 * 4 * kRate));
  float muted_peak = 0.0f;
  for (size_t i = 2 * (2 * kRate + 1024); i < size_t(2 * 3 * kRate); ++i) {
    muted_peak = std::max(muted_peak, std::fabs(wav->samples[i]));
  }
  EXPECT_LT(muted_peak, 1e-6f);
  const double before = meanSquare(channel(*wav, -1, size_t(1.5 * kRate), size_t(2 * kRate)));
  const double after = meanSquare(channel(*wav, -1, size_t(3.5 * kRate), size_t(4 * kRate)));
  EXPECT_GT(before, 1e-4);
  EXPECT_NEAR(after / before, 1.0, 0.05);
}

// The voices are deterministic, so volume 0.5 must give the very same samples at half the
// amplitude (to the 16-bit file's rounding).
TEST(SoundEngine, HalfVolumeHalvesTheAmplitude) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  auto session = [](double) { return steady(30000.0, 0.5, Material::Dentin, true, 1.0); };
  const WavAudio full = renderOffline(dir.file("full.wav"), 1.0, session);
  const WavAudio half = renderOffline(dir.file("half.wav"), 1.0, session, [](SoundEngine& e) { e.setVolume(0.5); });
  ASSERT_EQ(full.samples.size(), half.samples.size());
  ASSERT_FALSE(full.samples.empty());
  const double rms_full = std::sqrt(meanSquare(channel(full, -1, 0, size_t(kRate))));
  const double rms_half = std::sqrt(meanSquare(channel(half, -1, 0, size_t(kRate))));
  EXPECT_GT(rms_full, 0.01);
  RecordProperty("rms_ratio", std::to_string(rms_half / rms_full));
  EXPECT_NEAR(rms_half / rms_full, 0.5, 0.025);
  double worst = 0.0;
  for (size_t i = 0; i < full.samples.size(); ++i) {
    worst = std::max(worst, std::fabs(double(half.samples[i]) - 0.5 * double(full.samples[i])));
  }
  EXPECT_LT(worst, 2.0 / 32768.0);
}

// Frame times that are not whole samples apart (60 Hz at 48 kHz is 800 frames, 59.94 Hz is not)
// still add up to round(t * rate) frames: no drift. A time that runs backward starts a new
// segment at the end of the file, and a steady whine runs through the seam without a step.
TEST(SoundEngine, FileKeepsTheSessionClockAcrossSegments) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  const std::string path = dir.file("clock.wav");
  EngineOptions options;
  options.audio_out = path;
  auto engine = SoundEngine::create(options);
  ASSERT_TRUE(engine.ok()) << engine.message();
  SoundEngine& e = **engine;
  const double dt = 1.0 / 59.94;
  SoundInput in = steady(30000.0);
  int k = 0;
  for (; k * dt <= 2.0; ++k) {
    in.t_s = k * dt;
    e.update(in);
  }
  const double last = (k - 1) * dt;
  const auto first_segment = uint64_t(std::llround(last * kRate));
  EXPECT_EQ(e.framesRendered(), first_segment);
  // A new segment: its loop time starts again at 0.25 s.
  for (int j = 0; j <= 30; ++j) {
    in.t_s = 0.25 + j / 60.0;
    e.update(in);
  }
  EXPECT_EQ(e.framesRendered(), first_segment + uint64_t(std::llround(0.5 * kRate)));
  ASSERT_TRUE(e.finish().ok());
  auto wav = readWav(path);
  ASSERT_TRUE(wav.ok()) << wav.message();
  const std::vector<float> x = channel(*wav, 0, 0, size_t(-1));
  ASSERT_EQ(x.size(), e.framesRendered());
  // The largest step between neighbours around the seam is no larger than in the steady part.
  const std::span<const float> all(x);
  const double steady_step = test::maxStep(all.subspan(size_t(kRate), size_t(kRate / 2)));
  EXPECT_GT(steady_step, 0.0);
  EXPECT_LE(test::maxStep(all.subspan(first_segment - 2000, 4000)), 1.1 * steady_step);
}

// The live path, on OpenAL Soft's null backend: the first update queues latency_s of sound; the
// device plays on its own clock and later updates top the queue up by about what it played.
TEST(SoundEngine, LivePlaybackKeepsTheQueueFilled) {
  ASSERT_TRUE(kNullBackend);
  EngineOptions options;
  options.latency_s = 0.08;
  const auto start = std::chrono::steady_clock::now();
  auto engine = SoundEngine::create(options);
  ASSERT_TRUE(engine.ok()) << engine.message();
  SoundEngine& e = **engine;
  EXPECT_LT(std::chrono::steady_clock::now() - start, SoundEngine::kOpenTimeout + std::chrono::seconds(1));
  if (e.silent()) GTEST_SKIP() << "OpenAL's null backend did not open: " << e.notice();
  EXPECT_FALSE(e.offline());
  SoundInput in = steady(30000.0);
  // The clock starts before the first update: the device may start playing as soon as that update
  // queues sound, and a thread preempted just after it would otherwise not count what was played.
  const auto begun = std::chrono::steady_clock::now();
  e.update(in);
  const uint64_t target = uint64_t(std::ceil(0.08 * 48000));
  EXPECT_EQ(e.framesRendered(), target);
  for (int k = 1; k <= 30; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    in.t_s = k * 0.01;
    e.update(in);
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - begun).count();
  // What was added is what the device played (it cannot play more than the time allows, plus
  // one mix period of slack), and the device did play.
  const double added = double(e.framesRendered() - target);
  EXPECT_GT(added, 0.0);
  EXPECT_LT(added, (elapsed + 0.05) * 48000 + double(target));
  e.setVolume(0.3);
  e.setMute(true);
  e.setListener(Vec3{0, 0, 100}, Vec3{0, 0, -1}, Vec3{0, 1, 0});
  EXPECT_TRUE(e.finish().ok());
}

// With no device the engine is silent: every call is accepted, nothing is counted, one notice.
TEST(SoundEngine, SilentEngineAcceptsEveryCall) {
  EngineOptions options;
  options.force_silent = true;
  auto engine = SoundEngine::create(options);
  ASSERT_TRUE(engine.ok()) << engine.message();
  SoundEngine& e = **engine;
  EXPECT_TRUE(e.silent());
  EXPECT_FALSE(e.offline());
  EXPECT_NE(e.notice().find("running silently"), std::string::npos) << e.notice();
  EXPECT_EQ(e.notice().find('\n'), std::string::npos);
  e.setListener(Vec3{0, 0, 100}, Vec3{0, 0, -1}, Vec3{0, 1, 0});
  e.setVolume(0.5);
  e.setMute(true);
  for (int k = 0; k < 10; ++k) e.update(steady(20000.0, 0.5, Material::Dentin, true, 1.0));
  EXPECT_EQ(e.framesRendered(), 0u);
  EXPECT_TRUE(e.finish().ok());
}

TEST(SoundEngine, BadOptionsGiveOneLineErrorsNamingTheCulprit) {
  TempDir dir;
  EngineOptions options;
  options.audio_out = dir.file("out.wav");
  options.turbine_wav = dir.file("no_such_turbine.wav");
  auto missing = SoundEngine::create(options);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("no_such_turbine.wav"), std::string::npos) << missing.message();
  EXPECT_EQ(missing.message().find('\n'), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir.file("out.wav")));

  options.turbine_wav.clear();
  options.sample_rate = 1000;
  auto rate = SoundEngine::create(options);
  ASSERT_FALSE(rate.ok());
  EXPECT_NE(rate.message().find("1000"), std::string::npos) << rate.message();

  if (!SoundEngine::offlineAvailable()) return;
  options.sample_rate = kRate;
  options.audio_out = dir.file("no_such_dir/out.wav");
  auto unwritable = SoundEngine::create(options);
  ASSERT_FALSE(unwritable.ok());
  EXPECT_NE(unwritable.message().find("no_such_dir"), std::string::npos) << unwritable.message();
}

// A recorded turbine replaces the synthesized one and is pitch-shifted by rpm / recorded_rpm: a
// 1000 Hz tone recorded at 40 000 rpm plays at 750 Hz at 30 000 rpm.
TEST(SoundEngine, RecordedTurbineIsPitchShiftedByTheSpeed) {
  REQUIRE_LOOPBACK();
  TempDir dir;
  const std::string sample = dir.file("turbine_sample.wav");
  {
    auto writer = WavWriter::create(sample, 1, kRate);
    ASSERT_TRUE(writer.ok()) << writer.message();
    std::vector<float> tone(kRate);
    for (size_t i = 0; i < tone.size(); ++i) {
      tone[i] = float(0.5 * std::sin(2.0 * std::numbers::pi * 1000.0 * double(i) / kRate));
    }
    ASSERT_TRUE(writer->append(tone).ok());
    ASSERT_TRUE(writer->finish().ok());
  }
  const std::string path = dir.file("sampled.wav");
  EngineOptions options;
  options.audio_out = path;
  options.turbine_wav = sample;
  options.recorded_rpm = 40000.0;
  auto engine = SoundEngine::create(options);
  ASSERT_TRUE(engine.ok()) << engine.message();
  for (int k = 0; k <= 180; ++k) {
    SoundInput in = steady(30000.0);
    in.t_s = k / 60.0;
    (*engine)->update(in);
  }
  ASSERT_TRUE((*engine)->finish().ok());
  auto wav = readWav(path);
  ASSERT_TRUE(wav.ok()) << wav.message();
  const std::vector<float> x = channel(*wav, -1, size_t(2 * kRate), size_t(3 * kRate));
  const double measured = test::peakFrequency(x, kRate, 50.0, 20000.0);
  RecordProperty("sample_pitch", std::to_string(measured));
  EXPECT_NEAR(measured / 750.0, 1.0, 0.02);
}

}  // namespace
}  // namespace dentsim::audio
