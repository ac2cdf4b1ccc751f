// OrbitCamera: the viewer's camera around the tooth (view, Vulkan projection, presets, screen mapping), and the glm conversions the renderer poses tools with.
//
// Contents
//   1. ViewPreset: the five standard views of a tooth and their CLI names
//   2. OrbitCamera: state, matrices, controls, presets, pixels <-> world
//   3. Planes and reflections (the dental mirror's pass)
//   4. dentsim <-> glm conversions
//
// Frames. The world is the tooth frame (mm, right-handed, src/model/molar_generator.h): x mesiodistal
// (mesial -x, distal +x), y buccolingual (buccal -y, lingual +y), z the long axis, crown up (+z).
// Eye space is right-handed and looks down -Z with +Y up. Clip space is Vulkan's: y points down the
// screen and depth runs 0 (near) .. 1 (far). Pixels count from the top-left corner of the viewport,
// x to the right and y down, in framebuffer units (pixel i's centre is at i + 0.5).
//
// The orbit. The eye sits at target + distance * (cos pitch cos yaw, cos pitch sin yaw, sin pitch)
// and looks at the target. The camera's right vector is (-sin yaw, cos yaw, 0), from the yaw alone,
// so the basis stays regular at the poles themselves: pitch may reach +-pi/2 exactly (the occlusal
// view looks straight down -z), and the clamp there is what keeps "up" from flipping over the top.
#pragma once

#include <cstdint>
#include <string_view>

#include <glm/glm.hpp>

#include "core/result.h"
#include "core/rigid.h"

namespace dentsim::render {

// ---- 1. view presets ----------------------------------------------------------------------------

// Where the viewer stands: occlusal above the crown looking down -z; buccal on -y looking toward
// +y; lingual on +y; mesial on -x; distal on +x. The side views keep the crown up on screen; the
// occlusal view is the buccal view tipped over the crown (distal to the right, lingual up).
enum class ViewPreset : uint8_t { Occlusal, Buccal, Lingual, Mesial, Distal };

// "occlusal", "buccal", "lingual", "mesial", "distal" ("unknown" outside the enum).
std::string_view viewPresetName(ViewPreset preset);
// The preset of a name as viewPresetName spells it (any case). Error: "unknown view 'x' (occlusal, ...)".
Result<ViewPreset> parseViewPreset(std::string_view name);

// ---- 2. the orbit camera ------------------------------------------------------------------------

struct CameraBasis {
  glm::vec3 right;    // screen +x in the world (unit)
  glm::vec3 up;       // screen up in the world (unit): pixel y grows against it
  glm::vec3 forward;  // the viewing direction, eye toward target (unit); right x up = -forward
};

inline constexpr float kMaxPitchRad = 1.57079632679489661923f;  // pi/2: straight down or up [rad]

class OrbitCamera {
 public:
  OrbitCamera() = default;

  // ---- state ----
  const glm::vec3& target() const { return target_; }  // the point orbited and looked at [mm]
  float distance() const { return distance_; }          // eye to target [mm], in [minDistance, maxDistance]
  float yaw() const { return yaw_; }                    // azimuth about +z from +x, in [-pi, pi] [rad]
  float pitch() const { return pitch_; }                // elevation above the xy plane, in [-pi/2, pi/2] [rad]
  float fovY() const { return fov_y_; }                 // vertical field of view [rad]
  float nearMm() const { return near_mm_; }             // near clip distance [mm]
  float farMm() const { return far_mm_; }               // far clip distance [mm]
  float minDistance() const { return min_distance_; }   // zoom limits [mm]
  float maxDistance() const { return max_distance_; }

  void setTarget(const glm::vec3& target_mm) { target_ = target_mm; }
  void setDistance(float mm);                   // clamped to [minDistance, maxDistance]
  void setAngles(float yaw_rad, float pitch_rad);  // yaw wrapped to [-pi, pi], pitch clamped to +-kMaxPitchRad
  void setFovY(float radians);                  // in (0, pi)
  void setClip(float near_mm, float far_mm);    // 0 < near < far
  void setDistanceLimits(float min_mm, float max_mm);  // 0 < min <= max; re-clamps the distance

  // ---- matrices ----
  glm::mat4 view() const;                        // world to eye: right-handed, looking down -Z
  glm::mat4 projection(float aspect) const;      // eye to Vulkan clip space; aspect = width / height
  glm::mat4 viewProjection(float aspect) const;  // projection(aspect) * view()
  glm::vec3 eye() const;                         // the eye's position [mm]
  CameraBasis basis() const;

  // ---- controls ----
  // Turns the eye about the target: yaw about +z, pitch toward +z, both [rad]; pitch stops at the poles.
  void orbit(float dyaw_rad, float dpitch_rad);
  // Divides the distance by factor (> 0): a factor above 1 moves closer, so the tooth looks bigger.
  void zoom(float factor);
  // Slides eye and target together in the view plane: dx along right, dy along up [mm].
  void pan(float dx_mm, float dy_mm);

  // Looks at tooth_centre from the preset's side, far enough that a sphere of tooth_radius_mm about
  // the centre fits the vertical field of view with a small margin (the distance is then clamped).
  void setView(ViewPreset preset, const glm::vec3& tooth_centre, float tooth_radius_mm);

  // ---- pixels and world ----
  // World size of one pixel [mm] at eye depth depth_mm, for a viewport viewport_h pixels high.
  float mmPerPixel(float depth_mm, int viewport_h) const;
  // How far along the view direction `p` lies from the eye [mm] (negative behind the eye).
  float depthOf(const glm::vec3& p) const;
  // The world displacement, in the view plane at the depth of `at`, under a drag of (dpx, dpy)
  // pixels (screen y down): it keeps a point at that depth under the cursor. Its length is
  // 2 * depth * tan(fov/2) * |(dpx, dpy)| / viewport_h [mm].
  glm::vec3 pixelsToWorld(float dpx, float dpy, int viewport_h, const glm::vec3& at) const;
  // Pixel coordinates (x, y from the top-left) and depth (0 near .. 1 far) of world point p in a
  // width x height viewport. p must lie in front of the eye.
  glm::vec3 project(const glm::vec3& p, int width, int height) const;
  // The world point at pixel (px, py) and depth (as project returns them).
  glm::vec3 unproject(float px, float py, float depth, int width, int height) const;

 private:
  glm::vec3 target_{0.0f, 0.0f, 0.0f};
  float distance_ = 60.0f;
  float yaw_ = -kMaxPitchRad;          // -pi/2: the buccal side
  float pitch_ = 0.0f;
  float fov_y_ = 0.6981317f;           // 40 degrees
  float near_mm_ = 1.0f;
  float far_mm_ = 1000.0f;
  float min_distance_ = 5.0f;
  float max_distance_ = 500.0f;
};

// ---- 3. planes and reflections ------------------------------------------------------------------

// The plane through point with unit normal n as (n, -n.point): dot(plane, (x, 1)) is x's signed
// distance from the plane [mm], positive on the normal's side.
glm::vec4 planeEquation(const glm::vec3& point_on_plane, const glm::vec3& unit_normal);

// The affine reflection across that plane: x -> x - 2 ((x - point) . n) n. It is its own inverse and
// has determinant -1, so a pass drawn with view * reflectionMatrix(...) sees the mirror world but
// winds every triangle the other way (swap the front face there).
glm::mat4 reflectionMatrix(const glm::vec3& point_on_plane, const glm::vec3& unit_normal);

// ---- 4. conversions -----------------------------------------------------------------------------

glm::vec3 toGlm(const Vec3& v);  // rounded to float
Vec3 fromGlm(const glm::vec3& v);
// The body-to-world matrix of a pose: toGlm(pose) * (x, 1) = (pose.apply(x), 1), rounded to float.
glm::mat4 toGlm(const Pose& pose);

}  // namespace dentsim::render
