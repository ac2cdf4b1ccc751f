// VirtualPen's follower and PenInput's event mapping: the mouse and keyboard standing in for the haptic pens.
#include "ui/virtual_pen.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace dentsim::ui {
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

// ---- 1. VirtualPen ------------------------------------------------------------------------------

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

// ---- 2. PenInput --------------------------------------------------------------------------------

PenInput::PenInput(const render::OrbitCamera& camera, VirtualPen* drill, VirtualPen* mirror,
                   const PenInputParams& params)
    : camera_(camera), pens_{drill, mirror}, params_(params) {
  for (size_t r = 0; r < pens_.size(); ++r)
    if (pens_[r]) targets_[r] = pens_[r]->target();
  if (drill) pedal_ = drill->pedal();
}

void PenInput::setViewport(int width, int height) {
  assert(width > 0 && height > 0);
  width_ = width;
  height_ = height;
}

void PenInput::setActive(PenRole role) {
  assert(role == PenRole::Drill || role == PenRole::Mirror);
  active_ = role;
}

void PenInput::moveActive(const Pose& pose) {
  targets_[size_t(active_)] = pose;
  if (VirtualPen* p = pen(active_)) p->setTarget(pose);
}

void PenInput::drag(float dpx, float dpy) {
  if (height_ <= 0) return;  // no size reported yet: a pixel has no size in the world
  Pose pose = targets_[size_t(active_)];
  const glm::vec3 delta = camera_.pixelsToWorld(dpx, dpy, height_, render::toGlm(pose.position));
  pose.position += render::fromGlm(delta);
  moveActive(pose);
}

void PenInput::wheel(float steps) {
  Pose pose = targets_[size_t(active_)];
  pose.position += render::fromGlm(camera_.basis().forward) * (double(steps) * params_.wheel_mm_per_step);
  moveActive(pose);
}

void PenInput::rotate(double dyaw_rad, double dpitch_rad) {
  const render::CameraBasis b = camera_.basis();
  Pose pose = targets_[size_t(active_)];
  // World-frame turns applied on the left; the pose is the grip frame, so the grip point stays put.
  const Quat turn = Quat::fromAxisAngle(render::fromGlm(b.up), dyaw_rad) *
                    Quat::fromAxisAngle(render::fromGlm(b.right), dpitch_rad);
  pose.rotation = (turn * pose.rotation).normalized();
  moveActive(pose);
}

void PenInput::wheelPedal(float steps) { setPedal(pedal_ + double(steps) * params_.pedal_per_step); }

void PenInput::setPedal(double pedal) {
  assert(!std::isnan(pedal));
  pedal_ = std::clamp(pedal, 0.0, 1.0);
  if (VirtualPen* p = pen(PenRole::Drill)) p->setPedal(pedal_);
}

void PenInput::setButtons(uint32_t buttons) {
  if (VirtualPen* p = pen(active_)) p->setButtons(buttons);
}

void PenInput::reset(PenRole role, const Pose& pose) {
  const Pose clean{pose.position, pose.rotation.normalized()};
  targets_[size_t(role)] = clean;
  if (VirtualPen* p = pen(role)) p->reset(clean);
}

}  // namespace dentsim::ui
