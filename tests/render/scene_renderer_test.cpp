// The renderer on lavapipe: Phong shading and silhouettes against analytic values, the tooth and its edits, transparency, the mirror pass, the overlay, determinism.
#include "render/scene_renderer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "gpu/gpu_fixture.h"
#include "model/builtin_assets.h"
#include "render/camera.h"
#include "render/offscreen.h"
#include "render/render_layout.h"
#include "render/tool_mesh.h"
#include "render/tooth_surfaces.h"
#include "sim/builtin_tooth.h"
#include "render/look_params.h"

namespace dentsim::render::test {
namespace {

constexpr uint32_t kW = 160, kH = 120;

struct BurView;

// A graphics context with validation (gpu/gpu_fixture.h); skips only when the machine has no Vulkan device.
class RenderTest : public gpu::test::GraphicsGpuTest {
 protected:
  void TearDown() override {
    if (ctx_) {
      renderer_.reset();
      tooth_.reset();
      EXPECT_TRUE(ctx_->waitIdle().ok());
    }
    GraphicsGpuTest::TearDown();
  }

  SceneRenderer& renderer(const SceneRendererOptions& options = {}) {
    if (!renderer_) {
      auto r = SceneRenderer::create(*ctx_, kDefaultColourFormat, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, options);
      EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.message());
      renderer_.emplace(std::move(*r));
    }
    return *renderer_;
  }

  // An empty tooth (nothing built), for scenes of tools only.
  ToothSurfaces& emptyTooth() {
    if (!tooth_) {
      auto t = ToothSurfaces::create(*ctx_);
      EXPECT_TRUE(t.ok());
      tooth_.emplace(std::move(*t));
    }
    return *tooth_;
  }

  // Replaces the scene's tooth with the surfaces built from `voxels`.
  void buildTooth(const BrickVolume& voxels) {
    auto t = ToothSurfaces::create(*ctx_);
    ASSERT_TRUE(t.ok()) << t.message();
    tooth_.emplace(std::move(*t));
    ASSERT_TRUE(tooth_->build(voxels).ok());
  }

  RgbImage render(const FrameState& frame, uint32_t w = kW, uint32_t h = kH) {
    auto img = renderOffscreen(*ctx_, renderer(), tooth_ ? *tooth_ : emptyTooth(), frame, w, h);
    EXPECT_TRUE(img.ok()) << (img.ok() ? "" : img.message());
    if (!img.ok()) return RgbImage{};
    dump(*img);
    return std::move(*img);
  }

  // The bur of `v` through a renderer whose steel is testSteel().
  RgbImage renderSteelBur(const BurView& v);

  // With DENTSIM_TEST_IMAGES=DIR set, every rendered frame is also written there, to look at.
  void dump(const RgbImage& img) {
    const char* dir = std::getenv("DENTSIM_TEST_IMAGES");
    if (!dir || !*dir) return;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string path = std::string(dir) + "/" + info->name() + "_" + std::to_string(frames_++) + ".png";
    EXPECT_TRUE(writePng(path, img).ok());
  }
  int frames_ = 0;

  std::optional<SceneRenderer> renderer_;
  std::optional<ToothSurfaces> tooth_;
};

std::array<int, 3> px(const RgbImage& img, int x, int y) {
  const auto p = img.pixel(x, y);
  return {p[0], p[1], p[2]};
}

std::array<int, 3> to255(const std::array<float, 3>& c) {
  return {int(std::lround(c[0] * 255.0f)), int(std::lround(c[1] * 255.0f)), int(std::lround(c[2] * 255.0f))};
}

bool isBackground(const RgbImage& img, int x, int y, const std::array<int, 3>& bg) { return px(img, x, y) == bg; }

int maxChannelDiff(const std::array<int, 3>& a, const std::array<int, 3>& b) {
  int d = 0;
  for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(a[c] - b[c]));
  return d;
}

// ---- tools: silhouette and Phong ---------------------------------------------------------------------

// A 1.8 mm round bur seen from straight below its tip through an orthographic camera: its head is a
// ball of radius 0.9 mm centred at z = 0.9, and nothing behind it is wider (the shank is 1.6 mm), so
// the silhouette is that circle and each pixel inside shows the ball's lower half.
struct BurView {
  float half_h = 1.2f;                 // half the view's height [mm]
  float mm_per_px = 2.0f * 1.2f / float(kH);
  glm::vec3 eye{0.0f, 0.0f, -50.0f};
  FrameState frame;

  BurView() {
    frame.view = glm::lookAt(eye, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    const float half_w = half_h * float(kW) / float(kH);
    frame.projection = glm::orthoRH_ZO(-half_w, half_w, -half_h, half_h, 1.0f, 200.0f);
    frame.projection[1][1] = -frame.projection[1][1];  // Vulkan's y down
    frame.eye = eye;
    frame.light_dir = glm::normalize(glm::vec3(0.3f, -0.2f, -1.0f));
    frame.tooth_shown = false;
    frame.bur = "round_bur_018";
    frame.handpiece_shown = false;
  }
  // World x, y of pixel (i, j)'s centre: the camera's right is world -x, its up world +y.
  glm::vec2 world(int i, int j) const {
    return {-(float(i) + 0.5f - float(kW) / 2.0f) * mm_per_px, (float(kH) / 2.0f - (float(j) + 0.5f)) * mm_per_px};
  }
};

TissueLook testSteel() { return {0.10, 0.08, 0.06, 0.50, 0.55, 0.60, 0.30, 0.30, 0.30, 1.0, 8.0}; }

RgbImage RenderTest::renderSteelBur(const BurView& v) {
  SceneRendererOptions options;
  options.steel = testSteel();
  renderer(options);
  return render(v.frame);
}

TEST_F(RenderTest, BurSilhouetteIsTheHeadsCircle) {
  BurView v;
  const RgbImage img = renderSteelBur(v);
  ASSERT_EQ(img.width, int(kW));
  const auto bg = to255(v.frame.background);
  int covered = 0;
  for (int j = 0; j < int(kH); ++j)
    for (int i = 0; i < int(kW); ++i) covered += isBackground(img, i, j, bg) ? 0 : 1;
  const double r_px = 0.9 / double(v.mm_per_px);
  const double expected = 3.14159265358979 * r_px * r_px;
  EXPECT_NEAR(double(covered), expected, 0.03 * expected) << "pixels covered by the bur";
}

// The CPU reference of one pixel: the ray from the pixel's centre along +z (the orthographic view)
// hits the drawn triangles; the nearest hit's normal is the corners' normals interpolated
// barycentrically (what the rasterizer does), and the Phong formula gives its colour.
std::optional<glm::vec3> cpuPixel(const std::vector<ToolVertex>& corners, const BurView& v, int i, int j,
                                  const TissueLook& look) {
  const glm::vec2 w = v.world(i, j);
  const glm::dvec3 o(w.x, w.y, -50.0), d(0.0, 0.0, 1.0);
  double best = 1e30;
  glm::dvec3 normal(0.0);
  for (size_t t = 0; t + 2 < corners.size(); t += 3) {
    const auto pos = [&](size_t k) { return glm::dvec3(corners[k].px, corners[k].py, corners[k].pz); };
    const glm::dvec3 a = pos(t), e1 = pos(t + 1) - a, e2 = pos(t + 2) - a;
    const glm::dvec3 p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (det < 1e-12) continue;  // only triangles facing the viewer (outward normal against the ray)
    const glm::dvec3 s0 = o - a;
    const double u = glm::dot(s0, p) / det;
    const glm::dvec3 q = glm::cross(s0, e1);
    const double vv = glm::dot(d, q) / det, dist = glm::dot(e2, q) / det;
    if (u < 0 || vv < 0 || u + vv > 1 || dist <= 0 || dist >= best) continue;
    best = dist;
    const auto nrm = [&](size_t k) { return glm::dvec3(corners[k].nx, corners[k].ny, corners[k].nz); };
    normal = (1 - u - vv) * nrm(t) + u * nrm(t + 1) + vv * nrm(t + 2);
  }
  if (best == 1e30) return std::nullopt;
  const glm::vec3 hit(float(o.x), float(o.y), float(o.z + best));
  return phongColour(look, glm::normalize(glm::vec3(normal)), v.frame.light_dir, glm::normalize(v.eye - hit));
}

TEST_F(RenderTest, BurShadingMatchesCpuPhong) {
  BurView v;
  const RgbImage img = renderSteelBur(v);
  ASSERT_EQ(img.width, int(kW));
  auto mesh = loadBuiltinTool("round_bur_018");
  ASSERT_TRUE(mesh.ok()) << mesh.message();
  const std::vector<ToolVertex> corners = creasedVertices(*mesh);
  // Every third pixel inside the silhouette, away from its edge (where coverage rules decide).
  int checked = 0, worst = 0;
  for (int j = 0; j < int(kH); j += 3)
    for (int i = 0; i < int(kW); i += 3) {
      if (glm::length(v.world(i, j)) > 0.85f * 0.9f) continue;
      const auto c = cpuPixel(corners, v, i, j, testSteel());
      ASSERT_TRUE(c.has_value()) << "pixel " << i << "," << j << " misses the bur";
      const int d = maxChannelDiff(px(img, i, j), to255({c->x, c->y, c->z}));
      if (d > worst) worst = d;
      ++checked;
    }
  EXPECT_GT(checked, 300);
  EXPECT_LE(worst, 2) << "largest channel difference from the CPU Phong formula [1/255]";
}

TEST_F(RenderTest, BurTurnsRedWithForce) {
  BurView v;
  const RgbImage cold = render(v.frame);
  v.frame.drill_force_n = 8.0;
  v.frame.max_force_n = 8.0;
  const RgbImage hot = render(v.frame);
  const auto c = px(cold, int(kW) / 2, int(kH) / 2), h = px(hot, int(kW) / 2, int(kH) / 2);
  EXPECT_GT(h[0] - h[2], c[0] - c[2] + 40) << "the centre pixel is redder at the maximum force";
}

// ---- the tooth ---------------------------------------------------------------------------------------

struct ToothScene {
  ToothVolume tooth;
  glm::vec3 centre{0.0f};
  float radius = 0.0f;
  OrbitCamera camera;
  FrameState frame;
};

ToothScene toothScene(int level, ViewPreset preset) {
  ToothScene s;
  auto t = builtinMolarTooth(level);
  EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.message());
  s.tooth = std::move(*t);
  const VolumeFrame& f = s.tooth.frame;
  const float side = float(f.voxel_mm * double(f.dim()));
  s.centre = glm::vec3(float(f.origin_mm[0]), float(f.origin_mm[1]), float(f.origin_mm[2])) + glm::vec3(side / 2.0f);
  s.radius = side / 2.0f;
  s.camera.setView(preset, s.centre, s.radius);
  s.frame.view = s.camera.view();
  s.frame.projection = s.camera.projection(float(kW) / float(kH));
  s.frame.eye = s.camera.eye();
  s.frame.light_dir = glm::normalize(s.camera.eye() - s.centre);
  s.frame.tooth_frame = f;
  s.frame.looks = defaultLookParams().looks;
  s.frame.drill_shown = false;
  return s;
}

TEST_F(RenderTest, OcclusalToothShowsEnamelAndItsCarvedHole) {
  ToothScene s = toothScene(7, ViewPreset::Occlusal);
  ASSERT_NO_FATAL_FAILURE(buildTooth(s.tooth.voxels));
  // Opaque enamel for this test, so every tooth pixel is enamel-shaded; the molar's occlusal caries
  // reaches the surface, so it takes the enamel's look here.
  s.frame.looks[size_t(Material::Enamel)].alpha = 1.0;
  s.frame.looks[size_t(Material::Caries)] = s.frame.looks[size_t(Material::Enamel)];
  // Full detail: a cut that switches a region to another copy would change pixels away from it.
  s.frame.lod.pixel_error = 0.0f;
  const auto t0 = std::chrono::steady_clock::now();
  const RgbImage before = render(s.frame);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ info ] offscreen frame of the level-7 molar, %ux%u: %.1f ms\n", kW, kH, ms);
  ASSERT_EQ(before.width, int(kW));

  // Tooth pixels lie between the enamel's ambient colour and ambient + diffuse + specular.
  const TissueLook& e = s.frame.looks[size_t(Material::Enamel)];
  const std::array<double, 3> lo{e.ambient_r, e.ambient_g, e.ambient_b};
  const std::array<double, 3> hi{e.ambient_r + e.diffuse_r + e.specular_r, e.ambient_g + e.diffuse_g + e.specular_g,
                                 e.ambient_b + e.diffuse_b + e.specular_b};
  const auto bg = to255(s.frame.background);
  int tooth_px = 0, outside_range = 0;
  for (int j = 0; j < int(kH); ++j)
    for (int i = 0; i < int(kW); ++i) {
      if (isBackground(before, i, j, bg)) continue;
      ++tooth_px;
      const auto p = px(before, i, j);
      for (int c = 0; c < 3; ++c)
        if (p[c] < int(lo[c] * 255.0) - 1 || p[c] > int(std::min(hi[c], 1.0) * 255.0) + 1) {
          ++outside_range;
          break;
        }
    }
  EXPECT_GT(tooth_px, int(kW * kH) / 8) << "the crown fills a good part of the view";
  EXPECT_EQ(outside_range, 0) << "of " << tooth_px << " tooth pixels";

  // Carve a ball out of the crown's top near its middle: the highest solid voxel of the centre column.
  BrickVolume& vol = s.tooth.voxels;
  const uint32_t dim = vol.dim(), cx = dim / 2, cy = dim / 2;
  uint32_t top = 0;
  for (uint32_t z = 0; z < dim; ++z)
    if (voxelMaterial(vol.voxel(cx, cy, z)) != Material::Empty) top = z;
  ASSERT_GT(top, 0u);
  const int r = 6;
  std::set<std::tuple<uint32_t, uint32_t, uint32_t>> dirty_set;
  for (int dz = -r; dz <= r; ++dz)
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        if (dx * dx + dy * dy + dz * dz > r * r) continue;
        const uint32_t x = cx + uint32_t(dx), y = cy + uint32_t(dy), z = top + uint32_t(dz);
        if (z >= dim) continue;
        vol.setVoxel(x, y, z, makeVoxel(Material::Empty));
        dirty_set.insert({x >> DS_BRICK_LOG2, y >> DS_BRICK_LOG2, z >> DS_BRICK_LOG2});
      }
  std::vector<BrickCoord> dirty;
  for (auto [x, y, z] : dirty_set) dirty.push_back({x, y, z});
  ASSERT_TRUE(tooth_->update(vol, dirty).ok());
  const RgbImage after = render(s.frame);

  // Pixels over the hole change; pixels well away from it stay exactly as they were.
  const VolumeFrame& f = s.tooth.frame;
  const glm::vec3 hole = glm::vec3(float(f.origin_mm[0]), float(f.origin_mm[1]), float(f.origin_mm[2])) +
                         float(f.voxel_mm) * glm::vec3(float(cx) + 0.5f, float(cy) + 0.5f, float(top) + 0.5f);
  const glm::vec3 hp = s.camera.project(hole, int(kW), int(kH));
  const float hole_px = float(r) * float(f.voxel_mm) / s.camera.mmPerPixel(s.camera.depthOf(hole), int(kH));
  int near_changed = 0, far_changed = 0;
  for (int j = 0; j < int(kH); ++j)
    for (int i = 0; i < int(kW); ++i) {
      const float d = glm::length(glm::vec2(float(i) + 0.5f, float(j) + 0.5f) - glm::vec2(hp));
      const bool changed = px(before, i, j) != px(after, i, j);
      if (d < 0.7f * hole_px) near_changed += changed ? 1 : 0;
      if (d > 2.5f * hole_px + 4.0f) far_changed += changed ? 1 : 0;
    }
  EXPECT_GT(near_changed, int(0.5f * 3.14159f * 0.49f * hole_px * hole_px)) << "hole radius " << hole_px << " px";
  EXPECT_EQ(far_changed, 0);
}

TEST_F(RenderTest, TranslucentEnamelShowsTheDentin) {
  ToothScene s = toothScene(6, ViewPreset::Occlusal);
  ASSERT_NO_FATAL_FAILURE(buildTooth(s.tooth.voxels));
  // Grey enamel (and caries), red dentin and pulp: any red in a pixel came from beneath the enamel.
  const TissueLook grey{0.2, 0.2, 0.2, 0.6, 0.6, 0.6, 0.0, 0.0, 0.0, 1.0, 8.0};
  const TissueLook red{0.3, 0.0, 0.0, 0.7, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 8.0};
  s.frame.looks[size_t(Material::Enamel)] = grey;
  s.frame.looks[size_t(Material::Caries)] = grey;
  s.frame.looks[size_t(Material::Dentin)] = red;
  s.frame.looks[size_t(Material::Pulp)] = red;
  const auto reddish = [&](const RgbImage& img) {
    int n = 0;
    for (int j = 0; j < img.height; ++j)
      for (int i = 0; i < img.width; ++i) {
        const auto p = px(img, i, j);
        n += p[0] - p[1] > 30 ? 1 : 0;
      }
    return n;
  };
  const RgbImage opaque = render(s.frame);
  s.frame.looks[size_t(Material::Enamel)].alpha = 0.3;
  s.frame.looks[size_t(Material::Caries)].alpha = 0.3;
  const RgbImage translucent = render(s.frame);
  EXPECT_EQ(reddish(opaque), 0) << "opaque enamel hides the dentin";
  EXPECT_GT(reddish(translucent), int(kW * kH) / 20) << "dentin shows through enamel of alpha 0.3";
}

TEST_F(RenderTest, OffscreenFramesAreDeterministic) {
  ToothScene s = toothScene(6, ViewPreset::Buccal);
  ASSERT_NO_FATAL_FAILURE(buildTooth(s.tooth.voxels));
  s.frame.drill_shown = true;
  s.frame.drill.position = fromGlm(s.centre + glm::vec3(0.0f, 0.0f, s.radius * 0.5f));
  const RgbImage a = render(s.frame);
  const RgbImage b = render(s.frame);
  ASSERT_EQ(a.rgb.size(), size_t(kW) * kH * 3);
  EXPECT_EQ(a.rgb, b.rgb);
}

// ---- the mirror --------------------------------------------------------------------------------------

// A mirror on the tooth's lingual side (+y), its face turned 45 degrees toward the tooth and up toward
// an eye above the crown: it shows the crown's lingual side.
struct MirrorScene {
  ToothScene s;
  glm::vec3 point{0.0f}, normal{0.0f};
};

MirrorScene mirrorScene() {
  MirrorScene m{toothScene(6, ViewPreset::Occlusal)};
  // Full detail: where two copies of the tooth overlap at a border their surfaces nearly coincide,
  // and the last bit of a reflected matrix decides which one a pixel shows (tooth_lod_test.cpp
  // checks that the mirror pass chooses the copies the reflected camera would).
  m.s.frame.lod.pixel_error = 0.0f;
  m.s.camera.setDistance(m.s.camera.distance() * 1.6f);
  m.s.camera.setTarget(m.s.centre + glm::vec3(0.0f, m.s.radius * 0.6f, 0.0f));
  m.s.frame.view = m.s.camera.view();
  m.s.frame.eye = m.s.camera.eye();
  m.point = m.s.centre + glm::vec3(0.0f, m.s.radius * 1.25f, m.s.radius * 0.3f);
  m.normal = glm::normalize(glm::vec3(0.0f, -1.0f, 1.0f));
  // The mirror frame's +Z onto the normal: a rotation of 45 degrees about +x.
  m.s.frame.mirror.position = fromGlm(m.point);
  m.s.frame.mirror.rotation = Quat::fromAxisAngle({1.0, 0.0, 0.0}, 3.14159265358979 / 4.0);
  m.s.frame.mirror_shown = true;
  return m;
}

TEST_F(RenderTest, MirrorImageEqualsTheReflectedCamerasView) {
  SceneRendererOptions options;
  options.mirror_resolution = 128;
  renderer(options);
  MirrorScene m = mirrorScene();
  ASSERT_NO_FATAL_FAILURE(buildTooth(m.s.tooth.voxels));

  const RgbImage main = render(m.s.frame);
  ASSERT_TRUE(renderer().mirrorDrawn());
  auto mirror = readImage(ctx(), renderer().mirrorImage(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  ASSERT_TRUE(mirror.ok()) << mirror.message();

  // The same scene drawn directly with the reflected view, clipped at the glass, at the mirror's size.
  FrameState direct = m.s.frame;
  const glm::mat4 reflect = reflectionMatrix(m.point, m.normal);
  direct.view = m.s.frame.view * reflect;
  direct.eye = glm::vec3(reflect * glm::vec4(m.s.frame.eye, 1.0f));
  direct.clip_plane = planeEquation(m.point, m.normal);
  direct.mirror_shown = false;
  const RgbImage want = render(direct, 128, 128);
  ASSERT_EQ(mirror->rgb.size(), want.rgb.size());
  int differ = 0, tooth_px = 0;
  const auto bg = to255(m.s.frame.background);
  for (int j = 0; j < 128; ++j)
    for (int i = 0; i < 128; ++i) {
      differ += maxChannelDiff(px(*mirror, i, j), px(want, i, j)) > 1 ? 1 : 0;
      tooth_px += isBackground(want, i, j, bg) ? 0 : 1;
    }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(tooth_px, 128 * 128 / 40) << "the reflected view sees the tooth";

  // In the main frame, the glass shows the tooth: compare with the same frame without the tooth,
  // around the mirror's centre (the tooth itself is not there).
  FrameState no_tooth = m.s.frame;
  no_tooth.tooth_shown = false;
  const RgbImage empty_glass = render(no_tooth);
  const glm::vec3 c = m.s.camera.project(m.point, int(kW), int(kH));
  const float glass_px = 10.85f / m.s.camera.mmPerPixel(m.s.camera.depthOf(m.point), int(kH));
  int shows_tooth = 0, inside = 0;
  for (int j = 0; j < int(kH); ++j)
    for (int i = 0; i < int(kW); ++i) {
      const glm::vec2 d = glm::vec2(float(i) + 0.5f, float(j) + 0.5f) - glm::vec2(c);
      // The disc tilted by 45 degrees appears as an ellipse squeezed along the screen's y.
      if (d.x * d.x + 2.0f * d.y * d.y > 0.36f * glass_px * glass_px) continue;
      ++inside;
      shows_tooth += px(main, i, j) != px(empty_glass, i, j) ? 1 : 0;
    }
  EXPECT_GT(inside, 20);
  EXPECT_GT(shows_tooth, inside / 4) << "the mirror's face shows the tooth's lingual side";
}

// The mirror pass draws the glass's rectangle on the target and nothing else, pixel for pixel: its
// image there equals the reflected view drawn directly with the same crop of the frame's projection.
TEST_F(RenderTest, MirrorPassDrawsTheGlassRectanglePixelForPixel) {
  renderer();  // the default: the mirror at the size it is shown at
  MirrorScene m = mirrorScene();
  ASSERT_NO_FATAL_FAILURE(buildTooth(m.s.tooth.voxels));
  render(m.s.frame);
  ASSERT_TRUE(renderer().mirrorDrawn());
  const PixelRect rect = renderer().mirrorRect();
  ASSERT_FALSE(rect.empty());
  EXPECT_GE(rect.x, 0);
  EXPECT_GE(rect.y, 0);
  EXPECT_LE(rect.x + rect.width, int(kW));
  EXPECT_LE(rect.y + rect.height, int(kH));
  EXPECT_LT(rect.width * rect.height, int(kW * kH)) << "the glass covers part of the view, and the pass only that";
  auto mirror = readImage(ctx(), renderer().mirrorImage(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  ASSERT_TRUE(mirror.ok()) << mirror.message();

  FrameState direct = m.s.frame;
  const glm::mat4 reflect = reflectionMatrix(m.point, m.normal);
  direct.view = m.s.frame.view * reflect;
  direct.eye = glm::vec3(reflect * glm::vec4(m.s.frame.eye, 1.0f));
  direct.clip_plane = planeEquation(m.point, m.normal);
  direct.projection = cropProjection(m.s.frame.projection, rect, VkExtent2D{kW, kH});
  direct.mirror_shown = false;
  const RgbImage want = render(direct, uint32_t(rect.width), uint32_t(rect.height));
  int differ = 0, tooth_px = 0;
  const auto bg = to255(m.s.frame.background);
  for (int j = 0; j < rect.height; ++j)
    for (int i = 0; i < rect.width; ++i) {
      differ += maxChannelDiff(px(*mirror, i, j), px(want, i, j)) > 1 ? 1 : 0;
      tooth_px += isBackground(want, i, j, bg) ? 0 : 1;
    }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(tooth_px, rect.width * rect.height / 40) << "the reflected view sees the tooth";

  // A target twice as large (a larger window, a device pixel ratio of 2): the image grows to it, and
  // the glass's rectangle doubles with the pixels it covers.
  render(m.s.frame, 2 * kW, 2 * kH);
  ASSERT_TRUE(renderer().mirrorDrawn());
  const PixelRect twice = renderer().mirrorRect();
  EXPECT_NEAR(twice.width, 2 * rect.width, 3);
  EXPECT_NEAR(twice.height, 2 * rect.height, 3);
  EXPECT_GE(renderer().mirrorImage().extent.width, uint32_t(twice.x + twice.width));
  EXPECT_GE(renderer().mirrorImage().extent.height, uint32_t(twice.y + twice.height));
}

// Issue 44: the mirror's picture was stair-stepped at every silhouette while the main view beside it
// was smooth. The old pass drew a fixed 512 x 512 image of the whole view and stretched it over a
// 1280 x 800 frame, so each texel covered 2.5 x 1.6 pixels and every edge in the glass moved in steps
// that wide. Measured against the reflection drawn directly at the frame's own resolution (what a
// flat mirror shows, as sharp as the main view), on the glass where nothing stands in front of it:
// drawn at its shown size the glass equals it; the fixed image differs along every edge.
TEST_F(RenderTest, MirrorIsAsSharpAsTheMainView) {
  constexpr uint32_t w = 1280, h = 800;
  MirrorScene m = mirrorScene();
  ASSERT_NO_FATAL_FAILURE(buildTooth(m.s.tooth.voxels));
  m.s.frame.projection = m.s.camera.projection(float(w) / float(h));
  // A white reflectance, so that the glass shows the mirror image's texels unchanged.
  SceneRendererOptions options;
  options.mirror_tint = {1.0f, 1.0f, 1.0f};
  const auto glass = [&](uint32_t mirror_resolution) {
    renderer_.reset();
    options.mirror_resolution = mirror_resolution;
    renderer(options);
    RgbImage img = render(m.s.frame, w, h);
    EXPECT_TRUE(renderer().mirrorDrawn());
    return img;
  };
  const RgbImage sharp = glass(0);
  const RgbImage old = glass(512);

  // The reference: the reflected scene, clipped at the glass, drawn directly into the whole frame.
  FrameState direct = m.s.frame;
  const glm::mat4 reflect = reflectionMatrix(m.point, m.normal);
  direct.view = m.s.frame.view * reflect;
  direct.eye = glm::vec3(reflect * glm::vec4(m.s.frame.eye, 1.0f));
  direct.clip_plane = planeEquation(m.point, m.normal);
  direct.mirror_shown = false;
  const RgbImage want = render(direct, w, h);
  // The frame without the mirror: where it shows the tooth, the tooth may stand before the glass.
  FrameState plain = m.s.frame;
  plain.mirror_shown = false;
  const RgbImage bare = render(plain, w, h);

  // The glass's inner part (the disc tilted 45 degrees is an ellipse squeezed along y; the inner 0.6
  // of its radius keeps off the rim), where the frame without the mirror shows background.
  const glm::vec3 c = m.s.camera.project(m.point, int(w), int(h));
  const float glass_px = 10.85f / m.s.camera.mmPerPixel(m.s.camera.depthOf(m.point), int(h));
  const auto bg = to255(m.s.frame.background);
  int inside = 0, edges = 0, sharp_differ = 0, old_differ = 0, sharp_edge_differ = 0, old_edge_differ = 0;
  for (int j = 1; j + 1 < int(h); ++j)
    for (int i = 1; i + 1 < int(w); ++i) {
      const glm::vec2 d = glm::vec2(float(i) + 0.5f, float(j) + 0.5f) - glm::vec2(c);
      if (d.x * d.x + 2.0f * d.y * d.y > 0.36f * glass_px * glass_px || !isBackground(bare, i, j, bg)) continue;
      ++inside;
      // An edge of the reflection: a neighbour more than 24 grey levels away (silhouettes, creases).
      int contrast = 0;
      for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}})
        contrast = std::max(contrast, maxChannelDiff(px(want, i, j), px(want, i + di, j + dj)));
      const bool edge = contrast > 24;
      edges += edge ? 1 : 0;
      const bool s_off = maxChannelDiff(px(sharp, i, j), px(want, i, j)) > 2;
      const bool o_off = maxChannelDiff(px(old, i, j), px(want, i, j)) > 2;
      sharp_differ += s_off ? 1 : 0;
      old_differ += o_off ? 1 : 0;
      sharp_edge_differ += edge && s_off ? 1 : 0;
      old_edge_differ += edge && o_off ? 1 : 0;
    }
  std::printf("glass: %d pixels, %d on edges; off the direct reflection: shown size %d (%d on edges), fixed 512 %d (%d on edges)\n",
              inside, edges, sharp_differ, sharp_edge_differ, old_differ, old_edge_differ);
  ASSERT_GT(inside, 5000) << "the glass shows on the frame";
  ASSERT_GT(edges, 200) << "the reflection has silhouettes to measure";
  // Drawn at its shown size, the glass is the direct reflection (a crop's last bit of rounding may
  // move a pixel on an edge).
  EXPECT_LE(sharp_edge_differ, edges / 100);
  EXPECT_LE(sharp_differ, inside / 500);
  // The old fixed image misses most edges: this is the stair-stepping the issue saw.
  EXPECT_GT(old_edge_differ, edges / 3);
}

TEST_F(RenderTest, MirrorSeenFromBehindRunsNoPass) {
  MirrorScene m = mirrorScene();
  m.s.frame.mirror.rotation = Quat::fromAxisAngle({1.0, 0.0, 0.0}, 3.14159265358979 * 0.75);  // face away from the eye
  const RgbImage img = render(m.s.frame);
  EXPECT_EQ(img.width, int(kW));
  EXPECT_FALSE(renderer().mirrorDrawn());
}

// ---- the overlay -------------------------------------------------------------------------------------

TEST_F(RenderTest, OverlayImageFillsItsRectangle) {
  RgbImage overlay;
  overlay.width = 2;
  overlay.height = 1;
  overlay.rgb = {230, 20, 10, 10, 20, 230};  // red, blue
  ASSERT_TRUE(renderer().setOverlayImage(overlay).ok());
  FrameState f;
  f.tooth_shown = false;
  f.drill_shown = false;
  f.overlay_shown = true;
  f.overlay_rect = {20, 30, 40, 20};
  const RgbImage img = render(f);
  // Well inside each half, the linear sampler clamps to the texel's own colour.
  EXPECT_EQ(px(img, 25, 40), (std::array<int, 3>{230, 20, 10}));
  EXPECT_EQ(px(img, 54, 40), (std::array<int, 3>{10, 20, 230}));
  EXPECT_EQ(px(img, 10, 10), to255(f.background));
  EXPECT_EQ(px(img, 61, 40), to255(f.background));
}

// ---- the shared layout -------------------------------------------------------------------------------

TEST(RenderLayout, OffsetsArePinned) {
  EXPECT_EQ(offsetof(layout::FrameUniforms, mirrorViewProj), 64u);
  EXPECT_EQ(offsetof(layout::FrameUniforms, eye), 128u);
  EXPECT_EQ(offsetof(layout::FrameUniforms, lightDir), 144u);
  EXPECT_EQ(offsetof(layout::FrameUniforms, clipPlane), 160u);
  EXPECT_EQ(offsetof(layout::FrameUniforms, mirrorTint), 176u);
  EXPECT_EQ(offsetof(layout::FrameUniforms, mirrorRect), 192u);
  EXPECT_EQ(offsetof(layout::DrawConstants, ambient), 64u);
  EXPECT_EQ(offsetof(layout::DrawConstants, diffuse), 80u);
  EXPECT_EQ(offsetof(layout::DrawConstants, specular), 96u);
  EXPECT_EQ(offsetof(layout::DrawConstants, rect), 112u);
}

}  // namespace
}  // namespace dentsim::render::test
