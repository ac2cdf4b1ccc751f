// The simulator's sound: live through OpenAL, offline to a WAV file, or none; heard from the camera, made at the handpiece.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "audio/sound_engine.h"
#include "audio/sound_feed.h"
#include "core/result.h"
#include "render/camera.h"
#include "sim/haptic_loop.h"

namespace dentsim::app {

struct RunSoundOptions {
  bool sound = true;                     // false: no sound at all
  std::string audio_out;                 // FILE.wav; empty: live in a window, none headless
  std::string turbine_wav, cutting_wav;  // recordings replacing the synthesized voices; empty: synthesized
  double recorded_rpm = 40000.0;         // the turbine recording's speed [1/min]
};

class RunSound {
 public:
  // Opens the engine (none when sound is off, or headless without a file). Returns what the panel
  // shows as the output ("OpenAL Soft", "writing sound.wav", "no sound", or why it is silent);
  // `note` tells the user when the device is silent.
  Result<std::string> open(const RunSoundOptions& options, bool headless, const std::function<void(const std::string&)>& note);
  // Once a frame: the listener at the camera, the voices fed from the loop's state.
  void update(const render::OrbitCamera& camera, double volume, bool mute, const HapticState& state);
  bool offline() const { return engine_ && engine_->offline(); }
  // Offline: writes the file.
  Status finish() { return engine_->finish(); }

 private:
  std::unique_ptr<audio::SoundEngine> engine_;
  audio::SoundFeed feed_;
};

}  // namespace dentsim::app
