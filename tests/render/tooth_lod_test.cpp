// Screen-sized detail: the choice of copy by hand-worked cases, the coarse copies against fresh builds, the build in parts, and frames against full-detail frames.
#include "render/tooth_lod.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "gpu/gpu_fixture.h"
#include "render/camera.h"
#include "render/frame_compare.h"
#include "render/look_params.h"
#include "render/offscreen.h"
#include "render/scene_renderer.h"
#include "render/tooth_surfaces.h"
#include "sim/builtin_tooth.h"
#include "volume/brick_pyramid.h"

namespace dentsim::render::test {
namespace {

// ---- the choice, on the CPU -------------------------------------------------------------------------

// A level-8 grid (256 voxels, 8 regions a side) of 0.04 mm voxels with its corner at the origin,
// seen from straight above its centre along -z through a 40 degree lens at 1280 x 720.
struct ChoiceScene {
  VolumeFrame frame = VolumeFrame::axisAligned(8, 0.04, {0.0, 0.0, 0.0});
  LodView view;
  explicit ChoiceScene(float height_mm) {
    const glm::vec3 centre(5.12f, 5.12f, 5.12f);
    view.view = glm::lookAt(centre + glm::vec3(0.0f, 0.0f, height_mm), centre, glm::vec3(0.0f, 1.0f, 0.0f));
    view.projection = glm::perspective(glm::radians(40.0f), 1280.0f / 720.0f, 0.5f, 1000.0f);
    view.width = 1280;
    view.height = 720;
  }
  static size_t index(uint32_t x, uint32_t y, uint32_t z) { return (size_t(z) * 8 + y) * 8 + x; }
};

TEST(LodChoiceTest, FarAwayEverythingComesFromTheCoarsestCopy) {
  ChoiceScene s(500.0f);
  const LodChoice c = chooseLod(s.frame, 2, s.view, LodSettings{});
  ASSERT_EQ(c.region_dim, 8u);
  // 500 mm away a coarsest voxel (0.16 mm) is 0.16 * 989 / 495 = 0.32 px: half of it is far under 1 px.
  for (uint8_t k : c.copy) EXPECT_EQ(k, 2u);
}

TEST(LodChoiceTest, ZeroPixelsIsFullDetailAndTheBurKeepsItsNeighbourhoodFull) {
  ChoiceScene s(500.0f);
  LodSettings full;
  full.pixel_error = 0.0f;
  for (uint8_t k : chooseLod(s.frame, 2, s.view, full).copy) EXPECT_EQ(k, 0u);
  // A bur tip on the corner shared by regions (3..4, 3..4, 7): those 4 regions, and only they, are
  // within 1 mm (a region is 1.28 mm wide, so the next ones are 1.28 mm away or more).
  s.view.bur_tip = glm::vec3(5.12f, 5.12f, 10.0f);
  LodSettings near_bur;
  near_bur.bur_radius_mm = 1.0f;
  const LodChoice c = chooseLod(s.frame, 2, s.view, near_bur);
  int full_regions = 0;
  for (uint32_t z = 0; z < 8; ++z)
    for (uint32_t y = 0; y < 8; ++y)
      for (uint32_t x = 0; x < 8; ++x) {
        const bool by_bur = (x == 3 || x == 4) && (y == 3 || y == 4) && z == 7;
        EXPECT_EQ(c.at(x, y, z), by_bur ? 0u : 2u) << x << " " << y << " " << z;
        full_regions += c.at(x, y, z) == 0 ? 1 : 0;
      }
  EXPECT_EQ(full_regions, 4);
}

TEST(LodChoiceTest, TheCopyFollowsHalfAVoxelOnScreen) {
  // 30 mm above the grid's centre, i.e. 24.88 mm above its top face. The top centre regions'
  // nearest depth is 24.88 mm; focal = 0.5 * max(|P00| * 1280, |P11| * 720) = 989.1 px.
  // Half a voxel of copy k on screen: 0.02 * 2^k * 989.1 / 24.88 = 0.795 px * 2^k.
  ChoiceScene s(30.0f);
  const double focal = 0.5 * std::max(std::fabs(double(s.view.projection[0][0])) * 1280.0,
                                      std::fabs(double(s.view.projection[1][1])) * 720.0);
  const double half_voxel_px = 0.02 * focal / (30.0 - (10.24 - 5.12));
  LodSettings settings;
  settings.pixel_error = float(2.0 * half_voxel_px * 1.01);  // copy 1 fits, copy 2 does not
  EXPECT_EQ(chooseLod(s.frame, 2, s.view, settings).at(3, 3, 7), 1u);
  settings.pixel_error = float(4.0 * half_voxel_px * 1.01);  // both fit
  EXPECT_EQ(chooseLod(s.frame, 2, s.view, settings).at(3, 3, 7), 2u);
  settings.pixel_error = float(2.0 * half_voxel_px * 0.99);  // neither
  EXPECT_EQ(chooseLod(s.frame, 2, s.view, settings).at(3, 3, 7), 0u);
}

TEST(LodChoiceTest, MeasuredErrorsChooseTheCoarsestCopyThatFits) {
  // From 30 mm a full voxel is 0.04 * 989.1 / 24.88 = 1.59 px at the top centre regions.
  ChoiceScene s(30.0f);
  std::vector<std::vector<float>> error(3, std::vector<float>(512, 0.0f));
  const size_t top = ChoiceScene::index(3, 3, 7), next = ChoiceScene::index(4, 3, 7);
  error[1][top] = 0.3f;   // under the floor of half a full voxel (0.8 px): fits
  error[2][top] = 0.9f;   // 1.43 px: does not
  error[1][next] = 0.9f;  // neither fits
  error[2][next] = 2.0f;
  const LodChoice c = chooseLod(s.frame, 2, s.view, LodSettings{}, LodRegions{{}, {}, error});
  EXPECT_EQ(c.at(3, 3, 7), 1u);
  EXPECT_EQ(c.at(4, 3, 7), 0u);
  // No error measured: the floor, a quarter of the copy's voxel: 1.59 px for copy 2, 0.8 px for copy 1.
  EXPECT_EQ(c.at(2, 3, 7), 1u);
}

TEST(LodChoiceTest, RegionsOutsideTheViewAreNotDrawn) {
  // 2 mm above the top face: the view's half width at the top layer is under 2 mm, so the corner
  // regions of the top layer (3.8 mm from the axis) fall outside, and the centre regions stay.
  ChoiceScene s(2.0f + 5.12f);
  const LodChoice c = chooseLod(s.frame, 2, s.view, LodSettings{});
  EXPECT_EQ(c.at(0, 0, 7), kLodHidden);
  EXPECT_EQ(c.at(7, 7, 7), kLodHidden);
  EXPECT_NE(c.at(3, 3, 7), kLodHidden);
}

TEST(LodChoiceTest, LaggingAndUnmeshedRegionsFallBack) {
  ChoiceScene s(500.0f);
  std::vector<std::vector<uint8_t>> lagging(3, std::vector<uint8_t>(512, 0));
  lagging[2][ChoiceScene::index(1, 2, 3)] = 1;  // copy 2 lags: the next finer one
  lagging[2][ChoiceScene::index(2, 2, 3)] = 1;  // copies 2 and 1 lag: the full one
  lagging[1][ChoiceScene::index(2, 2, 3)] = 1;
  std::vector<std::vector<uint8_t>> ready(3, std::vector<uint8_t>(512, 1));
  ready[2][ChoiceScene::index(5, 5, 5)] = 0;  // the coarsest copy not there: the next finer one
  ready[2][ChoiceScene::index(6, 6, 6)] = 0;
  ready[1][ChoiceScene::index(6, 6, 6)] = 0;  // nor the next: the full one
  const LodChoice c = chooseLod(s.frame, 2, s.view, LodSettings{}, LodRegions{ready, lagging, {}});
  EXPECT_EQ(c.at(1, 2, 3), 1u);
  EXPECT_EQ(c.at(2, 2, 3), 0u);
  EXPECT_EQ(c.at(5, 5, 5), 1u);
  EXPECT_EQ(c.at(6, 6, 6), 0u);
  EXPECT_EQ(c.at(0, 0, 0), 2u);
}

TEST(LodChoiceTest, BlocksReachOneVoxelIntoNeighbouringRegions) {
  LodChoice c;
  c.region_dim = 8;
  c.copy.assign(512, 2);
  c.copy[ChoiceScene::index(3, 3, 3)] = 0;
  // Full block b spans voxels 8b - 0.5 .. 8b + 7.5, widened by 1: regions floor((8b - 1.5) / 32) to
  // floor((8b + 8.5) / 32) touch region 3 (voxels 96..128) for b = 11 .. 16: 6^3 blocks.
  // Copy-2 block b spans (8b - 0.5) * 4 - 1 .. (8b + 7.5) * 4 + 1 = 32b - 3 .. 32b + 31: regions b - 1
  // and b, never region 3 alone, so all 9^3 of them are drawn. No region is copy 1.
  std::array<int, 3> drawn{};
  for (uint32_t k = 0; k < 3; ++k) {
    const uint32_t blocks = (256u >> k) / 8u + 1u;
    for (uint32_t z = 0; z < blocks; ++z)
      for (uint32_t y = 0; y < blocks; ++y)
        for (uint32_t x = 0; x < blocks; ++x) drawn[k] += c.drawsBlock(k, MeshBlock{x, y, z}) ? 1 : 0;
  }
  EXPECT_EQ(drawn[0], 216);
  EXPECT_EQ(drawn[1], 0);
  EXPECT_EQ(drawn[2], 729);
}

TEST(LodChoiceTest, CoarseNormalBoxesKeepTheirWidthInMillimetres) {
  EXPECT_EQ(coarseNormalMode(NormalMode::Box216, 0), NormalMode::Box216);
  EXPECT_EQ(coarseNormalMode(NormalMode::Box216, 1), NormalMode::Box64);  // 3 voxels: 2 and 4 tie, the wider wins
  EXPECT_EQ(coarseNormalMode(NormalMode::Box216, 2), NormalMode::Box8);   // 1.5 voxels: 2 is nearest
  EXPECT_EQ(coarseNormalMode(NormalMode::Box64, 1), NormalMode::Box8);
  EXPECT_EQ(coarseNormalMode(NormalMode::Box8, 2), NormalMode::Box8);
}

// ---- copies and frames, on the device ---------------------------------------------------------------

class ToothLodTest : public gpu::test::GraphicsGpuTest {
 protected:
  void TearDown() override {
    if (ctx_) {
      renderer_.reset();
      EXPECT_TRUE(ctx_->waitIdle().ok());
    }
    GraphicsGpuTest::TearDown();
  }
  SceneRenderer& renderer() {
    if (!renderer_) {
      auto r = SceneRenderer::create(*ctx_, kDefaultColourFormat, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
      EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.message());
      renderer_.emplace(std::move(*r));
    }
    return *renderer_;
  }
  ToothSurfaces surfaces() {
    auto t = ToothSurfaces::create(*ctx_);
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.message());
    return std::move(*t);
  }
  // Every tissue's blocks of copy k.
  std::vector<std::vector<BlockMesh>> blocksOf(const ToothSurfaces& t, uint32_t k) {
    std::vector<std::vector<BlockMesh>> out;
    for (size_t i = 0; i < kDrawnTissues.size(); ++i) {
      auto b = t.surface(i, k).downloadBlocks();
      EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.message());
      out.push_back(b.ok() ? std::move(*b) : std::vector<BlockMesh>{});
    }
    return out;
  }
  static bool sameBlocks(const std::vector<std::vector<BlockMesh>>& a, const std::vector<std::vector<BlockMesh>>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
      if (a[i].size() != b[i].size()) return false;
      for (size_t j = 0; j < a[i].size(); ++j) {
        const BlockMesh &x = a[i][j], &y = b[i][j];
        if (!(x.block == y.block) || x.indices != y.indices || x.vertices.size() != y.vertices.size()) return false;
        for (size_t v = 0; v < x.vertices.size(); ++v)
          if (std::memcmp(&x.vertices[v], &y.vertices[v], sizeof x.vertices[v]) != 0) return false;
      }
    }
    return true;
  }
  std::optional<SceneRenderer> renderer_;
};

// A cut: the ball of radius r voxels at (x, y, z) emptied, and the bricks it touched.
std::vector<BrickCoord> carve(BrickVolume& v, int x, int y, int z, int r) {
  std::set<std::tuple<uint32_t, uint32_t, uint32_t>> touched;
  for (int dz = -r; dz <= r; ++dz)
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        if (dx * dx + dy * dy + dz * dz > r * r) continue;
        const uint32_t px = uint32_t(x + dx), py = uint32_t(y + dy), pz = uint32_t(z + dz);
        v.setVoxel(px, py, pz, makeVoxel(Material::Empty));
        touched.insert({px >> DS_BRICK_LOG2, py >> DS_BRICK_LOG2, pz >> DS_BRICK_LOG2});
      }
  std::vector<BrickCoord> out;
  for (auto [bx, by, bz] : touched) out.push_back({bx, by, bz});
  return out;
}

// The top of the crown at the grid's centre column.
int crownTop(const BrickVolume& v) {
  int top = 0;
  for (uint32_t z = 0; z < v.dim(); ++z)
    if (voxelMaterial(v.voxel(v.dim() / 2, v.dim() / 2, z)) != Material::Empty) top = int(z);
  return top;
}

TEST_F(ToothLodTest, CoarseCopiesLagACutUntilTheySettleThenEqualFreshBuilds) {
  auto tooth = builtinMolarTooth(8);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  BrickVolume& v = tooth->voxels;
  ToothSurfaces t = surfaces();
  ASSERT_TRUE(t.build(v).ok());
  ASSERT_EQ(t.copies(), 4u);  // level 8: copies of levels 7, 6 and 5
  const auto before = blocksOf(t, 1);
  const int c = int(v.dim() / 2);
  const std::vector<BrickCoord> dirty = carve(v, c, c, crownTop(v), 7);
  ASSERT_TRUE(t.update(v, dirty).ok());
  // Cut once: the coarse surfaces wait, and the regions around the cut are flagged.
  EXPECT_TRUE(t.coarseLagging());
  EXPECT_TRUE(sameBlocks(blocksOf(t, 1), before));
  const uint32_t rd = lodRegionDim(v.brickDim());
  const uint32_t r = uint32_t(c) / 32u, rz = uint32_t(crownTop(v)) / 32u;
  for (uint32_t k = 1; k < t.copies(); ++k) {
    EXPECT_EQ(t.laggingRegions()[k][(size_t(rz) * rd + r) * rd + r], 1u) << k;
    EXPECT_EQ(t.laggingRegions()[k][0], 0u) << k;
  }
  EXPECT_TRUE(t.laggingRegions()[0].empty());
  // Nothing cut in the next updates: one copy catches up per update, then all equal surfaces built
  // afresh from the copies.
  ASSERT_TRUE(t.update(v, {}).ok());
  EXPECT_TRUE(t.coarseLagging());
  EXPECT_EQ(t.laggingRegions()[1][(size_t(rz) * rd + r) * rd + r], 0u);
  EXPECT_EQ(t.laggingRegions()[2][(size_t(rz) * rd + r) * rd + r], 1u);
  ASSERT_TRUE(t.update(v, {}).ok());
  ASSERT_TRUE(t.update(v, {}).ok());
  EXPECT_FALSE(t.coarseLagging());
  for (uint32_t k = 1; k < t.copies(); ++k)
    for (uint8_t flag : t.laggingRegions()[k]) ASSERT_EQ(flag, 0u);
  ToothSurfaces fresh = surfaces();
  ASSERT_TRUE(fresh.build(v).ok());
  for (uint32_t k = 0; k < t.copies(); ++k) EXPECT_TRUE(sameBlocks(blocksOf(t, k), blocksOf(fresh, k))) << "copy " << k;
  EXPECT_FALSE(sameBlocks(blocksOf(t, 1), before));
}

TEST_F(ToothLodTest, ABuildInPartsFillsInNearestFirstAndEndsAsAWholeBuild) {
  auto tooth = builtinMolarTooth(8);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  const BrickVolume& v = tooth->voxels;
  ToothSurfaces parts = surfaces();
  ASSERT_TRUE(parts.beginBuild(v, tooth->frame).ok());
  EXPECT_FALSE(parts.done());
  EXPECT_EQ(parts.progress(), 0.0);
  ASSERT_EQ(parts.readyRegions().size(), 4u);
  // A corner of the grid as the focus: the first region meshed is the one nearest it that holds
  // surface, and the far corner's regions stay unready after a few steps.
  const glm::vec3 corner(float(tooth->frame.origin_mm[0]), float(tooth->frame.origin_mm[1]),
                         float(tooth->frame.origin_mm[2]));
  double last = 0.0;
  for (int step = 0; step < 3; ++step) {
    ASSERT_TRUE(parts.continueBuild(v, corner, 0.0).ok());  // no budget: one region a call
    EXPECT_GT(parts.progress(), last);
    last = parts.progress();
  }
  EXPECT_FALSE(parts.done());
  int steps = 3;
  while (!parts.done() && steps < 10000) {
    ASSERT_TRUE(parts.continueBuild(v, corner, 50.0).ok());
    ++steps;
  }
  ASSERT_TRUE(parts.done());
  EXPECT_EQ(parts.progress(), 1.0);
  EXPECT_TRUE(parts.readyRegions().empty());
  ToothSurfaces whole = surfaces();
  ASSERT_TRUE(whole.build(v).ok());
  for (uint32_t k = 0; k < parts.copies(); ++k) EXPECT_TRUE(sameBlocks(blocksOf(parts, k), blocksOf(whole, k))) << "copy " << k;
}

TEST_F(ToothLodTest, FramesStayWithinTwoGreyLevelsOfFullDetailWithNoCrack) {
  auto tooth = builtinMolarTooth(8);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  ToothSurfaces t = surfaces();
  ASSERT_TRUE(t.build(tooth->voxels).ok());
  for (uint32_t k = 1; k < t.copies(); ++k) {
    std::vector<float> e(t.copyErrors()[k].begin(), t.copyErrors()[k].end());
    std::sort(e.begin(), e.end());
    std::printf("[ info ] copy %u error: median %.2f, p90 %.2f, max %.2f voxels\n", k, e[e.size() / 2], e[e.size() * 9 / 10], e.back());
  }
  const VolumeFrame& f = tooth->frame;
  const float side = float(f.voxel_mm * double(f.dim()));
  const glm::vec3 centre = glm::vec3(float(f.origin_mm[0]), float(f.origin_mm[1]), float(f.origin_mm[2])) + glm::vec3(side / 2.0f);
  constexpr uint32_t kW = 400, kH = 300;
  struct View {
    ViewPreset preset;
    float zoom;  // the preset's distance divided by this
  };
  for (const View view : {View{ViewPreset::Occlusal, 1.0f}, View{ViewPreset::Buccal, 1.0f}, View{ViewPreset::Mesial, 1.0f},
                          View{ViewPreset::Lingual, 2.5f}, View{ViewPreset::Buccal, 0.3f}}) {
    OrbitCamera camera;
    camera.setView(view.preset, centre, side / 2.0f);
    camera.setDistance(camera.distance() / view.zoom);
    FrameState fs;
    fs.view = camera.view();
    fs.projection = camera.projection(float(kW) / float(kH));
    fs.eye = camera.eye();
    fs.light_dir = glm::normalize(camera.eye() - centre);
    fs.tooth_frame = f;
    fs.looks = defaultLookParams().looks;
    fs.drill_shown = false;
    fs.lod.pixel_error = 0.0f;
    auto full = renderOffscreen(*ctx_, renderer(), t, fs, kW, kH);
    ASSERT_TRUE(full.ok()) << full.message();
    const uint64_t full_triangles = renderer().toothDrawStats().main_triangles;
    fs.lod.pixel_error = 1.0f;
    auto lod = renderOffscreen(*ctx_, renderer(), t, fs, kW, kH);
    ASSERT_TRUE(lod.ok()) << lod.message();
    const ToothDrawStats drew = renderer().toothDrawStats();
    const std::array<uint8_t, 3> bg{uint8_t(std::lround(fs.background[0] * 255.0f)),
                                    uint8_t(std::lround(fs.background[1] * 255.0f)),
                                    uint8_t(std::lround(fs.background[2] * 255.0f))};
    const FrameDifference d = compareFrames(*full, *lod, bg);
    std::printf("[ info ] %s x%.1f: %llu of %llu triangles, copies %u/%u/%u/%u regions; %llu px covered, mean "
                "difference %.2f, %llu px over 8, %llu crack px\n",
                std::string(viewPresetName(view.preset)).c_str(), double(view.zoom),
                (unsigned long long)drew.main_triangles, (unsigned long long)full_triangles, drew.main_regions[0],
                drew.main_regions[1], drew.main_regions[2], drew.main_regions[3], (unsigned long long)d.covered, d.mean_abs,
                (unsigned long long)d.differing, (unsigned long long)d.cracks);
    EXPECT_GT(d.covered, uint64_t(kW * kH / 100));
    EXPECT_LT(d.mean_abs, 2.0);
    EXPECT_EQ(d.cracks, 0u);
    EXPECT_LE(drew.main_triangles, full_triangles);
    // Seen from 3x farther the tooth is small: the coarse copies carry it.
    if (view.zoom < 1.0f) {
      EXPECT_LT(double(drew.main_triangles), 0.3 * double(full_triangles));
    }
  }
}

TEST_F(ToothLodTest, TheMirrorPassChoosesAsTheReflectedCameraWould) {
  auto tooth = builtinMolarTooth(7);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  ToothSurfaces t = surfaces();
  ASSERT_TRUE(t.build(tooth->voxels).ok());
  const VolumeFrame& f = tooth->frame;
  const float side = float(f.voxel_mm * double(f.dim()));
  const glm::vec3 centre = glm::vec3(float(f.origin_mm[0]), float(f.origin_mm[1]), float(f.origin_mm[2])) + glm::vec3(side / 2.0f);
  OrbitCamera camera;
  camera.setView(ViewPreset::Occlusal, centre, side / 2.0f);
  FrameState fs;
  fs.view = camera.view();
  fs.projection = camera.projection(4.0f / 3.0f);
  fs.eye = camera.eye();
  fs.tooth_frame = f;
  fs.looks = defaultLookParams().looks;
  fs.drill_shown = false;
  const glm::vec3 point = centre + glm::vec3(0.0f, side * 0.6f, side * 0.15f);
  fs.mirror_shown = true;
  fs.mirror.position = fromGlm(point);
  fs.mirror.rotation = Quat::fromAxisAngle({1.0, 0.0, 0.0}, 3.14159265358979 / 4.0);
  ASSERT_TRUE(renderOffscreen(*ctx_, renderer(), t, fs, 320, 240).ok());
  ASSERT_TRUE(renderer().mirrorDrawn());
  const uint64_t mirror = renderer().toothDrawStats().mirror_triangles;
  FrameState direct = fs;
  const glm::vec3 normal = glm::normalize(toGlm(fs.mirror.applyDirection(Vec3{0.0, 0.0, 1.0})));
  direct.view = fs.view * reflectionMatrix(point, normal);
  direct.mirror_shown = false;
  // The mirror pass draws the glass's rectangle of the frame, pixel for pixel.
  const PixelRect rect = renderer().mirrorRect();
  ASSERT_FALSE(rect.empty());
  direct.projection = cropProjection(fs.projection, rect, VkExtent2D{320, 240});
  ASSERT_TRUE(renderOffscreen(*ctx_, renderer(), t, direct, uint32_t(rect.width), uint32_t(rect.height)).ok());
  EXPECT_GT(mirror, 0u);
  EXPECT_EQ(renderer().toothDrawStats().main_triangles, mirror);
}

}  // namespace
}  // namespace dentsim::render::test
