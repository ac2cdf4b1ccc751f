// YieldingHand: the hand's give, a first-order lag toward force / stiffness, added to the scripted reading.
#include "sim/yielding_hand.h"

#include <algorithm>

namespace dentsim {

bool YieldingHand::read(double t_s, PenReading* out) {
  if (!pen_.read(t_s, out)) return false;
  const double dt = started_ ? std::max(0.0, t_s - last_t_) : 0.0;
  started_ = true;
  last_t_ = t_s;
  // An implicit step of the lag: the give closes a share dt / (lag + dt) of its gap, never overshooting.
  const Vec3 target = force_ / settings_.stiffness_n_per_mm;
  const double share = dt / (settings_.lag_s + dt);
  const Vec3 before = give_;
  give_ += (target - give_) * share;
  give_velocity_ = dt > 0 ? (give_ - before) / dt : Vec3{};
  out->grip.position += give_;
  out->velocity += give_velocity_;
  return true;
}

void YieldingHand::display(const Wrench& wrench, double t_s) {
  force_ = finite(wrench.force) ? wrench.force : Vec3{};
  pen_.display(wrench, t_s);
}

}  // namespace dentsim
