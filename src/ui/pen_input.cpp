// PenInput's event mapping: mouse drags, wheel and keys as targets for the virtual pens.
#include "ui/pen_input.h"

#include <algorithm>
#include <cmath>

namespace dentsim::ui {

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

void PenInput::alongTool(double mm) {
  Pose pose = targets_[size_t(active_)];
  pose.position += pose.rotation.rotate(Vec3{0, 0, 1}) * mm;
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
