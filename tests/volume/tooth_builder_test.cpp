// Tests of src/volume/tooth_builder.cpp: tiny labels, grey values and a box mesh into a tooth volume standing in its frame, counted by hand.
#include "volume/tooth_builder.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/ply_file.h"
#include "io/stl_file.h"
#include "test_meshes.h"
#include "test_support.h"

namespace dentsim {
namespace {

// A 4 x 4 x 4 label image of 1 mm voxels: dentin (2) in the 2 x 2 x 2 block i, j = 1..2 at
// k = `dentin_k`..+1, enamel (1) in the 2 x 2 layer i, j = 1..2 at k = `enamel_k`.
LabelImage smallTooth(int dentin_k, int enamel_k) {
  LabelImage im;
  im.dims = {4, 4, 4};
  im.pitch_mm = {1.0, 1.0, 1.0};
  im.scanner_from_voxel = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  im.labels.assign(64, 0);
  for (int j = 1; j <= 2; ++j)
    for (int i = 1; i <= 2; ++i) {
      im.labels[im.index(i, j, dentin_k)] = 2;
      im.labels[im.index(i, j, dentin_k + 1)] = 2;
      im.labels[im.index(i, j, enamel_k)] = 1;
    }
  return im;
}

LabelImportOptions enamelDentinMap() {
  LabelImportOptions import;
  import.map = parseLabelMap("1=enamel,2=dentin").value();
  import.where = "small.nii";
  return import;
}

ToothAxesHint crownAlong(double z) {
  ToothAxesHint hint;
  hint.crown = Vec3{0, 0, z};
  return hint;
}

TEST(ToothBuilder, ALabelVolumeBecomesAToothWithItsVoxelsCounted) {
  // No level or voxel size: source voxel (i,j,k) is grid voxel (i,j,k), each full. The grid is the
  // smallest 2^L >= 4 with L >= 3: 8. Dentin 2 x 2 x 2 = 8 voxels, enamel 2 x 2 = 4 on top.
  Result<ToothVolume> tooth = buildToothFromLabels(smallTooth(0, 2), enamelDentinMap(), crownAlong(1), {});
  ASSERT_TRUE(tooth) << tooth.message();
  EXPECT_EQ(tooth->frame.level, 3);
  const MaterialTotals totals = tooth->voxels.materialTotals();
  EXPECT_EQ(totals.voxels[DS_MAT_DENTIN], 8u);
  EXPECT_EQ(totals.voxels[DS_MAT_ENAMEL], 4u);
  EXPECT_EQ(totals.voxels[DS_MAT_PULP], 0u);
  EXPECT_EQ(tooth->frame.tooth.crown_source, AxisSource::Given);
  EXPECT_FALSE(tooth->frame.tooth.turned());  // the crown already points along +z
}

TEST(ToothBuilder, ACrownThatPointsDownIsStoodUpWithItsVoxels) {
  // Enamel at k = 0 under dentin at k = 1..2, crown given as -z: a half turn brings the enamel on
  // top. A quarter turn moves whole voxels, so the counts stay 8 and 4.
  Result<ToothVolume> tooth = buildToothFromLabels(smallTooth(1, 0), enamelDentinMap(), crownAlong(-1), {});
  ASSERT_TRUE(tooth) << tooth.message();
  EXPECT_TRUE(tooth->frame.tooth.turned());
  EXPECT_NEAR(tooth->frame.tooth.crown[2], 1.0, 1e-9);
  const MaterialTotals totals = tooth->voxels.materialTotals();
  EXPECT_EQ(totals.voxels[DS_MAT_DENTIN], 8u);
  EXPECT_EQ(totals.voxels[DS_MAT_ENAMEL], 4u);
  const auto boxes = tissueVoxelBoxes(tooth->voxels);
  EXPECT_GT(boxes[DS_MAT_ENAMEL].lo[2], boxes[DS_MAT_DENTIN].hi[2]);
}

TEST(ToothBuilder, KeepOrientationRecordsTheAxisButLeavesTheGrid) {
  ToothAxesHint hint = crownAlong(-1);
  hint.turn = false;
  Result<ToothVolume> tooth = buildToothFromLabels(smallTooth(1, 0), enamelDentinMap(), hint, {});
  ASSERT_TRUE(tooth) << tooth.message();
  EXPECT_FALSE(tooth->frame.tooth.turned());
  const auto boxes = tissueVoxelBoxes(tooth->voxels);
  EXPECT_EQ(boxes[DS_MAT_ENAMEL].lo[2], 0);  // still under the dentin
}

TEST(ToothBuilder, AnUnmappedLabelIsTheImportsError) {
  LabelImportOptions import = enamelDentinMap();
  import.map.erase(1);
  Result<ToothVolume> tooth = buildToothFromLabels(smallTooth(0, 2), import, crownAlong(1), {});
  ASSERT_FALSE(tooth);
  EXPECT_EQ(tooth.message().rfind("small.nii: ", 0), 0u) << tooth.message();
}

TEST(ToothBuilder, TheSegmentationLabelMapFollowsTheGreyClasses) {
  // segmentTooth's classes are caries, dentin and enamel, under the tissue table's labels.
  EXPECT_EQ(toothSegmentLabelMap(), parseLabelMap("1=enamel,2=dentin,4=caries").value());
}

// A 12^3 grey image of 0.5 mm voxels: a 4^3 block of dentin (1500) at i, j, k = 4..7, its top layer
// (k = 7) enamel (2500); air 0 elsewhere.
GreyImage smallScan() {
  GreyImage im;
  im.dims = {12, 12, 12};
  im.pitch_mm = {0.5, 0.5, 0.5};
  im.scanner_from_voxel = {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0};
  im.values.assign(12 * 12 * 12, 0.0f);
  for (int k = 4; k <= 7; ++k)
    for (int j = 4; j <= 7; ++j)
      for (int i = 4; i <= 7; ++i) im.values[size_t(i + 12 * (j + 12 * k))] = k == 7 ? 2500.0f : 1500.0f;
  return im;
}

TEST(ToothBuilder, AScanIsSegmentedImportedAndDescribed) {
  ScanToothOptions so;
  so.ct = "small.nrrd";
  so.segment.dentin_above = 1000;
  so.segment.enamel_above = 2000;
  so.segment.partial_volume_voxels = 0;  // plain thresholds: the counts below are the block's
  so.segment.min_island_mm3 = 0;
  // Level 3: the 2 mm tissue box in 8 - 4 voxels makes the voxel 0.5 mm, the scan's pitch, so each
  // grid voxel samples exactly one scan voxel. Enamel 4 x 4 = 16, dentin 4 x 4 x 3 = 48; the block
  // is solid, so no pulp is enclosed.
  so.level = 3;
  ScanToothReport report;
  Result<ToothVolume> tooth = buildToothFromGreyImage(smallScan(), "small.nrrd", so, {}, {}, &report);
  ASSERT_TRUE(tooth) << tooth.message();
  const MaterialTotals totals = tooth->voxels.materialTotals();
  EXPECT_EQ(totals.voxels[DS_MAT_ENAMEL], 16u);
  EXPECT_EQ(totals.voxels[DS_MAT_DENTIN], 48u);
  EXPECT_EQ(totals.voxels[DS_MAT_PULP], 0u);
  EXPECT_DOUBLE_EQ(tooth->frame.voxel_mm, 0.5);
  // The crown is found from the enamel on top: +z, no turn.
  EXPECT_EQ(tooth->frame.tooth.crown_source, AxisSource::Found);
  EXPECT_FALSE(tooth->frame.tooth.turned());
  // scan, thresholds, tooth, clean-up, pulp: printed by voxelize and kept as the file's note.
  ASSERT_EQ(report.lines.size(), 5u);
  EXPECT_EQ(report.lines[0].rfind("scan: small.nrrd, 12 x 12 x 12 voxels", 0), 0u) << report.lines[0];
  EXPECT_EQ(report.lines[4].rfind("pulp: ", 0), 0u) << report.lines[4];
  EXPECT_EQ(tooth->source_note.find(report.lines[1]), tooth->source_note.find('\n') + 1);
}

TEST(ToothBuilder, ABoxMeshIsVoxelizedOnTheCpuAndTheEngineIsAsked) {
  // A 4 mm dentin cube at 1 mm voxels: 4 + 2 x 2 margin voxels fit level 3 with the voxel exactly
  // 1 mm, and the cube, centred, lies on voxel faces: 4^3 = 64 full voxels.
  test::TempDir dir;
  const std::string path = dir.file("cube.stl");
  ASSERT_TRUE(writeStl(path, test::box({0, 0, 0}, {4, 4, 4}), "cube"));
  MeshToothOptions mo;
  mo.layers = {{path, Material::Dentin}};
  mo.voxel_mm = 1.0;
  int opened = 0;
  mo.engine.open = [&opened]() -> Result<bool> {
    ++opened;
    return false;  // no device: the CPU reference runs
  };
  std::vector<VoxelizeCost> plans;
  ToothBuildHooks hooks;
  hooks.approve = [&plans](const VoxelizeCost& cost) -> Status {
    plans.push_back(cost);
    return Ok{};
  };
  MeshToothReport report;
  Result<ToothVolume> tooth = buildToothFromMeshes(mo, crownAlong(1), hooks, &report);
  ASSERT_TRUE(tooth) << tooth.message();
  EXPECT_EQ(opened, 1);
  EXPECT_EQ(plans.size(), 1u);
  EXPECT_FALSE(report.engine_ran);
  EXPECT_EQ(tooth->frame.level, 3);
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_DENTIN], 64u);
  ASSERT_EQ(report.layers.size(), 1u);
  EXPECT_EQ(report.layers[0].triangles, 12u);
  EXPECT_NEAR(report.layers[0].volume_mm3, 64.0, 1e-6);
}

TEST(ToothBuilder, APlanThatRefusesEndsTheBuildWithItsMessage) {
  test::TempDir dir;
  const std::string path = dir.file("cube.stl");
  ASSERT_TRUE(writeStl(path, test::box({0, 0, 0}, {4, 4, 4}), "cube"));
  MeshToothOptions mo;
  mo.layers = {{path, Material::Dentin}};
  ToothBuildHooks hooks;
  hooks.approve = [](const VoxelizeCost&) -> Status { return Error{"voxelize: beyond the memory budget"}; };
  Result<ToothVolume> tooth = buildToothFromMeshes(mo, crownAlong(1), hooks);
  ASSERT_FALSE(tooth);
  EXPECT_EQ(tooth.message(), "voxelize: beyond the memory budget");
}

// A 4 mm dentin cube at 0..4 and two neighbour cubes beside it, one at -5..-1 (apart) and one at
// 3..7 (overlapping the tooth's last millimetre in x). The grid is fitted to all three: -5..7 in x
// with 2 margin voxels of 1 mm is 16 voxels, level 4, origin (-7, -6, -6), so every cube lies on
// voxel faces. The tooth keeps its 64 voxels; the neighbours get 64 + (64 - 16) = 112.
TEST(ToothBuilder, NeighboursJoinWhereTheToothIsEmptyAndTheToothWinsSharedVoxels) {
  test::TempDir dir;
  ASSERT_TRUE(writeStl(dir.file("tooth.stl"), test::box({0, 0, 0}, {4, 4, 4}), "tooth"));
  ASSERT_TRUE(writeStl(dir.file("left.stl"), test::box({-5, 0, 0}, {-1, 4, 4}), "left"));
  ASSERT_TRUE(writeStl(dir.file("right.stl"), test::box({3, 0, 0}, {7, 4, 4}), "right"));
  MeshToothOptions mo;
  mo.layers = {{dir.file("tooth.stl"), Material::Dentin}};
  mo.neighbours = {dir.file("left.stl"), dir.file("right.stl")};
  mo.voxel_mm = 1.0;
  MeshToothReport report;
  Result<ToothVolume> tooth = buildToothFromMeshes(mo, crownAlong(1), {}, &report);
  ASSERT_TRUE(tooth) << tooth.message();
  EXPECT_EQ(tooth->frame.level, 4);
  EXPECT_EQ(tooth->frame.origin_mm, (std::array<double, 3>{-7, -6, -6}));
  const MaterialTotals totals = tooth->voxels.materialTotals();
  EXPECT_EQ(totals.voxels[DS_MAT_DENTIN], 64u);
  EXPECT_EQ(totals.voxels[DS_MAT_NEIGHBOUR], 112u);
  EXPECT_EQ(totals.fill_sum[DS_MAT_NEIGHBOUR], 112u * DS_FILL_FULL);
  EXPECT_EQ(report.neighbour_voxels, 112u);
  ASSERT_EQ(report.neighbours.size(), 2u);
  EXPECT_NEAR(report.neighbours[1].volume_mm3, 64.0, 1e-6);
  // Voxel (x = 3 mm .. 4 mm) is the tooth's, (4 .. 5) the right neighbour's: grid x 10 and 11.
  EXPECT_EQ(voxelMaterial(tooth->voxels.voxel(10, 7, 7)), Material::Dentin);
  EXPECT_EQ(voxelMaterial(tooth->voxels.voxel(11, 7, 7)), Material::Neighbour);
  // The frame is the treated tooth's: its occlusal centre over the tooth (x 1..3 mm, the middle
  // voxel's centre: 1.5 mm), not over all three cubes (0.5 mm).
  ASSERT_TRUE(tooth->frame.tooth.has_occlusal_centre);
  EXPECT_GE(tooth->frame.tooth.occlusal_centre_mm[0], 1.0);
  EXPECT_LE(tooth->frame.tooth.occlusal_centre_mm[0], 3.0);
  EXPECT_NEAR(tooth->frame.tooth.occlusal_centre_mm[2], 4.0, 0.01);
}

// An enamel top over dentin, and one neighbour standing taller, to one side: the crown axis is found
// from the tooth's enamel against its own roots, +z, not tilted toward the neighbour.
TEST(ToothBuilder, TheCrownAxisIsFoundFromTheTreatedToothAlone) {
  test::TempDir dir;
  ASSERT_TRUE(writeStl(dir.file("enamel.stl"), test::box({0, 0, 0}, {4, 4, 6}), "enamel"));
  ASSERT_TRUE(writeStl(dir.file("dentin.stl"), test::box({0, 0, 0}, {4, 4, 5}), "dentin"));
  ASSERT_TRUE(writeStl(dir.file("near.stl"), test::box({-5, 0, -6}, {-1, 4, 6}), "near"));
  MeshToothOptions mo;
  mo.layers = {{dir.file("enamel.stl"), Material::Enamel}, {dir.file("dentin.stl"), Material::Dentin}};
  mo.neighbours = {dir.file("near.stl")};
  mo.voxel_mm = 0.5;
  ToothAxesHint hint;
  hint.turn = false;
  Result<ToothVolume> tooth = buildToothFromMeshes(mo, hint, {});
  ASSERT_TRUE(tooth) << tooth.message();
  EXPECT_EQ(tooth->frame.tooth.crown_source, AxisSource::Found);
  EXPECT_GT(tooth->frame.tooth.crown[2], 0.99) << tooth->frame.tooth.crown[0];
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_NEIGHBOUR], 8u * 8u * 24u);
}

TEST(ToothBuilder, LayersAreSynthesizedFromOneSurfaceOnly) {
  test::TempDir dir;
  ASSERT_TRUE(writeStl(dir.file("a.stl"), test::box({0, 0, 0}, {4, 4, 4}), "a"));
  MeshToothOptions mo;
  mo.layers = {{dir.file("a.stl"), Material::Enamel}, {dir.file("a.stl"), Material::Dentin}};
  mo.synthesize = LayerSynthOptions{};
  Result<ToothVolume> tooth = buildToothFromMeshes(mo, {}, {});
  ASSERT_FALSE(tooth);
  EXPECT_EQ(tooth.message(), "layers are synthesized from one whole-tooth surface, not from 2 layers");
}

// The pulp from a scan replaces a synthesized one in the surface's own mm: without synthesis, or in
// a reference's turned grid, it is refused before any scan is read (the scan named here does not exist).
TEST(ToothBuilder, ThePulpFromAScanNeedsSynthesisAndTheSurfacesOwnMm) {
  test::TempDir dir;
  ASSERT_TRUE(writeStl(dir.file("a.stl"), test::box({0, 0, 0}, {4, 4, 4}), "a"));
  MeshToothOptions mo;
  mo.layers = {{dir.file("a.stl"), Material::Dentin}};
  mo.pulp_from = dir.file("none.nii");
  Result<ToothVolume> plain = buildToothFromMeshes(mo, {}, {});
  ASSERT_FALSE(plain);
  EXPECT_EQ(plain.message(), "the pulp is taken from a scan in place of a synthesized one: give one whole-tooth surface");
  mo.synthesize = LayerSynthOptions{};
  mo.reference = VolumeFrame::axisAligned(5, 0.25, {0, 0, 0});
  Result<ToothVolume> referenced = buildToothFromMeshes(mo, {}, {});
  ASSERT_FALSE(referenced);
  EXPECT_EQ(referenced.message(), "the pulp from a scan needs the surface's own mm; a reference grid turns them");
  mo.reference.reset();
  Result<ToothVolume> missing = buildToothFromMeshes(mo, {}, {});
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.message().find("none.nii"), std::string::npos) << missing.message();
}

// A PLY or an OBJ is read as an STL would be: the same cube, the same voxels.
TEST(ToothBuilder, PlyAndObjLayersAreReadLikeAnStl) {
  test::TempDir dir;
  const TriangleMesh cube = test::box({0, 0, 0}, {4, 4, 4});
  ASSERT_TRUE(writePly(dir.file("cube.PLY"), PlyView{cube.positions, {}, {}, cube.triangles}));
  MeshToothOptions mo;
  mo.layers = {{dir.file("cube.PLY"), Material::Dentin}};
  mo.voxel_mm = 1.0;
  Result<ToothVolume> tooth = buildToothFromMeshes(mo, crownAlong(1), {});
  ASSERT_TRUE(tooth) << tooth.message();
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_DENTIN], 64u);

  // And an OBJ of the same cube, its corners written out by hand.
  std::string obj;
  for (const Vec3f& p : cube.positions)
    obj += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  for (const auto& t : cube.triangles)
    obj += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  test::writeBytes(dir.file("cube.obj"), std::vector<uint8_t>(obj.begin(), obj.end()));
  mo.layers = {{dir.file("cube.obj"), Material::Dentin}};
  tooth = buildToothFromMeshes(mo, crownAlong(1), {});
  ASSERT_TRUE(tooth) << tooth.message();
  EXPECT_EQ(tooth->voxels.materialTotals().voxels[DS_MAT_DENTIN], 64u);
}

}  // namespace
}  // namespace dentsim
