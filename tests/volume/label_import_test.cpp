// Tests of src/volume/label_import.cpp: label maps, direct and resampled import, small-piece clean-up, enclosed-space filling, export, against hand counts.
#include "volume/label_import.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <map>

namespace dentsim {
namespace {

LabelImage blankImage(std::array<int32_t, 3> dims, double pitch) {
  LabelImage im;
  im.dims = dims;
  im.pitch_mm = {pitch, pitch, pitch};
  im.scanner_from_voxel = {pitch, 0, 0, 0, 0, pitch, 0, 0, 0, 0, pitch, 0};
  im.labels.assign(size_t(im.voxelCount()), 0);
  return im;
}

void fillBox(LabelImage& im, std::array<int, 3> lo, std::array<int, 3> hi, Label v) {
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) im.labels[im.index(i, j, k)] = v;
}

LabelMap ctMap() { return parseLabelMap("1=caries,2=enamel,3=dentin").value(); }

// Caries 1 -> 4, enamel 2 -> 1, dentin 3 -> 2: the CT codes as Material codes.
Label renumbered(Label l) {
  switch (l) {
    case 1: return DS_MAT_CARIES;
    case 2: return DS_MAT_ENAMEL;
    case 3: return DS_MAT_DENTIN;
    default: return 0;
  }
}

class CountingInterrupter : public Interrupter {
 public:
  explicit CountingInterrupter(int allow) : allow_(allow) {}
  bool progress(double fraction) override {
    last = fraction;
    return ++calls <= allow_;
  }
  int calls = 0;
  double last = -1;

 private:
  int allow_;
};

// ---- label maps -------------------------------------------------------------------------------

TEST(LabelMapTest, ParsesTissues) {
  Result<LabelMap> m = parseLabelMap(" 1=caries, 2 = enamel,3=dentin,7=pulp,-2=empty");
  ASSERT_TRUE(m.ok()) << m.message();
  EXPECT_EQ(m->size(), 5u);
  EXPECT_EQ(m->at(1), Material::Caries);
  EXPECT_EQ(m->at(2), Material::Enamel);
  EXPECT_EQ(m->at(3), Material::Dentin);
  EXPECT_EQ(m->at(7), Material::Pulp);
  EXPECT_EQ(m->at(-2), Material::Empty);
}

TEST(LabelMapTest, RejectsBadMaps) {
  const std::pair<const char*, const char*> cases[] = {
      {"1=bone", "unknown tissue 'bone'"},
      {"1=caries,1=enamel", "mapped twice"},
      {"0=enamel", "label 0"},
      {"1:caries", "expected LABEL=TISSUE"},
      {"x=caries", "not an integer"},
      {"1.5=caries", "not an integer"},
      {"40000=caries", "outside"},
      {"", "no LABEL=TISSUE"},
      {"1=caries,,2=enamel", "expected LABEL=TISSUE"},
      {"1=caries,", "trailing comma"},
  };
  for (const auto& [text, problem] : cases) {
    Result<LabelMap> m = parseLabelMap(text);
    ASSERT_FALSE(m.ok()) << text;
    EXPECT_NE(m.message().find(problem), std::string::npos) << text << " -> " << m.message();
    EXPECT_EQ(m.message().find('\n'), std::string::npos);
  }
}

// ---- direct import ----------------------------------------------------------------------------

TEST(LabelImportTest, DirectImportKeepsEveryLabelAndExportsItBack) {
  // 13 x 10 x 9: no side is a power of two, and the bricks at the far faces are partial.
  LabelImage im = blankImage({13, 10, 9}, 0.034);
  im.scanner_from_voxel = {-1, 0, 0, 5, 0, -1, 0, -6, 0, 0, 1, 7};  // header pitch 1, flipped x and y
  fillBox(im, {0, 0, 0}, {12, 9, 1}, 3);   // 13*10*2 = 260 dentin
  fillBox(im, {2, 3, 2}, {6, 5, 4}, 2);    // 5*3*3 = 45 enamel
  fillBox(im, {12, 9, 8}, {12, 9, 8}, 1);  // 1 caries, in the far corner
  fillBox(im, {8, 0, 5}, {11, 0, 5}, 1);   // 4 more caries
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.source_pitch_mm = 0.034;
  opt.where = "small.nii";
  Result<ToothVolume> tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();

  const VolumeFrame& f = tooth->frame;
  EXPECT_EQ(f.level, 4);  // 13 voxels need 16 per side
  EXPECT_DOUBLE_EQ(f.voxel_mm, 0.034);
  EXPECT_EQ(f.source_dims, im.dims);
  EXPECT_EQ(f.source_offset, (std::array<int32_t, 3>{0, 0, 0}));
  // Pitch replaced, direction cosines and offset kept.
  const std::array<double, 12> expected = {-0.034, 0, 0, 5, 0, -0.034, 0, -6, 0, 0, 0.034, 7};
  for (size_t i = 0; i < 12; ++i) EXPECT_NEAR(f.scanner_from_grid[i], expected[i], 1e-12) << i;

  const MaterialTotals t = tooth->voxels.materialTotals();
  EXPECT_EQ(t.voxels[DS_MAT_DENTIN], 260u);
  EXPECT_EQ(t.voxels[DS_MAT_ENAMEL], 45u);
  EXPECT_EQ(t.voxels[DS_MAT_CARIES], 5u);
  EXPECT_EQ(t.voxels[DS_MAT_PULP], 0u);
  EXPECT_EQ(t.fill_sum[DS_MAT_DENTIN], 260u * DS_FILL_FULL);
  EXPECT_NEAR(t.volumeMm3(Material::Enamel, f.voxel_mm), 45 * 0.034 * 0.034 * 0.034, 1e-15);
  EXPECT_EQ(tooth->voxels.voxel(12, 9, 8), makeVoxel(Material::Caries));
  EXPECT_EQ(tooth->voxels.voxel(13, 9, 8), 0);  // just outside the source

  const LabelImage back = exportLabels(*tooth);
  EXPECT_EQ(back.dims, im.dims);
  ASSERT_EQ(back.labels.size(), im.labels.size());
  for (size_t i = 0; i < im.labels.size(); ++i) ASSERT_EQ(back.labels[i], renumbered(im.labels[i])) << i;
  for (size_t i = 0; i < 12; ++i) EXPECT_NEAR(back.scanner_from_voxel[i], expected[i], 1e-12) << i;
  EXPECT_DOUBLE_EQ(back.pitch_mm[0], 0.034);
}

TEST(LabelImportTest, HeaderPitchIsUsedWithoutOverride) {
  LabelImage im = blankImage({8, 8, 8}, 0.25);
  im.scanner_from_voxel = {0, 0.25, 0, 1, 0.25, 0, 0, 2, 0, 0, -0.25, 3};  // axes swapped and flipped
  fillBox(im, {1, 1, 1}, {2, 2, 2}, 2);
  LabelImportOptions opt;
  opt.map = ctMap();
  Result<ToothVolume> tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(tooth->frame.level, 3);
  EXPECT_DOUBLE_EQ(tooth->frame.voxel_mm, 0.25);
  EXPECT_EQ(tooth->frame.scanner_from_grid, im.scanner_from_voxel);
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_ENAMEL], 8u);
}

TEST(LabelImportTest, UnknownLabelNamesValueAndCount) {
  LabelImage im = blankImage({4, 4, 4}, 1.0);
  fillBox(im, {0, 0, 0}, {1, 0, 0}, 7);  // two voxels of label 7
  fillBox(im, {0, 1, 0}, {3, 3, 3}, 3);
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.where = "scan.nii.gz";
  Result<ToothVolume> tooth = importLabels(im, opt);
  ASSERT_FALSE(tooth.ok());
  EXPECT_EQ(tooth.message(), "scan.nii.gz: label 7 (2 voxels) is not in the label map");
}

TEST(LabelImportTest, AnisotropicPitchNeedsATarget) {
  LabelImage im = blankImage({4, 4, 4}, 1.0);
  im.pitch_mm = {1.0, 1.0, 2.0};
  fillBox(im, {1, 1, 1}, {2, 2, 2}, 3);
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.where = "aniso.nii";
  Result<ToothVolume> r = importLabels(im, opt);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("anisotropic"), std::string::npos) << r.message();
  opt.source_pitch_mm = 0.5;  // an override makes the source isotropic
  EXPECT_TRUE(importLabels(im, opt).ok());
}

TEST(LabelImportTest, CancelIsAnError) {
  LabelImage im = blankImage({16, 16, 16}, 1.0);
  fillBox(im, {2, 2, 2}, {12, 12, 12}, 3);
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.where = "c.nii";
  CountingInterrupter stop_at_first(0);
  Result<ToothVolume> r = importLabels(im, opt, stop_at_first);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), "c.nii: import cancelled");
  CountingInterrupter never(1 << 30);
  ASSERT_TRUE(importLabels(im, opt, never).ok());
  EXPECT_GT(never.calls, 2);
  EXPECT_DOUBLE_EQ(never.last, 1.0);
}

// ---- small pieces -----------------------------------------------------------------------------

// Voxels whose exported label (a Material code) differs from the input's, as index -> new code.
std::map<size_t, Label> changedVoxels(const LabelImage& in, const ToothVolume& tooth) {
  const LabelImage out = exportLabels(tooth);
  EXPECT_EQ(out.dims, in.dims);
  std::map<size_t, Label> changed;
  for (size_t i = 0; i < in.labels.size() && i < out.labels.size(); ++i)
    if (out.labels[i] != renumbered(in.labels[i])) changed[i] = out.labels[i];
  return changed;
}

// A 12 x 10 x 8 image: dentin at x = 0..5, enamel at x = 6..8, empty at x = 9..11, and in it one
// example of each case the clean-up must handle. Every small piece is a single voxel unless noted.
class LabelCleanupTest : public ::testing::Test {
 protected:
  void SetUp() override {
    im_ = blankImage({12, 10, 8}, 0.1);
    fillBox(im_, {0, 0, 0}, {5, 9, 7}, 3);
    fillBox(im_, {6, 0, 0}, {8, 9, 7}, 2);
    // A caries speck inside dentin: 6 dentin faces.
    fillBox(im_, {2, 4, 4}, {2, 4, 4}, 1);
    // An empty hole inside dentin: empty is a tissue too, so the hole is a piece.
    fillBox(im_, {2, 2, 2}, {2, 2, 2}, 0);
    // A 3-voxel caries line at x = 3..5 touching enamel at its end: 14 faces, 13 dentin and 1 enamel.
    fillBox(im_, {3, 8, 5}, {5, 8, 5}, 1);
    // A 20-voxel caries block (5 x 2 x 2) against the enamel (4 faces) and the top border (10 faces
    // that do not vote); the other 34 faces are dentin.
    fillBox(im_, {1, 5, 6}, {5, 6, 7}, 1);
    // A tie between dentin and enamel: a caries speck in the enamel at x = 6 with two dentin bumps
    // beside it (part of the dentin through x = 5), so 3 dentin and 3 enamel faces. The inner wins.
    fillBox(im_, {6, 4, 4}, {6, 4, 4}, 3);
    fillBox(im_, {6, 6, 4}, {6, 6, 4}, 3);
    fillBox(im_, {6, 5, 4}, {6, 5, 4}, 1);
    // A tie between enamel and empty: a dentin speck in the empty space at x = 9 with two enamel
    // bumps beside it, so 3 enamel and 3 empty faces. A tissue beats empty.
    fillBox(im_, {9, 4, 4}, {9, 4, 4}, 2);
    fillBox(im_, {9, 6, 4}, {9, 6, 4}, 2);
    fillBox(im_, {9, 5, 4}, {9, 5, 4}, 3);
    // At the image border: a caries speck in a corner (3 dentin faces, the other 3 are the border),
    // an enamel speck in another corner, and a 2-voxel empty pocket on an edge (6 dentin faces). What
    // lies beyond the border is unknown, so it does not vote, not even for empty.
    fillBox(im_, {0, 0, 0}, {0, 0, 0}, 1);
    fillBox(im_, {0, 9, 7}, {0, 9, 7}, 2);
    fillBox(im_, {0, 0, 4}, {0, 0, 5}, 0);
    opt_.map = ctMap();
    opt_.where = "pieces.nii";
  }

  // What min_piece_voxels 4 (or anything from 4 to 20) changes: every piece above but the block.
  std::map<size_t, Label> expectedUnder20() const {
    std::map<size_t, Label> e;
    for (auto [x, y, z] : {std::array<int, 3>{2, 4, 4}, {2, 2, 2}, {3, 8, 5}, {4, 8, 5}, {5, 8, 5}, {6, 5, 4},
                           {0, 0, 0}, {0, 9, 7}, {0, 0, 4}, {0, 0, 5}})
      e[im_.index(x, y, z)] = DS_MAT_DENTIN;
    e[im_.index(9, 5, 4)] = DS_MAT_ENAMEL;
    return e;
  }

  LabelImage im_;
  LabelImportOptions opt_;
};

TEST_F(LabelCleanupTest, OffByDefaultAndWithZero) {
  EXPECT_EQ(opt_.min_piece_voxels, 0);
  LabelImportReport report;
  report.cleanup.pieces[DS_MAT_CARIES] = 99;  // reset by the import
  Result<ToothVolume> tooth = importLabels(im_, opt_, nullInterrupter(), &report);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_TRUE(changedVoxels(im_, *tooth).empty());
  for (uint32_t m = 0; m < DS_MATERIAL_COUNT; ++m) {
    EXPECT_EQ(report.cleanup.pieces[m], 0u) << m;
    EXPECT_EQ(report.cleanup.voxels_into[m], 0u) << m;
  }
  // No piece is smaller than one voxel, so 1 changes nothing either.
  opt_.min_piece_voxels = 1;
  tooth = importLabels(im_, opt_, nullInterrupter(), &report);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_TRUE(changedVoxels(im_, *tooth).empty());
}

TEST_F(LabelCleanupTest, PiecesUnderFourTakeTheMajorityOfTheirFaces) {
  opt_.min_piece_voxels = 4;
  LabelImportReport report;
  Result<ToothVolume> tooth = importLabels(im_, opt_, nullInterrupter(), &report);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(changedVoxels(im_, *tooth), expectedUnder20());

  const PieceCleanup& c = report.cleanup;
  // Caries: the speck, the line, the dentin/enamel tie and the corner speck (1 + 3 + 1 + 1 voxels).
  EXPECT_EQ(c.pieces[DS_MAT_CARIES], 4u);
  EXPECT_EQ(c.voxels[DS_MAT_CARIES], 6u);
  EXPECT_EQ(c.pieces[DS_MAT_ENAMEL], 1u);  // the corner speck
  EXPECT_EQ(c.voxels[DS_MAT_ENAMEL], 1u);
  EXPECT_EQ(c.pieces[DS_MAT_DENTIN], 1u);  // the speck in the empty space
  EXPECT_EQ(c.voxels[DS_MAT_DENTIN], 1u);
  EXPECT_EQ(c.pieces[DS_MAT_EMPTY], 2u);   // the hole and the edge pocket
  EXPECT_EQ(c.voxels[DS_MAT_EMPTY], 3u);
  EXPECT_EQ(c.voxels_into[DS_MAT_DENTIN], 10u);
  EXPECT_EQ(c.voxels_into[DS_MAT_ENAMEL], 1u);
  EXPECT_EQ(c.voxels_into[DS_MAT_CARIES], 0u);
  EXPECT_EQ(c.voxels_into[DS_MAT_EMPTY], 0u);
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_CARIES], 20u);  // the block stays

  // The clean-up works on the source grid, so resampling sees the cleaned labels and the report is
  // the same.
  LabelImportReport resampled;
  opt_.level = 5;
  ASSERT_TRUE(importLabels(im_, opt_, nullInterrupter(), &resampled).ok());
  EXPECT_EQ(resampled.cleanup.pieces, c.pieces);
  EXPECT_EQ(resampled.cleanup.voxels_into, c.voxels_into);
}

TEST_F(LabelCleanupTest, TheLimitIsExclusive) {
  // A piece of exactly min_piece_voxels stays; one more and it goes.
  opt_.min_piece_voxels = 20;
  Result<ToothVolume> tooth = importLabels(im_, opt_);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(changedVoxels(im_, *tooth), expectedUnder20());

  opt_.min_piece_voxels = 21;
  LabelImportReport report;
  tooth = importLabels(im_, opt_, nullInterrupter(), &report);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  std::map<size_t, Label> expected = expectedUnder20();
  for (int z = 6; z <= 7; ++z)
    for (int y = 5; y <= 6; ++y)
      for (int x = 1; x <= 5; ++x) expected[im_.index(x, y, z)] = DS_MAT_DENTIN;  // 34 dentin faces to 4
  EXPECT_EQ(changedVoxels(im_, *tooth), expected);
  EXPECT_EQ(report.cleanup.pieces[DS_MAT_CARIES], 5u);
  EXPECT_EQ(report.cleanup.voxels[DS_MAT_CARIES], 26u);
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_CARIES], 0u);
}

TEST_F(LabelCleanupTest, HolesAreCleanedBeforeTheEnclosedFill) {
  // Without the clean-up the hole is enclosed, so it becomes a pulp speck. (The edge pocket is not:
  // the fill floods from the border, while the clean-up lets only voxels in the image vote.)
  opt_.fill_enclosed = Material::Pulp;
  Result<ToothVolume> tooth = importLabels(im_, opt_);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_PULP], 1u);
  EXPECT_EQ(tooth->voxels.voxel(2, 2, 2), makeVoxel(Material::Pulp));
  // With it the hole is dentin before the fill runs, and nothing is left to fill.
  opt_.min_piece_voxels = 4;
  tooth = importLabels(im_, opt_);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_PULP], 0u);
  EXPECT_EQ(tooth->voxels.voxel(2, 2, 2), makeVoxel(Material::Dentin));
}

TEST_F(LabelCleanupTest, NegativeLimitIsAnErrorAndCancelIsHeard) {
  opt_.min_piece_voxels = -1;
  Result<ToothVolume> r = importLabels(im_, opt_);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), "pieces.nii: minimum piece size must be 0 or more voxels, not -1");
  // The label codes report twice; the third report is the clean-up's.
  opt_.min_piece_voxels = 4;
  CountingInterrupter stop_in_cleanup(2);
  r = importLabels(im_, opt_, stop_in_cleanup);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), "pieces.nii: import cancelled");
  EXPECT_EQ(stop_in_cleanup.calls, 3);
}

TEST(LabelCleanupOrderTest, ASpeckInsideASmallShellFollowsTheShell) {
  // An enamel voxel at the centre of a 3^3 caries shell (26 voxels) inside a 7^3 dentin cube. With a
  // limit of 27 the shell comes first in scan order (its first voxel, (2,2,2), precedes the centre)
  // and turns to dentin; the centre then sees 6 dentin faces. Decided on the input labels instead,
  // it would have become caries, a new speck inside the dentin.
  LabelImage im = blankImage({7, 7, 7}, 0.1);
  fillBox(im, {0, 0, 0}, {6, 6, 6}, 3);
  fillBox(im, {2, 2, 2}, {4, 4, 4}, 1);
  fillBox(im, {3, 3, 3}, {3, 3, 3}, 2);
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.min_piece_voxels = 27;
  LabelImportReport report;
  Result<ToothVolume> tooth = importLabels(im, opt, nullInterrupter(), &report);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_DENTIN], 343u);
  EXPECT_EQ(report.cleanup.voxels[DS_MAT_CARIES], 26u);
  EXPECT_EQ(report.cleanup.voxels[DS_MAT_ENAMEL], 1u);
  EXPECT_EQ(report.cleanup.voxels_into[DS_MAT_DENTIN], 27u);
}

TEST(LabelCleanupOrderTest, AnImageThatIsOnePieceIsKept) {
  // No face of the piece has a voxel outside it, and the border does not vote: nothing to go by.
  LabelImage im = blankImage({2, 2, 2}, 0.1);
  fillBox(im, {0, 0, 0}, {1, 1, 1}, 1);
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.min_piece_voxels = 100;
  LabelImportReport report;
  Result<ToothVolume> tooth = importLabels(im, opt, nullInterrupter(), &report);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_CARIES], 8u);
  EXPECT_EQ(report.cleanup.pieces[DS_MAT_CARIES], 0u);
}

// ---- enclosed space ---------------------------------------------------------------------------

TEST(LabelImportTest, FillEnclosedFillsExactlyTheCavity) {
  // A 7^3 dentin cube at 1..7 of a 9^3 grid, hollowed by a 3^3 cavity at 3..5: 343 - 27 = 316 dentin.
  LabelImage im = blankImage({9, 9, 9}, 0.1);
  fillBox(im, {1, 1, 1}, {7, 7, 7}, 3);
  fillBox(im, {3, 3, 3}, {5, 5, 5}, 0);
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.fill_enclosed = Material::Pulp;
  Result<ToothVolume> tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  MaterialTotals t = tooth->voxels.materialTotals();
  EXPECT_EQ(t.voxels[DS_MAT_PULP], 27u);
  EXPECT_EQ(t.voxels[DS_MAT_DENTIN], 316u);
  EXPECT_EQ(tooth->voxels.voxel(0, 0, 0), 0);  // the outside stays empty

  // A tunnel from the cavity to the border (x = 0..2 at y = z = 4) opens it: nothing is filled.
  fillBox(im, {0, 4, 4}, {2, 4, 4}, 0);
  tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  t = tooth->voxels.materialTotals();
  EXPECT_EQ(t.voxels[DS_MAT_PULP], 0u);
  EXPECT_EQ(t.voxels[DS_MAT_DENTIN], 316u - 2u);  // the tunnel cut x = 1, 2 of the wall

  // A diagonal-only contact is not 6-connected: a cavity touching the wall at an edge stays enclosed.
  LabelImage edge = blankImage({6, 6, 6}, 0.1);
  fillBox(edge, {0, 0, 0}, {5, 5, 5}, 3);
  fillBox(edge, {2, 2, 2}, {3, 3, 3}, 0);     // 8-voxel cavity
  fillBox(edge, {0, 0, 0}, {1, 1, 5}, 0);     // an outside notch meeting the cavity only along an edge
  tooth = importLabels(edge, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_PULP], 8u);
}

// ---- resampling -------------------------------------------------------------------------------

TEST(LabelImportTest, SealClosesNarrowCanalsButNotWideOnesOrEnamelGrooves) {
  // A 13^3 dentin cube at 3..15 of a 19^3 grid (pitch 0.1 mm) with a 5^3 cavity at 7..11 and a
  // one-voxel canal from the cavity to the outside (x = 3..6 at y = z = 9): an open root canal.
  // On top, an enamel slab (z = 16..17) with a one-voxel groove at x = 9 through its depth.
  LabelImage im = blankImage({19, 19, 19}, 0.1);
  fillBox(im, {3, 3, 3}, {15, 15, 15}, 3);
  fillBox(im, {7, 7, 7}, {11, 11, 11}, 0);
  fillBox(im, {3, 9, 9}, {6, 9, 9}, 0);
  fillBox(im, {3, 3, 16}, {15, 15, 17}, 2);
  fillBox(im, {9, 3, 16}, {9, 15, 17}, 0);
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.fill_enclosed = Material::Pulp;

  // No seal: the canal lets the flood in, so nothing is enclosed.
  Result<ToothVolume> tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_PULP], 0u);

  // Seal radius 1 voxel: the dilated dentin closes the canal; the flood stops outside, and its
  // dilation back reaches x <= 2 only, so the cavity (125) and the canal's 4 voxels become pulp.
  // The enamel groove is not dentin, so it is never sealed and stays empty.
  opt.seal_mm = 0.1;
  tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  const MaterialTotals t = tooth->voxels.materialTotals();
  EXPECT_EQ(t.voxels[DS_MAT_PULP], 125u + 4u);
  EXPECT_EQ(t.voxels[DS_MAT_DENTIN], 13u * 13u * 13u - 125u - 4u);
  EXPECT_EQ(tooth->voxels.voxel(9, 9, 16), 0);  // the groove
  EXPECT_EQ(tooth->voxels.voxel(1, 9, 9), 0);   // the outside in front of the canal
  EXPECT_EQ(tooth->voxels.voxel(4, 9, 9), makeVoxel(Material::Pulp));

  // A canal three voxels wide keeps an open centre line at radius 1: the flood enters and, dilated
  // back, covers the whole cavity, so nothing is filled.
  fillBox(im, {3, 8, 8}, {6, 10, 10}, 0);
  tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_PULP], 0u);
}

TEST(LabelImportTest, LevelFitKeepsAnAlignedBlockExactly) {
  // A 24 x 16 x 12 dentin block at pitch 0.1 mm: 4.608 mm^3. Level 4 gives a voxel of
  // 2.4 mm / (16 - 4) = 0.2 mm, two source voxels, and the centred grid lines up with the block,
  // so the volume comes out exact: 12 x 8 x 6 full voxels.
  LabelImage im = blankImage({40, 30, 20}, 0.1);
  fillBox(im, {5, 7, 3}, {28, 22, 14}, 3);
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.level = 4;
  Result<ToothVolume> tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  EXPECT_EQ(tooth->frame.level, 4);
  EXPECT_NEAR(tooth->frame.voxel_mm, 0.2, 1e-12);
  EXPECT_FALSE(tooth->frame.hasSource());
  const MaterialTotals t = tooth->voxels.materialTotals();
  EXPECT_EQ(t.voxels[DS_MAT_DENTIN], 12u * 8u * 6u);
  EXPECT_NEAR(t.volumeMm3(Material::Dentin, tooth->frame.voxel_mm), 4.608, 1e-9);
  // The grid voxel at the block's low corner maps back onto the block's low corner in the scanner:
  // its centre is the centre of source voxels 5..6, i.e. x = 5.5 * 0.1 mm.
  const auto& g = tooth->frame.scanner_from_grid;
  EXPECT_NEAR(g[0], 0.2, 1e-12);
  const double first_x = 2.0;  // 2 margin voxels along the longest axis
  EXPECT_NEAR(g[0] * first_x + g[3], 0.55, 1e-9);
}

TEST(LabelImportTest, LevelFitKeepsVolumeOfAnUnalignedBlock) {
  // A 23 x 17 x 11 enamel block at pitch 0.05 mm: 0.215050 mm^3. At level 5 the voxel is
  // 1.15 / 28 mm, not a divisor of the block: the error is bounded by half a voxel over the surface.
  LabelImage im = blankImage({30, 30, 30}, 0.05);
  fillBox(im, {3, 5, 9}, {25, 21, 19}, 2);
  const double volume = 23 * 17 * 11 * 0.05 * 0.05 * 0.05;
  const double area = 2 * (23 * 17 + 17 * 11 + 23 * 11) * 0.05 * 0.05;
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.level = 5;
  Result<ToothVolume> tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  const double v = tooth->frame.voxel_mm;
  EXPECT_NEAR(v, 23 * 0.05 / 28, 1e-12);
  const double got = tooth->voxels.materialTotals().volumeMm3(Material::Enamel, v);
  EXPECT_NEAR(got, volume, 0.5 * area * v);
  EXPECT_NEAR(got, volume, 0.05 * volume);  // and, for this block, within 5 %
}

TEST(LabelImportTest, MajorityAndTieRules) {
  // Target voxels of 2 source voxels; the tissue spans source 2..5 on each axis, so target voxel 3
  // covers source 2..3 and target voxel 4 covers source 4..5 (grid 8, low corner at -4.5).
  LabelImage im = blankImage({8, 8, 8}, 1.0);
  // Target (3,3,3): 4 enamel + 4 dentin -> the tie goes to dentin, the inner tissue.
  fillBox(im, {2, 2, 2}, {3, 3, 2}, 2);
  fillBox(im, {2, 2, 3}, {3, 3, 3}, 3);
  // Target (4,3,3): 5 enamel + 3 dentin -> enamel, the majority.
  fillBox(im, {4, 2, 2}, {5, 3, 2}, 2);
  fillBox(im, {4, 2, 3}, {4, 2, 3}, 2);
  fillBox(im, {5, 2, 3}, {5, 3, 3}, 3);
  fillBox(im, {4, 3, 3}, {4, 3, 3}, 3);
  // Target (3,4,3): 4 caries + 4 empty -> caries, half full: round(31 * 4 / 8) = 16.
  fillBox(im, {2, 4, 2}, {3, 5, 2}, 1);
  // Target (3,3,4): 2 pulp, 2 caries, 2 dentin, 2 enamel -> pulp wins the four-way tie.
  fillBox(im, {2, 2, 4}, {3, 2, 4}, 4);
  fillBox(im, {2, 3, 4}, {3, 3, 4}, 1);
  fillBox(im, {2, 2, 5}, {3, 2, 5}, 3);
  fillBox(im, {2, 3, 5}, {3, 3, 5}, 2);
  // Something at source x,y,z = 5 so that the bounding box is 2..5 on every axis.
  fillBox(im, {5, 5, 5}, {5, 5, 5}, 3);
  LabelImportOptions opt;
  opt.map = parseLabelMap("1=caries,2=enamel,3=dentin,4=pulp").value();
  opt.voxel_mm = 2.0;
  Result<ToothVolume> tooth = importLabels(im, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  ASSERT_EQ(tooth->frame.level, 3);
  const BrickVolume& v = tooth->voxels;
  EXPECT_EQ(v.voxel(3, 3, 3), makeVoxel(Material::Dentin, 31));
  EXPECT_EQ(v.voxel(4, 3, 3), makeVoxel(Material::Enamel, 31));
  EXPECT_EQ(v.voxel(3, 4, 3), makeVoxel(Material::Caries, 16));
  EXPECT_EQ(v.voxel(3, 3, 4), makeVoxel(Material::Pulp, 31));
  EXPECT_EQ(v.voxel(4, 4, 4), makeVoxel(Material::Dentin, 4));  // 1 of 8 samples: round(3.875)
  EXPECT_EQ(v.voxel(2, 2, 2), 0);                                // all samples empty
}

TEST(LabelImportTest, LevelWithNoTissueIsAnError) {
  LabelImage im = blankImage({8, 8, 8}, 1.0);
  LabelImportOptions opt;
  opt.map = ctMap();
  opt.level = 5;
  opt.where = "blank.nii";
  Result<ToothVolume> r = importLabels(im, opt);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no tissue"), std::string::npos) << r.message();
}

// A tooth-like label image: an enamel ball around a dentin ball around an empty pulp, off centre,
// with a caries bite in the enamel and one-voxel specks, so every kind of brick occurs (empty,
// solid of each tissue, tissue borders, the image's own border).
LabelImage layeredBall(int32_t n, double pitch) {
  LabelImage im = blankImage({n, n + 3, n - 5}, pitch);
  const double c[3] = {0.52 * n, 0.47 * (n + 3), 0.5 * (n - 5)};
  for (int k = 0; k < im.dims[2]; ++k)
    for (int j = 0; j < im.dims[1]; ++j)
      for (int i = 0; i < im.dims[0]; ++i) {
        const double d = std::sqrt((i - c[0]) * (i - c[0]) + (j - c[1]) * (j - c[1]) + 1.3 * (k - c[2]) * (k - c[2]));
        // The innermost ball stays empty: the pulp's hole (the map has no pulp label).
        Label l = 0;
        if (d < 0.45 * n) l = d < 0.18 * n ? Label(0) : d < 0.33 * n ? Label(3) : Label(2);
        if (l == 2 && i > 0.7 * n && j > 0.6 * n) l = 1;
        if ((i * 7 + j * 13 + k * 29) % 211 == 0) l = Label((i + j + k) % 3 + 1);
        im.labels[im.index(i, j, k)] = l;
      }
  return im;
}

TEST(LabelImportTest, ResamplingShortcutsGiveExactlyTheVoxelByVoxelResult) {
  // The chunk and brick tiles are only a shortcut: at every level, up- and down-sampling, the
  // volume equals the one sampled voxel by voxel.
  const LabelImage im = layeredBall(40, 0.05);
  struct Case {
    std::optional<int> level;
    std::optional<double> voxel_mm;
  };
  for (const Case& c : {Case{4, {}}, Case{6, {}}, Case{7, {}}, Case{8, {}}, Case{{}, 0.13}, Case{{}, 0.031}}) {
    LabelImportOptions opt;
    opt.map = ctMap();
    opt.level = c.level;
    opt.voxel_mm = c.voxel_mm;
    LabelImportReport fast_report, slow_report;
    Result<ToothVolume> fast = importLabels(im, opt, nullInterrupter(), &fast_report);
    opt.uniform_shortcuts = false;
    Result<ToothVolume> slow = importLabels(im, opt, nullInterrupter(), &slow_report);
    ASSERT_TRUE(fast.ok() && slow.ok()) << fast.message() << slow.message();
    const std::string name = c.level ? "level " + std::to_string(*c.level) : "voxel " + std::to_string(*c.voxel_mm);
    EXPECT_EQ(fast->frame.level, slow->frame.level) << name;
    EXPECT_TRUE(fast->voxels == slow->voxels) << name;
    fast->voxels.compact();
    slow->voxels.compact();
    EXPECT_TRUE(std::ranges::equal(fast->voxels.chunkWords(), slow->voxels.chunkWords())) << name;
    EXPECT_TRUE(std::ranges::equal(fast->voxels.brickWords(), slow->voxels.brickWords())) << name;
    EXPECT_LE(fast_report.sampled_voxels, slow_report.sampled_voxels) << name;
  }
}

TEST(LabelImportTest, ResamplingCostFollowsTheSurfaceNotTheGrid) {
  // A 48^3 image at levels 9 and 10. Sampling every voxel would grow 8 times a level (the grid);
  // with the tiles only the bricks that tissue borders cross are sampled, which grow 4 times a
  // level (the surface), and the count stays a small multiple of the dense bricks kept. Counted,
  // not timed.
  const LabelImage im = layeredBall(48, 0.1);
  std::array<uint64_t, 2> sampled{};
  for (int level : {9, 10}) {
    SCOPED_TRACE("level " + std::to_string(level));
    LabelImportOptions opt;
    opt.map = ctMap();
    opt.level = level;
    LabelImportReport report;
    Result<ToothVolume> tooth = importLabels(im, opt, nullInterrupter(), &report);
    ASSERT_TRUE(tooth.ok()) << tooth.message();
    tooth->voxels.compact();
    const uint64_t dense = tooth->voxels.brickWords().size() / DS_BRICK_WORDS;
    ASSERT_GT(dense, 0u);
    EXPECT_LE(report.sampled_voxels, 4 * dense * DS_BRICK_VOXELS) << dense << " dense bricks";
    EXPECT_LT(report.sampled_voxels, (uint64_t{1} << (3 * level)) / 10);
    sampled[size_t(level - 9)] = report.sampled_voxels;
    // The solid stays what the source says: the dentin shell's volume within 2 % of the source's.
    const double source_dentin = double(std::count(im.labels.begin(), im.labels.end(), Label(3))) * 1e-3;
    const double got = tooth->voxels.materialTotals().volumeMm3(Material::Dentin, tooth->frame.voxel_mm);
    EXPECT_NEAR(got, source_dentin, 0.02 * source_dentin);
  }
  const double growth = double(sampled[1]) / double(sampled[0]);
  EXPECT_GT(growth, 3.0);
  EXPECT_LT(growth, 5.0);
}

// ---- export -----------------------------------------------------------------------------------

TEST(LabelExportTest, HalfFillRuleAndWholeGrid) {
  ToothVolume tooth;
  tooth.voxels = BrickVolume(3);
  tooth.frame = VolumeFrame::axisAligned(3, 0.5, {1.0, 2.0, 3.0});
  tooth.voxels.setVoxel(1, 0, 0, makeVoxel(Material::Dentin, 16));  // half or more: kept
  tooth.voxels.setVoxel(2, 0, 0, makeVoxel(Material::Dentin, 15));  // less than half: empty
  tooth.voxels.setVoxel(0, 7, 7, makeVoxel(Material::Pulp, 31));
  const LabelImage im = exportLabels(tooth);
  ASSERT_EQ(im.dims, (std::array<int32_t, 3>{8, 8, 8}));
  EXPECT_EQ(im.labels[im.index(1, 0, 0)], DS_MAT_DENTIN);
  EXPECT_EQ(im.labels[im.index(2, 0, 0)], 0);
  EXPECT_EQ(im.labels[im.index(0, 7, 7)], DS_MAT_PULP);
  EXPECT_EQ(std::count(im.labels.begin(), im.labels.end(), 0), 512 - 2);
  EXPECT_DOUBLE_EQ(im.scanner_from_voxel[3], 1.25);  // centre of voxel 0 [mm]
}

TEST(LabelExportTest, SourceBoxWithOffsetShiftsTheMatrix) {
  ToothVolume tooth;
  tooth.voxels = BrickVolume(4);
  tooth.frame = VolumeFrame::axisAligned(4, 0.1, {0, 0, 0});
  tooth.frame.source_offset = {2, 3, 4};
  tooth.frame.source_dims = {5, 6, 7};
  tooth.voxels.setVoxel(2, 3, 4, makeVoxel(Material::Enamel));   // source (0,0,0)
  tooth.voxels.setVoxel(6, 8, 10, makeVoxel(Material::Caries));  // source (4,5,6)
  tooth.voxels.setVoxel(7, 3, 4, makeVoxel(Material::Dentin));   // outside the box
  const LabelImage im = exportLabels(tooth);
  ASSERT_EQ(im.dims, (std::array<int32_t, 3>{5, 6, 7}));
  EXPECT_EQ(im.labels[im.index(0, 0, 0)], DS_MAT_ENAMEL);
  EXPECT_EQ(im.labels[im.index(4, 5, 6)], DS_MAT_CARIES);
  EXPECT_EQ(std::count(im.labels.begin(), im.labels.end(), 0), 5 * 6 * 7 - 2);
  EXPECT_NEAR(im.scanner_from_voxel[3], 0.25, 1e-12);  // (2 + 0.5) * 0.1
  EXPECT_NEAR(im.scanner_from_voxel[7], 0.35, 1e-12);
  EXPECT_NEAR(im.scanner_from_voxel[11], 0.45, 1e-12);
  const LabelImage whole = exportLabels(tooth, ExportRegion::WholeGrid);
  EXPECT_EQ(whole.dims, (std::array<int32_t, 3>{16, 16, 16}));
  EXPECT_EQ(std::count(whole.labels.begin(), whole.labels.end(), 0), 4096 - 3);
}

}  // namespace
}  // namespace dentsim

namespace dentsim {
namespace {

// Two images of one scanner space whose tissue boxes differ (a stray voxel in one) land on one grid
// when both fit the same box: same voxel size, same scanner matrix, and the shared tissue agrees.
TEST(LabelImportTest, AGivenFitBoxPutsTwoImportsOnOneGrid) {
  LabelImage a = blankImage({20, 20, 20}, 0.1);
  fillBox(a, {4, 4, 4}, {11, 13, 9}, 3);  // inclusive: the fit box below is this tissue's own box
  LabelImage b = a;
  b.labels[b.index(17, 17, 17)] = 3;  // widens b's own box
  LabelImportOptions o;
  o.map = ctMap();
  o.level = 5;
  o.fit_box = {{{4, 11}, {4, 13}, {4, 9}}};
  Result<ToothVolume> ta = importLabels(a, o), tb = importLabels(b, o);
  ASSERT_TRUE(ta && tb);
  EXPECT_EQ(ta->frame.voxel_mm, tb->frame.voxel_mm);
  EXPECT_EQ(ta->frame.scanner_from_grid, tb->frame.scanner_from_grid);
  // The box is 1.0 mm at its longest, over 2^5 - 4 voxels.
  EXPECT_DOUBLE_EQ(ta->frame.voxel_mm, 1.0 / 28.0);
  o.fit_box.reset();
  Result<ToothVolume> own = importLabels(b, o);
  ASSERT_TRUE(own);
  EXPECT_GT(own->frame.voxel_mm, tb->frame.voxel_mm);  // b's own box is wider
  o.fit_box = {{{4, 3}, {4, 13}, {4, 9}}};
  EXPECT_FALSE(importLabels(a, o));  // an empty box
}

}  // namespace
}  // namespace dentsim
