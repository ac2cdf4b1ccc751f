// SoundFeed: the haptic loop's state, sampled at frame or block rate, turned into what the sound engine hears.
#pragma once

#include <array>

#include "audio/sound_input.h"
#include "sim/haptic_loop.h"

namespace dentsim::audio {

class SoundFeed {
 public:
  // The input for `state`, taken at its loop time. The removal rate and each tissue's share of it
  // are over the time since the previous call. A state whose time runs backward (a new segment's
  // loop starts at 0) or a first call starts the rates over. `handpiece_mm` places the sources.
  SoundInput next(const HapticState& state, const Vec3& handpiece_mm);

 private:
  bool started_ = false;
  double last_t_s_ = 0.0;
  std::array<double, DS_MATERIAL_COUNT> last_removed_{};  // the loop's totals by Material at the last call
  std::array<double, kTissueCount> share_{};                  // kept while nothing is cut, so colour never jumps
};

}  // namespace dentsim::audio
