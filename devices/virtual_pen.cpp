// VirtualPen's follower: the exact step of a critically damped follower of the UI's targets.
#include "devices/virtual_pen.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace dentsim::devices {
namespace {

struct FollowState {
  Vec3 error;  // follower minus target
  Vec3 rate;   // the follower's velocity
};

// One exact step of dt [s] of x'' = w^2 (r - x) - 2 w x' while the target r moves at the constant
// velocity c. About the ramp's own steady solution (x = r - 2c/w, x' = c) the error eps obeys the
// free critically damped equation, whose solution is eps(t) = (eps0 + (eps0' + w eps0) t) e^(-wt).
// error0 is taken against the target at the step's start; the result's error against the target at its end.
FollowState followStep(const Vec3& error0, const Vec3& rate0, const Vec3& c, double omega, double dt) {
  const Vec3 lag = c * (2.0 / omega);
  const Vec3 eps0 = error0 + lag;
  const Vec3 eta0 = rate0 - c;
  const Vec3 k = eta0 + eps0 * omega;
  const double decay = std::exp(-omega * dt);
  const Vec3 eps1 = (eps0 + k * dt) * decay;
  const Vec3 eta1 = (eta0 - k * (omega * dt)) * decay;
  return {eps1 - lag, c + eta1};
}

// The world-frame rotation vector that takes orientation `from` to `to`.
Vec3 rotationBetween(const Quat& from, const Quat& to) { return (to * from.conjugate()).rotationVector(); }

}  // namespace

VirtualPen::VirtualPen(const Pose& grip, const VirtualPenParams& params)
    : omega_(1.0 / params.follow_time_s) {
  assert(params.follow_time_s > 0.0);
  command_.grip = {grip.position, grip.rotation.normalized()};
  publish();
}

void VirtualPen::publish() { channel_.publish(command_); }

void VirtualPen::setTarget(const Pose& grip) {
  assert(finite(grip.position) && grip.rotation.finite());
  command_.grip = {grip.position, grip.rotation.normalized()};
  publish();
}

void VirtualPen::setButtons(uint32_t buttons) {
  command_.buttons = buttons;
  publish();
}

void VirtualPen::setPedal(double pedal) {
  assert(!std::isnan(pedal));
  command_.pedal = std::clamp(pedal, 0.0, 1.0);
  publish();
}

void VirtualPen::reset(const Pose& grip) {
  assert(finite(grip.position) && grip.rotation.finite());
  command_.grip = {grip.position, grip.rotation.normalized()};
  ++command_.reset_count;
  publish();
}

bool VirtualPen::read(double t_s, PenReading* out) {
  const Command& cmd = channel_.read();
  if (!started_ || cmd.reset_count != reset_seen_ || t_s < last_t_s_) {
    // Nothing to glide from (or told not to): sit on the target, at rest.
    started_ = true;
    reset_seen_ = cmd.reset_count;
    follower_ = cmd.grip;
    velocity_ = {};
    angular_velocity_ = {};
    last_target_ = cmd.grip;
    last_t_s_ = t_s;
  } else if (t_s > last_t_s_) {
    // The target is taken to have moved at constant speed from the last read's command to this one.
    const double dt = t_s - last_t_s_;
    const Vec3 c = (cmd.grip.position - last_target_.position) / dt;
    const FollowState move = followStep(follower_.position - last_target_.position, velocity_, c, omega_, dt);
    follower_.position = cmd.grip.position + move.error;
    velocity_ = move.rate;

    const Vec3 spin = rotationBetween(last_target_.rotation, cmd.grip.rotation) / dt;
    const FollowState turn = followStep(rotationBetween(last_target_.rotation, follower_.rotation),
                                        angular_velocity_, spin, omega_, dt);
    follower_.rotation = (Quat::fromRotationVector(turn.error) * cmd.grip.rotation).normalized();
    angular_velocity_ = turn.rate;

    last_target_ = cmd.grip;
    last_t_s_ = t_s;
  }
  // (t_s equal to the last read's: nothing has elapsed, so the follower stays; the new target is
  // ramped toward over the next step.)
  *out = PenReading{};
  out->grip = follower_;
  out->velocity = velocity_;
  out->angular_velocity = angular_velocity_;
  out->buttons = cmd.buttons;
  out->pedal = cmd.pedal;
  return true;
}

}  // namespace dentsim::devices
