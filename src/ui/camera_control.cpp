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

bool CameraControl::showPreset(render::ViewPreset preset, const Vec3& centre, float radius_mm) {
  if (fixed_) return false;
  camera_.setView(preset, render::toGlm(centre), radius_mm);
  return true;
}

}  // namespace dentsim::ui
