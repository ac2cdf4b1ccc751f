// Tests of the score picture: over-cut shows red, under-cut blue, untouched tooth neither; healthy tissue cut outside a caries zone red, inside it not; PNG bytes and files.
#include "eval/score_image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "eval/tooth_diff.h"
#include "eval_fixtures.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::enamelSlab;
using test::setBox;

constexpr Voxel kEmpty = 0;

bool redDominant(std::array<uint8_t, 3> c) { return c[0] > 2 * c[1] && c[0] > 2 * c[2]; }
bool blueDominant(std::array<uint8_t, 3> c) { return c[2] > 2 * c[0] && c[2] > c[1] + 40; }

// The enamel slab (top at z = 8) seen from above, with three strips along y:
//   x 1..4:   the student cut z 5..7 and the ideal keeps it       -> over-cut, red
//   x 6..9:   the ideal cuts z 6..7 and the student left it       -> under-cut, blue
//   x 11..14: both leave it                                       -> ivory
struct Scene {
  ToothVolume initial = enamelSlab();
  ToothVolume ideal, student;
  Scene() {
    ideal = initial;
    setBox(ideal, {6, 3, 6}, {10, 13, 8}, kEmpty);
    student = initial;
    setBox(student, {1, 3, 5}, {5, 13, 8}, kEmpty);
  }
};

// The picture of a cavity: the over-cut of the diff against the ideal is red.
ScoreImage cavityPicture(const Scene& scene, const ScoreImageOptions& options) {
  auto diff = compareTeeth(scene.initial, scene.student, &scene.ideal, ZoneOptions{});
  EXPECT_TRUE(diff.ok()) << diff.message();
  return renderScoreImage(scene.initial, scene.student, &scene.ideal, &diff->beyond_target, options);
}

std::array<uint8_t, 3> pixelAbove(const ScoreImage& s, double x, double y, double z = 8.0) {
  const std::array<double, 2> p = s.views.at(0).pixelOf({x, y, z});
  return s.image.pixel(int(std::floor(p[0])), int(std::floor(p[1])));
}

TEST(ScoreImage, OvercutRedUndercutBlueUntouchedNeither) {
  const Scene scene;
  const ScoreImage s = cavityPicture(scene, {200, 150});
  ASSERT_EQ(s.views.size(), 1u);
  ASSERT_EQ(s.image.rgb.size(), 200u * 150u * 3u);
  const auto over = pixelAbove(s, 3.0, 8.0), under = pixelAbove(s, 8.0, 8.0), clean = pixelAbove(s, 13.0, 8.0);
  EXPECT_TRUE(redDominant(over)) << int(over[0]) << " " << int(over[1]) << " " << int(over[2]);
  EXPECT_TRUE(blueDominant(under)) << int(under[0]) << " " << int(under[1]) << " " << int(under[2]);
  EXPECT_FALSE(redDominant(clean)) << int(clean[0]) << " " << int(clean[1]) << " " << int(clean[2]);
  EXPECT_FALSE(blueDominant(clean)) << int(clean[0]) << " " << int(clean[1]) << " " << int(clean[2]);
  // The untouched strip is lit tooth, not background: bright in every channel.
  EXPECT_GT(int(clean[0]) + clean[1] + clean[2], 300);
}

TEST(ScoreImage, WithoutIdealThereIsNoTintAndCariesIsBrown) {
  Scene scene;
  setBox(scene.initial, {11, 3, 7}, {15, 13, 8}, makeVoxel(Material::Caries));
  setBox(scene.student, {11, 3, 7}, {15, 13, 8}, makeVoxel(Material::Caries));
  const ScoreImage s = renderScoreImage(scene.initial, scene.student, nullptr, nullptr, {200, 150});
  const auto cut = pixelAbove(s, 3.0, 8.0), caries = pixelAbove(s, 13.0, 8.0);
  EXPECT_FALSE(redDominant(cut));
  EXPECT_FALSE(blueDominant(cut));
  EXPECT_GT(caries[0], caries[1]);
  EXPECT_GT(caries[1], caries[2]);
  EXPECT_LT(caries[0], 160);  // darker than enamel: brown, not ivory
}

// A caries task without an ideal: the caries (x 6..9, y 3..12, z 6..7) and the enamel above it
// are the target. The student cut the caries and, apart from it, a strip x 1..4 that lies beyond the
// 0.2 mm leeway: that strip is red, the cut caries is not.
TEST(ScoreImage, HealthyTissueCutOutsideTheCariesZoneIsRed) {
  ToothVolume initial = enamelSlab();
  setBox(initial, {6, 3, 6}, {10, 13, 8}, makeVoxel(Material::Caries));
  ToothVolume student = initial;
  setBox(student, {6, 3, 6}, {10, 13, 8}, kEmpty);
  setBox(student, {1, 3, 5}, {3, 13, 8}, kEmpty);
  auto diff = compareTeeth(initial, student, nullptr, ZoneOptions{});
  ASSERT_TRUE(diff.ok()) << diff.message();
  const ScoreImage s = renderScoreImage(initial, student, nullptr, &diff->healthy_outside_zone, {200, 150});
  const auto outside = pixelAbove(s, 2.0, 8.0), caries = pixelAbove(s, 8.0, 8.0);
  EXPECT_TRUE(redDominant(outside)) << int(outside[0]) << " " << int(outside[1]) << " " << int(outside[2]);
  EXPECT_FALSE(redDominant(caries)) << int(caries[0]) << " " << int(caries[1]) << " " << int(caries[2]);
}

TEST(ScoreImage, ObliqueViewSitsBesideTheFirst) {
  const Scene scene;
  const ScoreImage s = cavityPicture(scene, {201, 100, {0, 0, -1}, true});
  ASSERT_EQ(s.views.size(), 2u);
  EXPECT_EQ(s.views[0].x0, 0);
  EXPECT_EQ(s.views[0].width, 100);
  EXPECT_EQ(s.views[1].x0, 100);
  EXPECT_EQ(s.views[1].width, 101);
  // The slab's centre is in the middle of the oblique view too.
  const auto p = s.views[1].pixelOf({8, 8, 4});
  EXPECT_NEAR(p[0], 150.5, 1.0);
  EXPECT_NEAR(p[1], 50.0, 1.0);
}

TEST(ScoreImage, EmptyVolumesGiveBackground) {
  const ToothVolume empty = test::emptyTooth();
  const ScoreImage s = renderScoreImage(empty, empty, nullptr, nullptr, {32, 32});
  EXPECT_EQ(s.image.pixel(0, 0), s.image.pixel(16, 16));
}

TEST(ScoreImage, PngBytesAndFile) {
  const Scene scene;
  const ScoreImage s = cavityPicture(scene, {64, 48});
  auto png = encodePng(s.image);
  ASSERT_TRUE(png.ok()) << png.message();
  ASSERT_GT(png->size(), 8u);
  const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  EXPECT_TRUE(std::equal(kSignature, kSignature + 8, png->begin()));

  test::TempDir dir;
  ASSERT_TRUE(writePng(dir.file("score.png"), s.image).ok());
  std::ifstream in(dir.file("score.png"), std::ios::binary);
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_EQ(bytes, *png);

  auto bad = writePng(dir.file("nope/score.png"), s.image);
  EXPECT_FALSE(bad.ok());
}

}  // namespace
}  // namespace dentsim
