// SoundFeed: removal rates and tissue shares from the loop's running totals, force and contact from the drill.
#include "audio/sound_feed.h"

#include <algorithm>

namespace dentsim::audio {

SoundInput SoundFeed::next(const HapticState& state, const Vec3& handpiece_mm) {
  SoundInput in;
  in.t_s = state.t_s;
  in.turbine_rpm = state.rpm;
  const ToolState& drill = state.tools[size_t(PenRole::Drill)];
  in.force_n = norm(drill.display.force);
  in.contact = drill.contacts > 0;
  in.handpiece_mm = handpiece_mm;
  const bool restart = !started_ || state.t_s < last_t_s_;
  if (restart) last_removed_ = {};
  const double dt = restart ? state.t_s : state.t_s - last_t_s_;
  std::array<double, kTissueCount> removed{};
  double total = 0.0;
  for (size_t k = 0; k < kTissueCount; ++k) {
    const size_t m = size_t(kTissueTable[k].material);
    removed[k] = std::max(0.0, state.removed_by_material_mm3[m] - last_removed_[m]);
    total += removed[k];
  }
  if (total > 0) {
    for (size_t k = 0; k < kTissueCount; ++k) share_[k] = removed[k] / total;
  }
  in.removal_mm3_per_s = dt > 0 ? total / dt : 0.0;
  in.removal_share = share_;
  last_removed_ = state.removed_by_material_mm3;
  last_t_s_ = state.t_s;
  started_ = true;
  return in;
}

}  // namespace dentsim::audio
