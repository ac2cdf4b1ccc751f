// The camera's controls and their lock.
#include "ui/camera_control.h"

#include <algorithm>
#include <cmath>

namespace dentsim::ui {

bool CameraControl::orbit(double dx_px, double dy_px) {
  if (fixed_) return false;
  camera_.orbit(float(-dx_px * kOrbitRadPerPx), float(dy_px * kOrbitRadPerPx));
  return true;
}

bool CameraControl::pan(double dx_px, double dy_px, int viewport_h) {
  if (fixed_) return false;
  const float mm = camera_.mmPerPixel(camera_.distance(), std::max(1, viewport_h));
  camera_.pan(float(-dx_px) * mm, float(dy_px) * mm);
  return true;
}

bool CameraControl::zoom(double notches) {
  if (fixed_) return false;
  camera_.zoom(float(std::pow(1.1, notches)));
  return true;
}

bool CameraControl::toolsHideTooth(const Vec3& centre, float radius_mm, std::span<const Vec3> tools) const {
  const glm::vec3 eye = camera_.eye(), c = render::toGlm(centre);
  const glm::vec3 to_c = c - eye;
  const float dist = glm::length(to_c);
  if (dist <= radius_mm) return false;  // the eye inside the tooth's sphere: nothing to dodge
  // The tooth's middle: half its bounding sphere's radius, which takes in the roots and a margin.
  // A tool inside the sphere is the bur at work, what the student is there to see; what hides the
  // tooth is the handpiece, the shank above it and the mirror's handle, outside it.
  const float middle = 0.5f * radius_mm / dist;
  const float cos_middle = std::sqrt(1.0f - middle * middle);
  for (const Vec3& t : tools) {
    if (glm::length(render::toGlm(t) - c) <= radius_mm) continue;
    const glm::vec3 to_t = render::toGlm(t) - eye;
    const float along = glm::dot(to_t, to_c) / dist;  // depth along the line of sight [mm]
    if (along <= 0.0f || along >= dist) continue;       // behind the eye, or behind the tooth's centre
    if (glm::dot(glm::normalize(to_t), to_c / dist) > cos_middle) return true;
  }
  return false;
}

bool CameraControl::showPreset(render::ViewPreset preset, const Vec3& centre, float radius_mm, std::span<const Vec3> tools) {
  if (fixed_) return false;
  camera_.setView(preset, render::toGlm(centre), radius_mm);
  if (!toolsHideTooth(centre, radius_mm, tools)) return true;
  const float yaw = camera_.yaw(), pitch = camera_.pitch();
  constexpr float kStep = 0.0872665f;  // 5 degrees
  // The eye lowered first (off the top, a side view raised is lowered toward the side), then
  // turned either way about the tooth; the first clear view wins, else the preset as it was.
  for (float a = kStep; a <= float(kMaxDodgeRad) + 1e-4f; a += kStep) {
    const float lowered = pitch > 0.0f ? pitch - a : pitch + a;
    for (const auto& [y, p] : {std::pair{yaw, lowered}, std::pair{yaw - a, pitch}, std::pair{yaw + a, pitch}}) {
      camera_.setAngles(y, p);
      if (!toolsHideTooth(centre, radius_mm, tools)) return true;
    }
  }
  camera_.setView(preset, render::toGlm(centre), radius_mm);
  return true;
}

}  // namespace dentsim::ui
