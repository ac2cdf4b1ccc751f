// OrbitCamera and the plane, reflection and conversion helpers: the camera math the renderer and the virtual pen share.
#include "render/camera.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cctype>
#include <cmath>
#include <string>

#include <glm/ext/matrix_clip_space.hpp>

namespace dentsim::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kHalfPi = kMaxPitchRad;

// The distance setView leaves is this much more than the one at which the tooth's bounding sphere
// just touches the top and bottom of the view, so the outline never runs into the edge.
constexpr float kFillMargin = 1.15f;

struct PresetInfo {
  ViewPreset preset;
  std::string_view name;
  float yaw_rad;    // the eye's azimuth about +z from +x
  float pitch_rad;  // the eye's elevation
};

constexpr std::array<PresetInfo, 5> kPresets{{
    {ViewPreset::Occlusal, "occlusal", -kHalfPi, kHalfPi},  // the buccal view tipped over the crown
    {ViewPreset::Buccal, "buccal", -kHalfPi, 0.0f},         // eye on -y
    {ViewPreset::Lingual, "lingual", kHalfPi, 0.0f},        // eye on +y
    {ViewPreset::Mesial, "mesial", float(kPi), 0.0f},       // eye on -x
    {ViewPreset::Distal, "distal", 0.0f, 0.0f},             // eye on +x
}};

}  // namespace

// ---- 1. view presets ----------------------------------------------------------------------------

std::string_view viewPresetName(ViewPreset preset) {
  for (const PresetInfo& p : kPresets)
    if (p.preset == preset) return p.name;
  return "unknown";
}

Result<ViewPreset> parseViewPreset(std::string_view name) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](char c) { return char(std::tolower(static_cast<unsigned char>(c))); });
  for (const PresetInfo& p : kPresets)
    if (p.name == lower) return p.preset;
  return Error{"unknown view '" + std::string(name) + "' (occlusal, buccal, lingual, mesial, distal)"};
}

// ---- 2. the orbit camera ------------------------------------------------------------------------

void OrbitCamera::setDistance(float mm) {
  assert(std::isfinite(mm));
  distance_ = std::clamp(mm, min_distance_, max_distance_);
}

void OrbitCamera::setAngles(float yaw_rad, float pitch_rad) {
  assert(std::isfinite(yaw_rad) && std::isfinite(pitch_rad));
  // Wrapping keeps the angle small, so float keeps its precision however long the user orbits.
  yaw_ = float(std::remainder(double(yaw_rad), 2.0 * kPi));
  pitch_ = std::clamp(pitch_rad, -kMaxPitchRad, kMaxPitchRad);
}

void OrbitCamera::setFovY(float radians) {
  assert(radians > 0.0f && double(radians) < kPi);
  fov_y_ = radians;
}

void OrbitCamera::setClip(float near_mm, float far_mm) {
  assert(near_mm > 0.0f && near_mm < far_mm);
  near_mm_ = near_mm;
  far_mm_ = far_mm;
}

void OrbitCamera::setDistanceLimits(float min_mm, float max_mm) {
  assert(min_mm > 0.0f && min_mm <= max_mm);
  min_distance_ = min_mm;
  max_distance_ = max_mm;
  setDistance(distance_);
}

CameraBasis OrbitCamera::basis() const {
  const double cy = std::cos(double(yaw_)), sy = std::sin(double(yaw_));
  const double cp = std::cos(double(pitch_)), sp = std::sin(double(pitch_));
  CameraBasis b;
  b.forward = glm::vec3(float(-cp * cy), float(-cp * sy), float(-sp));
  b.right = glm::vec3(float(-sy), float(cy), 0.0f);
  // up = right x forward, expanded: unit because right and forward are orthonormal for every pitch.
  b.up = glm::vec3(float(-sp * cy), float(-sp * sy), float(cp));
  return b;
}

glm::vec3 OrbitCamera::eye() const { return target_ - basis().forward * distance_; }

glm::mat4 OrbitCamera::view() const {
  const CameraBasis b = basis();
  const glm::vec3 e = eye();
  // Rows: eye X = right, eye Y = up, eye Z = -forward (the camera looks down -Z); then the eye to the origin.
  glm::mat4 v(1.0f);
  for (int i = 0; i < 3; ++i) {
    v[i][0] = b.right[i];
    v[i][1] = b.up[i];
    v[i][2] = -b.forward[i];
  }
  v[3][0] = -glm::dot(b.right, e);
  v[3][1] = -glm::dot(b.up, e);
  v[3][2] = glm::dot(b.forward, e);
  return v;
}

glm::mat4 OrbitCamera::projection(float aspect) const {
  assert(aspect > 0.0f);
  glm::mat4 p = glm::perspectiveRH_ZO(fov_y_, aspect, near_mm_, far_mm_);
  // Vulkan's clip y points down the screen; glm's (OpenGL's) points up.
  p[1][1] = -p[1][1];
  return p;
}

glm::mat4 OrbitCamera::viewProjection(float aspect) const { return projection(aspect) * view(); }

void OrbitCamera::orbit(float dyaw_rad, float dpitch_rad) { setAngles(yaw_ + dyaw_rad, pitch_ + dpitch_rad); }

void OrbitCamera::zoom(float factor) {
  assert(factor > 0.0f);
  setDistance(distance_ / factor);
}

void OrbitCamera::pan(float dx_mm, float dy_mm) {
  const CameraBasis b = basis();
  target_ += b.right * dx_mm + b.up * dy_mm;
}

void OrbitCamera::setView(ViewPreset preset, const glm::vec3& tooth_centre, float tooth_radius_mm) {
  assert(tooth_radius_mm > 0.0f);
  for (const PresetInfo& p : kPresets) {
    if (p.preset != preset) continue;
    setAngles(p.yaw_rad, p.pitch_rad);
    break;
  }
  target_ = tooth_centre;
  setDistance(kFillMargin * tooth_radius_mm / float(std::sin(0.5 * double(fov_y_))));
}

float OrbitCamera::mmPerPixel(float depth_mm, int viewport_h) const {
  assert(viewport_h > 0);
  return float(2.0 * double(depth_mm) * std::tan(0.5 * double(fov_y_)) / double(viewport_h));
}

float OrbitCamera::depthOf(const glm::vec3& p) const { return glm::dot(p - eye(), basis().forward); }

glm::vec3 OrbitCamera::pixelsToWorld(float dpx, float dpy, int viewport_h, const glm::vec3& at) const {
  const CameraBasis b = basis();
  const float s = mmPerPixel(depthOf(at), viewport_h);
  // Screen y grows down, against the up vector.
  return b.right * (dpx * s) - b.up * (dpy * s);
}

glm::vec3 OrbitCamera::project(const glm::vec3& p, int width, int height) const {
  assert(width > 0 && height > 0);
  // The matrix is the float one the GPU gets; the arithmetic after it is double, so that a
  // project/unproject round trip loses only what the float matrix itself does.
  const glm::dmat4 vp(viewProjection(float(width) / float(height)));
  const glm::dvec4 clip = vp * glm::dvec4(glm::dvec3(p), 1.0);
  assert(clip.w > 0.0);
  const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
  // Vulkan's viewport transform: ndc -1..1 onto 0..size, y already pointing down.
  return {float((ndc.x + 1.0) * 0.5 * width), float((ndc.y + 1.0) * 0.5 * height), float(ndc.z)};
}

glm::vec3 OrbitCamera::unproject(float px, float py, float depth, int width, int height) const {
  assert(width > 0 && height > 0);
  const glm::dmat4 inv = glm::inverse(glm::dmat4(viewProjection(float(width) / float(height))));
  const glm::dvec4 ndc(2.0 * px / width - 1.0, 2.0 * py / height - 1.0, double(depth), 1.0);
  const glm::dvec4 world = inv * ndc;
  return glm::vec3(glm::dvec3(world) / world.w);
}

// ---- 3. planes and reflections ------------------------------------------------------------------

glm::vec4 planeEquation(const glm::vec3& point_on_plane, const glm::vec3& unit_normal) {
  return {unit_normal, -glm::dot(unit_normal, point_on_plane)};
}

glm::mat4 reflectionMatrix(const glm::vec3& point_on_plane, const glm::vec3& unit_normal) {
  assert(std::abs(glm::dot(unit_normal, unit_normal) - 1.0f) < 1e-4f);
  const glm::vec3& n = unit_normal;
  // I - 2 n n^T, then the shift 2 (p.n) n that puts the plane back on itself (column-major: m[col][row]).
  glm::mat4 m(1.0f);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m[c][r] -= 2.0f * n[r] * n[c];
  const glm::vec3 shift = 2.0f * glm::dot(point_on_plane, n) * n;
  m[3] = glm::vec4(shift, 1.0f);
  return m;
}

// ---- 4. conversions -----------------------------------------------------------------------------

glm::vec3 toGlm(const Vec3& v) { return {float(v.x), float(v.y), float(v.z)}; }

Vec3 fromGlm(const glm::vec3& v) { return {double(v.x), double(v.y), double(v.z)}; }

glm::mat4 toGlm(const Pose& pose) {
  const std::array<double, 9> r = pose.rotation.matrix();  // row-major
  glm::mat4 m(1.0f);
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) m[c][row] = float(r[size_t(row * 3 + c)]);
  m[3] = glm::vec4(toGlm(pose.position), 1.0f);
  return m;
}

}  // namespace dentsim::render
