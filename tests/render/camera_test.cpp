// The orbit camera against hand-worked values: preset axes, Vulkan clip space, pixel drags, the mirror's reflection, pose conversion.
#include "render/camera.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dentsim::render {
namespace {

constexpr float kTol = 1e-5f;  // float rounding of unit vectors and matrices

void expectNear(const glm::vec3& got, const glm::vec3& want, float tol) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

glm::vec3 transformPoint(const glm::mat4& m, const glm::vec3& p) {
  const glm::vec4 q = m * glm::vec4(p, 1.0f);
  return glm::vec3(q) / q.w;
}

struct PresetCase {
  ViewPreset preset;
  glm::vec3 forward;  // the stated viewing axis
  glm::vec3 right;    // worked from right = (-sin yaw, cos yaw, 0)
  glm::vec3 up;
};

// Each preset looks along its axis, keeps the crown (or, occlusally, the lingual side) up, and
// puts the tooth's centre in the middle of the viewport.
TEST(OrbitCamera, PresetsLookAlongTheirAxesAtTheToothCentre) {
  const PresetCase cases[] = {
      {ViewPreset::Occlusal, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}},
      {ViewPreset::Buccal, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}},
      {ViewPreset::Lingual, {0, -1, 0}, {-1, 0, 0}, {0, 0, 1}},
      {ViewPreset::Mesial, {1, 0, 0}, {0, -1, 0}, {0, 0, 1}},
      {ViewPreset::Distal, {-1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
  };
  const glm::vec3 centre{1.0f, -2.0f, -3.0f};
  const float radius = 11.0f;
  for (const PresetCase& c : cases) {
    SCOPED_TRACE(std::string(viewPresetName(c.preset)));
    OrbitCamera cam;
    cam.setView(c.preset, centre, radius);
    const CameraBasis b = cam.basis();
    expectNear(b.forward, c.forward, kTol);
    expectNear(b.right, c.right, kTol);
    expectNear(b.up, c.up, kTol);
    expectNear(cam.target(), centre, 0.0f);
    expectNear(cam.eye(), centre - c.forward * cam.distance(), 1e-4f);
    // The bounding sphere's angular radius asin(r/d) fits inside half the field of view and fills most of it.
    const double half_fov = 0.5 * cam.fovY();
    const double angular = std::asin(radius / cam.distance());
    EXPECT_LT(angular, half_fov);
    EXPECT_GT(angular, 0.8 * half_fov);
    const glm::vec3 px = cam.project(centre, 800, 600);
    EXPECT_NEAR(px.x, 400.0f, 1e-3f);
    EXPECT_NEAR(px.y, 300.0f, 1e-3f);
  }
}

TEST(OrbitCamera, PresetNamesRoundTrip) {
  for (ViewPreset p : {ViewPreset::Occlusal, ViewPreset::Buccal, ViewPreset::Lingual, ViewPreset::Mesial,
                       ViewPreset::Distal}) {
    const Result<ViewPreset> parsed = parseViewPreset(viewPresetName(p));
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(*parsed, p);
  }
  const Result<ViewPreset> upper = parseViewPreset("Occlusal");
  ASSERT_TRUE(upper.ok());
  EXPECT_EQ(*upper, ViewPreset::Occlusal);
  const Result<ViewPreset> bad = parseViewPreset("apical");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("unknown view 'apical'"), std::string::npos);
}

// Eye space: the eye at the origin, the target straight ahead at -distance on Z, right on +X, up on +Y.
TEST(OrbitCamera, ViewMatrixIsRightHandedLookingDownMinusZ) {
  OrbitCamera cam;
  cam.setTarget({2.0f, 3.0f, 4.0f});
  cam.setDistance(50.0f);
  cam.setAngles(0.4f, 0.3f);
  const CameraBasis b = cam.basis();
  const glm::mat4 v = cam.view();
  expectNear(transformPoint(v, cam.eye()), {0, 0, 0}, 1e-4f);
  expectNear(transformPoint(v, cam.target()), {0, 0, -50}, 1e-4f);
  expectNear(transformPoint(v, cam.target() + b.right), {1, 0, -50}, 1e-4f);
  expectNear(transformPoint(v, cam.target() + b.up), {0, 1, -50}, 1e-4f);
  expectNear(glm::cross(b.right, b.up), -b.forward, kTol);
  // The eye from the angles: target + d (cos p cos y, cos p sin y, sin p).
  const glm::vec3 want = cam.target() + 50.0f * glm::vec3(std::cos(0.3f) * std::cos(0.4f),
                                                            std::cos(0.3f) * std::sin(0.4f), std::sin(0.3f));
  expectNear(cam.eye(), want, 1e-4f);
}

// Vulkan: y down the screen, depth 0 at the near plane and 1 at the far plane.
TEST(OrbitCamera, ProjectionIsVulkanClipSpace) {
  OrbitCamera cam;
  cam.setView(ViewPreset::Buccal, {0, 0, 0}, 10.0f);
  cam.setClip(2.0f, 400.0f);
  const glm::vec3 eye = cam.eye();
  const CameraBasis b = cam.basis();
  EXPECT_NEAR(cam.project(eye + 2.0f * b.forward, 640, 480).z, 0.0f, 1e-6f);
  EXPECT_NEAR(cam.project(eye + 400.0f * b.forward, 640, 480).z, 1.0f, 1e-6f);
  // A point on the upper edge of the vertical field of view lands on pixel row 0; one on the right
  // edge (aspect 4:3) on column 640.
  const float d = cam.distance();
  const float t = std::tan(0.5f * cam.fovY());
  const glm::vec3 top = cam.project(cam.target() + b.up * (d * t), 640, 480);
  EXPECT_NEAR(top.x, 320.0f, 1e-3f);
  EXPECT_NEAR(top.y, 0.0f, 1e-3f);
  const glm::vec3 right = cam.project(cam.target() + b.right * (d * t * 640.0f / 480.0f), 640, 480);
  EXPECT_NEAR(right.x, 640.0f, 1e-3f);
  EXPECT_NEAR(right.y, 240.0f, 1e-3f);
}

TEST(OrbitCamera, ProjectUnprojectRoundTrip) {
  OrbitCamera cam;
  cam.setView(ViewPreset::Mesial, {0.5f, -0.5f, -2.0f}, 12.0f);
  cam.orbit(0.3f, 0.2f);
  const glm::vec3 points[] = {{0, 0, 0}, {5, -3, 7}, {-8, 6, -12}, {1.25f, 9, 3}};
  for (const glm::vec3& p : points) {
    const glm::vec3 s = cam.project(p, 1280, 720);
    expectNear(cam.unproject(s.x, s.y, s.z, 1280, 720), p, 2e-3f);
  }
  const glm::vec3 w = cam.unproject(100.5f, 600.25f, 0.97f, 1280, 720);
  const glm::vec3 s = cam.project(w, 1280, 720);
  EXPECT_NEAR(s.x, 100.5f, 1e-2f);
  EXPECT_NEAR(s.y, 600.25f, 1e-2f);
  EXPECT_NEAR(s.z, 0.97f, 1e-5f);
}

// A drag of N pixels moves a point at depth D by 2 D tan(fov/2) N / h, and that point stays under the cursor.
TEST(OrbitCamera, DragMovesTheAnalyticDistanceAtThatDepth) {
  OrbitCamera cam;
  cam.setView(ViewPreset::Buccal, {0, 0, 0}, 10.0f);
  const int w = 1000, h = 700;
  const glm::vec3 at{3.0f, 8.0f, -2.0f};  // buccal view: depth = distance + 8 (forward is +y)
  const double depth = double(cam.distance()) + 8.0;
  EXPECT_NEAR(cam.depthOf(at), depth, 1e-4);
  const double n = 37.0;
  const double want = 2.0 * depth * std::tan(0.5 * double(cam.fovY())) * n / h;

  const glm::vec3 dx = cam.pixelsToWorld(float(n), 0.0f, h, at);
  expectNear(dx, {float(want), 0, 0}, 1e-5f);  // right is +x
  const glm::vec3 dy = cam.pixelsToWorld(0.0f, float(n), h, at);
  expectNear(dy, {0, 0, float(-want)}, 1e-5f);  // screen down is -z

  const glm::vec3 before = cam.project(at, w, h);
  const glm::vec3 after = cam.project(at + dx + dy, w, h);
  EXPECT_NEAR(after.x - before.x, n, 1e-3);
  EXPECT_NEAR(after.y - before.y, n, 1e-3);
}

// Plane through (1,0,0) with normal (1,2,2)/3: a point (1,0,0) + t n mirrors to (1,0,0) - t n.
TEST(Reflection, IsAnInvolutionWithDeterminantMinusOne) {
  const glm::vec3 p0{1, 0, 0};
  const glm::vec3 n = glm::vec3(1, 2, 2) / 3.0f;
  const glm::mat4 r = reflectionMatrix(p0, n);
  EXPECT_NEAR(glm::determinant(r), -1.0f, kTol);
  const glm::mat4 rr = r * r;
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(rr[c][k], c == k ? 1.0f : 0.0f, kTol);
  // Points on the plane stay: (1,0,0) + any direction orthogonal to n.
  for (const glm::vec3& q : {p0, p0 + glm::vec3(2, -1, 0), p0 + glm::vec3(0, 3, -3)})
    expectNear(transformPoint(r, q), q, kTol);
  // The normal, as a direction (w = 0), turns into minus itself.
  expectNear(glm::vec3(r * glm::vec4(n, 0.0f)), -n, kTol);
  expectNear(transformPoint(r, p0 + 2.5f * n), p0 - 2.5f * n, 1e-5f);

  const glm::vec4 plane = planeEquation(p0, n);
  EXPECT_NEAR(glm::dot(plane, glm::vec4(p0 + 2.5f * n, 1.0f)), 2.5f, kTol);
  EXPECT_NEAR(glm::dot(plane, glm::vec4(p0 - 0.5f * n, 1.0f)), -0.5f, kTol);
}

// The mirror pass draws with view * R: what it shows of p is what the camera shows of p's mirror
// image; and the reflected camera's eye is the mirror image of the eye.
TEST(Reflection, ReflectedCameraSeesTheMirrorImage) {
  OrbitCamera cam;
  cam.setView(ViewPreset::Buccal, {0, 0, 0}, 10.0f);
  const glm::mat4 r = reflectionMatrix({5, 0, 0}, {1, 0, 0});  // the plane x = 5
  const glm::mat4 reflected_view = cam.view() * r;
  const glm::vec3 p{2, 1, 3}, image{8, 1, 3};  // x -> 10 - x
  expectNear(transformPoint(reflected_view, p), transformPoint(cam.view(), image), 1e-4f);
  const glm::vec3 eye = cam.eye();
  expectNear(transformPoint(glm::inverse(reflected_view), {0, 0, 0}), {10.0f - eye.x, eye.y, eye.z}, 1e-3f);
}

// Past the pole the pitch stops at pi/2 (straight down), and the basis there stays orthonormal with
// the up vector continuous: no flip however far the drag goes.
TEST(OrbitCamera, PitchStopsAtThePoles) {
  OrbitCamera cam;
  cam.setAngles(-kMaxPitchRad, 1.2f);
  const glm::vec3 up_before = cam.basis().up;
  cam.orbit(0.0f, 10.0f);
  EXPECT_EQ(cam.pitch(), kMaxPitchRad);
  const CameraBasis b = cam.basis();
  expectNear(b.forward, {0, 0, -1}, kTol);
  expectNear(b.up, {0, 1, 0}, kTol);
  EXPECT_GT(glm::dot(b.up, up_before), 0.0f);  // up turned toward +y, never away from it
  EXPECT_NEAR(glm::dot(b.right, b.up), 0.0f, kTol);
  EXPECT_NEAR(glm::dot(b.right, b.forward), 0.0f, kTol);
  EXPECT_NEAR(glm::dot(b.up, b.forward), 0.0f, kTol);
  cam.orbit(0.0f, -25.0f);
  EXPECT_EQ(cam.pitch(), -kMaxPitchRad);
  expectNear(cam.basis().forward, {0, 0, 1}, kTol);
  // Yaw has no limit; it wraps.
  cam.setAngles(0.0f, 0.0f);
  cam.orbit(7.0f, 0.0f);
  EXPECT_NEAR(cam.yaw(), 7.0 - 2.0 * 3.14159265358979, 1e-6);
}

TEST(OrbitCamera, ZoomIsClamped) {
  OrbitCamera cam;
  cam.setDistanceLimits(10.0f, 200.0f);
  cam.setDistance(60.0f);
  cam.zoom(2.0f);
  EXPECT_FLOAT_EQ(cam.distance(), 30.0f);
  cam.zoom(0.5f);
  EXPECT_FLOAT_EQ(cam.distance(), 60.0f);
  cam.zoom(1e6f);
  EXPECT_EQ(cam.distance(), 10.0f);
  cam.zoom(1e-6f);
  EXPECT_EQ(cam.distance(), 200.0f);
  cam.setDistanceLimits(20.0f, 100.0f);  // tighter limits pull the distance in
  EXPECT_EQ(cam.distance(), 100.0f);
}

TEST(OrbitCamera, PanSlidesTargetAndEyeInTheViewPlane) {
  OrbitCamera cam;
  cam.setView(ViewPreset::Distal, {0, 0, 0}, 10.0f);  // right +y, up +z
  const glm::vec3 eye = cam.eye();
  cam.pan(2.0f, -3.0f);
  expectNear(cam.target(), {0, 2, -3}, kTol);
  expectNear(cam.eye(), eye + glm::vec3(0, 2, -3), 1e-4f);
}

TEST(Conversions, PoseMatrixMatchesPoseApply) {
  const Pose pose{{4.0, -5.0, 6.0}, Quat::fromAxisAngle({1.0, 2.0, 3.0}, 0.7)};
  const glm::mat4 m = toGlm(pose);
  for (const Vec3& x : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 0, 19}, Vec3{-25, 0, -5.1}, Vec3{3, -2, 7}}) {
    const Vec3 want = pose.apply(x);
    expectNear(transformPoint(m, toGlm(x)), toGlm(want), 1e-5f);
  }
  EXPECT_EQ(fromGlm(toGlm(Vec3{1.5, -2.25, 3.0})), (Vec3{1.5, -2.25, 3.0}));
}

}  // namespace
}  // namespace dentsim::render
