// SoundInput and Voice: what the sound engine hears from the simulation each frame, and the mono generators it pulls samples from.
//
// The simulation is sampled at frame rate (or at any block rate a replay chooses); a voice renders
// a block of samples moving its inputs linearly from the block's first state to its last, so that
// pitch and loudness glide instead of stepping at every frame.
#pragma once

#include <array>
#include <span>

#include "core/rigid.h"
#include "volume/tissue_table.h"

namespace dentsim::audio {

struct SoundInput {
  double t_s = 0.0;                 // loop time [s]
  double turbine_rpm = 0.0;         // the speed the pedal commands [1/min] (0..about 40 000)
  double removal_mm3_per_s = 0.0;   // tissue removed per second over the last block [mm^3/s]
  std::array<double, kTissueCount> removal_share{};  // by tissue table row: its share of that removal (sums to 1 while cutting)
  double force_n = 0.0;             // the bur's contact force [N]
  bool contact = false;             // the bur touches tissue
  Vec3 handpiece_mm;                // where the sounds come from, tooth frame [mm]
};

// A mono signal generator. Deterministic: the same inputs give the same samples.
class Voice {
 public:
  virtual ~Voice() = default;
  // Renders out.size() samples at the voice's sample rate, its inputs moving linearly from `from`
  // to `to` over the block. Samples are nominally within [-1, 1].
  virtual void render(const SoundInput& from, const SoundInput& to, std::span<float> out) = 0;
};

}  // namespace dentsim::audio
