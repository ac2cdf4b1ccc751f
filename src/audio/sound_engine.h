// SoundEngine: plays the turbine and cutting voices through OpenAL Soft at the handpiece, or renders them offline to a WAV file.
//
// Two mono sources, the turbine and the cutting, each stream their voice through a small queue of
// AL buffers and sit at the handpiece; the listener sits at the camera.
//
//   - Live (EngineOptions::audio_out empty): the default playback device. The engine keeps each
//     queue latency_s ahead of what the device has played. With no sound device (no card, no
//     server) or when opening does not answer within kOpenTimeout, the engine is *silent*: create()
//     still succeeds, notice() says so in one line and every call is a cheap no-op. The device is
//     opened on a helper thread, because a sound server can keep OpenAL Soft waiting; OpenAL Soft
//     picks its backend from ALSOFT_DRIVERS (e.g. "alsa", or "null" to mix into nothing in real
//     time), read once per process on its first call.
//   - Offline (audio_out = FILE.wav): OpenAL's loopback device (ALC_SOFT_loopback) mixes exactly
//     the samples between two inputs' loop times, and they are appended to the WAV file, so the file
//     follows the session's clock sample for sample, however fast or slow the program runs.
//
// Units: positions in the tooth frame [mm] (converted to metres for OpenAL), times [s].
// Distance: a mouth-sized scene, so the sources play at full gain within 0.3 m of the listener
// (moving the bur pans the sound without pumping its loudness) and fall off as 1/distance beyond,
// down to 3 m (OpenAL's inverse-distance-clamped law); no Doppler shift.
// Threads: one thread at a time calls an engine. Each call makes the engine's context current, so
// several engines may live in one process (tests).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "audio/sound_input.h"
#include "audio/voices.h"
#include "core/result.h"
#include "core/rigid.h"

namespace dentsim::audio {

struct EngineOptions {
  std::string audio_out;         // non-empty: render offline through ALC_SOFT_loopback into this WAV (16-bit stereo)
  int sample_rate = 48000;       // the voices' and the offline file's rate [Hz] (8000..192000)
  double latency_s = 0.08;       // live: how far each source's queue runs ahead of the device [s] (0.01..1)
  SynthParams synth = defaultSynthParams();  // the voices; its sample_rate is replaced by sample_rate
  std::string turbine_wav;       // non-empty: this recording replaces the synthesized turbine
  std::string cutting_wav;       // non-empty: this recording replaces the synthesized cutting
  double recorded_rpm = 40000;   // the turbine recording's speed [1/min]
  bool force_silent = false;     // live: behave as if no device opened (tests, --no-sound)
};

class SoundEngine {
 public:
  // How long create() waits for the default device to open before going silent.
  static constexpr std::chrono::milliseconds kOpenTimeout{3000};

  // Live or offline as EngineOptions says. Fails only for bad options, a WAV sample that cannot be
  // loaded, an output file that cannot be created, or (offline) an OpenAL without the loopback
  // extension; a missing sound device gives a silent engine instead.
  static Result<std::unique_ptr<SoundEngine>> create(const EngineOptions& options);
  // Whether this OpenAL can render offline (has ALC_SOFT_loopback); cheap, opens no device.
  static bool offlineAvailable();
  ~SoundEngine();
  SoundEngine(const SoundEngine&) = delete;
  SoundEngine& operator=(const SoundEngine&) = delete;

  // The camera: its position, tooth frame [mm], and where it looks and its up (directions, need not
  // be unit). Until called: 200 mm in front of the tooth on +z, looking down -z, up +y.
  void setListener(const Vec3& position_mm, const Vec3& forward, const Vec3& up);

  // The simulation's latest state, at frame rate or any block rate. Live: tops each queue up to
  // latency_s, gliding from the previous input to this one, and restarts a source that starved.
  // Offline: mixes and writes exactly round(t*rate) - round(t_prev*rate) frames. The file starts at
  // the first input's time; a time that runs backward starts a new segment where the file stands.
  void update(const SoundInput& in);

  // Master volume [0, 1] and mute (the listener's gain; muted, the file still runs in time).
  void setVolume(double volume);
  void setMute(bool mute);

  // Offline: completes the WAV file (sizes, fsync, rename into place); an engine destroyed without
  // finish() leaves no file. Live or silent: nothing. Later updates are ignored.
  Status finish();

  bool silent() const { return state_ == nullptr; }
  bool offline() const { return offline_; }
  // One line for the user, or empty: why the engine is silent.
  const std::string& notice() const { return notice_; }
  // Frames mixed into the file (offline) or queued to the device (live); 0 when silent.
  uint64_t framesRendered() const { return frames_; }

 private:
  struct AlState;  // the OpenAL objects and the streaming state (sound_engine.cpp)
  SoundEngine() = default;

  std::unique_ptr<AlState> state_;  // null: silent
  bool offline_ = false;
  std::string notice_;
  uint64_t frames_ = 0;
  double volume_ = 1.0;
  bool mute_ = false;
  bool finished_ = false;
};

}  // namespace dentsim::audio
