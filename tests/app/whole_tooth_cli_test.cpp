// Tests of `dentsim voxelize --tooth` with one whole-tooth surface: layers synthesized, the crown axis found from the shape, adjacent teeth as neighbours, and a task run on the result.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <nlohmann/json.hpp>

#include "io/stl_file.h"
#include "test_support.h"
#include "volume/tissue_table.h"
#include "volume/tooth_file.h"
#include "volume/tooth_frame.h"

namespace dentsim {
namespace {

using test::runDentsim;
using test::TempDir;

// The shared real teeth: the chai3d molar (unitless, 25 units a mm, crown +Z) and the Wikimedia
// CC0 molar (in cm); empty when the data folder lacks them.
std::string sharedTooth(const std::string& name) {
  const std::filesystem::path p = test::dataDir() / "teeth" / name;
  return std::filesystem::exists(p) ? p.string() : std::string();
}
const char* const kChaiScale = " --scale 0.04";

double degreesBetween(const Vec3& a, const Vec3& b) {
  const double c = dot(a, b) / (norm(a) * norm(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

nlohmann::json infoJson(const std::string& dvol) {
  const auto r = runDentsim("info --json " + dvol);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return nlohmann::json::parse(r.output, nullptr, false);
}

// The crown axis the file records, in the STL's own coordinates (before voxelize's quarter turns).
Vec3 crownInSource(const ToothVolume& t) {
  const auto& c = t.frame.tooth.crown;
  return sourceDirection(t.frame, Vec3{c[0], c[1], c[2]});
}

// Each tissue's voxels and the z range of the enamel against the whole tooth's, in voxels.
struct Layers {
  MaterialTotals totals;
  VoxelBox tooth, enamel;
};
Layers layersOf(const ToothVolume& t) {
  const auto boxes = tissueVoxelBoxes(t.voxels);
  return {t.voxels.materialTotals(), boxes[0], boxes[DS_MAT_ENAMEL]};
}

// Enamel, dentin and pulp present, the enamel only over the upper part (the crown, above the CEJ):
// a molar's crown is about 7.5 of its 20 mm, so nothing of it in the lower 45 % (the tooth may stand
// tilted by up to 45 degrees after its quarter turns).
void expectSynthesizedLayers(const ToothVolume& t) {
  EXPECT_EQ(t.layers, LayerSource::Synthesized);
  const Layers l = layersOf(t);
  EXPECT_GT(l.totals.voxels[DS_MAT_ENAMEL], 0u);
  EXPECT_GT(l.totals.voxels[DS_MAT_DENTIN], 0u);
  EXPECT_GT(l.totals.voxels[DS_MAT_PULP], 0u);
  EXPECT_EQ(l.totals.voxels[DS_MAT_CARIES], 0u);
  ASSERT_FALSE(l.enamel.empty());
  const double height = double(l.tooth.hi[2] - l.tooth.lo[2] + 1);
  EXPECT_GT(double(l.enamel.lo[2] - l.tooth.lo[2]), 0.45 * height) << "enamel from z " << l.enamel.lo[2];
  EXPECT_EQ(l.enamel.hi[2], l.tooth.hi[2]);  // the cap reaches the cusps
}

TEST(WholeToothCli, TheChaiMolarGetsEnamelDentinAndPulpAndItsCrownAxisFound) {
  const std::string stl = sharedTooth("chai3d_molar_tooth.stl");
  if (stl.empty()) GTEST_SKIP() << "no shared teeth (DENTSIM_DATA_DIR)";
  TempDir dir;
  const std::string out = dir.file("m.dvol");
  const auto r = runDentsim("voxelize --tooth " + stl + kChaiScale + " --level 7 --cpu -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("synthesized"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("crown axis found from the tooth's shape"), std::string::npos) << r.output;
  auto t = loadTooth(out);
  ASSERT_TRUE(t.ok()) << t.message();
  expectSynthesizedLayers(*t);
  EXPECT_EQ(t->frame.tooth.crown_source, AxisSource::Found);
  EXPECT_LT(degreesBetween(crownInSource(*t), {0, 0, 1}), 15.0);
  // The report's lines are kept for info, the first saying the layers are synthesized.
  EXPECT_NE(t->source_note.find("synthesized"), std::string::npos) << t->source_note;

  const nlohmann::json j = infoJson(out);
  EXPECT_EQ(j["tooth_frame"]["crown_from"], "found");
  EXPECT_EQ(j["layers"]["source"], "synthesized");
  const auto text = runDentsim("info " + out);
  EXPECT_NE(text.output.find("layers      synthesized from one surface ("), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("type), not measured"), std::string::npos) << text.output;
}

// The crown axis comes from the shape, not from how the file lies: the molar on its side and
// turned about the long axis of the jaw still has its crown found where its +Z went.
TEST(WholeToothCli, TheCrownAxisIsFoundWhenTheToothLiesOnItsSide) {
  const std::string stl = sharedTooth("chai3d_molar_tooth.stl");
  if (stl.empty()) GTEST_SKIP() << "no shared teeth (DENTSIM_DATA_DIR)";
  TempDir dir;
  auto mesh = readStl(stl);
  ASSERT_TRUE(mesh.ok()) << mesh.message();
  // 90 degrees about x (crown +Z to -Y), then 30 degrees about z.
  const double a = std::numbers::pi / 6.0;
  const auto rotate = [a](Vec3 p) {
    const Vec3 s{p.x, -p.z, p.y};  // (0,0,1) -> (0,-1,0)
    return Vec3{std::cos(a) * s.x - std::sin(a) * s.y, std::sin(a) * s.x + std::cos(a) * s.y, s.z};
  };
  for (Vec3f& p : mesh->mesh.positions) {
    const Vec3 q = rotate(Vec3{p[0], p[1], p[2]});
    p = Vec3f{float(q.x), float(q.y), float(q.z)};
  }
  ASSERT_TRUE(writeStl(dir.file("side.stl"), mesh->mesh, "chai3d molar on its side"));
  const auto r = runDentsim("voxelize --tooth " + dir.file("side.stl") + kChaiScale + " --level 7 --cpu -o " +
                            dir.file("side.dvol"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto t = loadTooth(dir.file("side.dvol"));
  ASSERT_TRUE(t.ok()) << t.message();
  EXPECT_EQ(t->frame.tooth.crown_source, AxisSource::Found);
  const Vec3 expected = rotate({0, 0, 1});
  EXPECT_LT(degreesBetween(crownInSource(*t), expected), 15.0)
      << "found (" << crownInSource(*t).x << ", " << crownInSource(*t).y << ", " << crownInSource(*t).z << ")";
  EXPECT_TRUE(t->frame.tooth.turned());  // stood up
  expectSynthesizedLayers(*t);           // in the grid as turned: crown up
}

TEST(WholeToothCli, TheWikimediaMolarInCentimetresGetsItsLayers) {
  const std::string stl = sharedTooth("cc0_molar_wikimedia.stl");
  if (stl.empty()) GTEST_SKIP() << "no shared teeth (DENTSIM_DATA_DIR)";
  TempDir dir;
  const auto r = runDentsim("voxelize --tooth " + stl + " --scale 10 --level 6 --cpu -o " + dir.file("w.dvol"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto t = loadTooth(dir.file("w.dvol"));
  ASSERT_TRUE(t.ok()) << t.message();
  expectSynthesizedLayers(*t);
  const nlohmann::json j = infoJson(dir.file("w.dvol"));
  EXPECT_EQ(j["tooth_frame"]["crown_from"], "found");
  EXPECT_EQ(j["layers"]["source"], "synthesized");
}

// --tooth-material named keeps the tooth one tissue, as before, and --tooth-type sets the proportions.
TEST(WholeToothCli, ToothMaterialKeepsOneTissueAndToothTypeIsUsed) {
  const std::string stl = sharedTooth("chai3d_molar_tooth.stl");
  if (stl.empty()) GTEST_SKIP() << "no shared teeth (DENTSIM_DATA_DIR)";
  TempDir dir;
  const auto one = runDentsim("voxelize --tooth " + stl + kChaiScale + " --tooth-material dentin --level 6 --cpu -o " +
                              dir.file("one.dvol"));
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_EQ(one.output.find("synthesized"), std::string::npos) << one.output;
  auto t = loadTooth(dir.file("one.dvol"));
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->layers, LayerSource::Measured);
  const MaterialTotals totals = t->voxels.materialTotals();
  EXPECT_GT(totals.voxels[DS_MAT_DENTIN], 0u);
  EXPECT_EQ(totals.voxels[DS_MAT_ENAMEL] + totals.voxels[DS_MAT_PULP], 0u);
  EXPECT_EQ(infoJson(dir.file("one.dvol"))["layers"]["source"], "measured");

  const auto typed = runDentsim("voxelize --tooth " + stl + kChaiScale + " --tooth-type premolar --level 6 --cpu -o " +
                                dir.file("p.dvol"));
  ASSERT_EQ(typed.exit_code, 0) << typed.output;
  EXPECT_EQ(infoJson(dir.file("p.dvol"))["layers"]["tooth_type"], "premolar");
}

// Two copies of the molar, one each side, become neighbour voxels of about their volume; the treated
// tooth's voxels are those of a run without them in the same grid, and its frame is its own.
TEST(WholeToothCli, NeighboursArePlacedBesideTheToothWhichKeepsItsVoxels) {
  const std::string stl = sharedTooth("chai3d_molar_tooth.stl");
  if (stl.empty()) GTEST_SKIP() << "no shared teeth (DENTSIM_DATA_DIR)";
  TempDir dir;
  auto mesh = readStl(stl);
  ASSERT_TRUE(mesh.ok());
  const Bounds3 b = mesh->mesh.bounds();
  const double step = (b.hi[0] - b.lo[0]) + 25.0;  // a 1 mm gap (25 units)
  for (const auto& [name, dx] : {std::pair{"left.stl", -step}, std::pair{"right.stl", step}}) {
    TriangleMesh copy = mesh->mesh;
    for (Vec3f& p : copy.positions) p[0] += float(dx);
    ASSERT_TRUE(writeStl(dir.file(name), copy, name));
  }
  const double mm = 0.04;
  const double copy_mm3 = std::abs(mesh->mesh.signedVolume()) * mm * mm * mm;
  const std::string with = dir.file("with.dvol"), without = dir.file("without.dvol");
  const auto r = runDentsim("voxelize --tooth " + stl + kChaiScale + " --neighbour " + dir.file("left.stl") +
                            " --neighbour " + dir.file("right.stl") + " --level 7 --keep-orientation --cpu -o " + with);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("neighbour voxels"), std::string::npos) << r.output;
  // The same tooth alone in the same grid.
  const auto alone = runDentsim("voxelize --tooth " + stl + kChaiScale + " --frame-of " + with + " --cpu -o " + without);
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  auto a = loadTooth(with);
  auto n = loadTooth(without);
  ASSERT_TRUE(a.ok() && n.ok());
  const MaterialTotals ta = a->voxels.materialTotals();
  const MaterialTotals tn = n->voxels.materialTotals();
  EXPECT_EQ(tn.voxels[DS_MAT_NEIGHBOUR], 0u);
  EXPECT_NEAR(ta.volumeMm3(Material::Neighbour, a->frame.voxel_mm) / (2.0 * copy_mm3), 1.0, 0.03);
  for (uint32_t m = DS_MAT_ENAMEL; m <= DS_MAT_CARIES; ++m) EXPECT_EQ(ta.voxels[m], tn.voxels[m]) << materialName(Material(m));
  // Voxel for voxel: the run with neighbours, its neighbours emptied, is the run without.
  BrickVolume emptied = a->voxels;
  const int64_t dim = emptied.dim();
  for (uint32_t z = 0; z < dim; ++z)
    for (uint32_t y = 0; y < dim; ++y)
      for (uint32_t x = 0; x < dim; ++x)
        if (voxelMaterial(emptied.voxel(x, y, z)) == Material::Neighbour) emptied.setVoxel(x, y, z, makeVoxel(Material::Empty));
  EXPECT_TRUE(emptied == n->voxels);
  // The frame is the treated tooth's: its crown as found without neighbours, its occlusal centre
  // over it (the neighbours lie either side along x, so a centre over all three would be no nearer).
  const auto own = runDentsim("voxelize --tooth " + stl + kChaiScale + " --level 7 --keep-orientation --cpu -o " +
                              dir.file("own.dvol"));
  ASSERT_EQ(own.exit_code, 0) << own.output;
  auto o = loadTooth(dir.file("own.dvol"));
  ASSERT_TRUE(o.ok());
  EXPECT_LT(degreesBetween(crownInSource(*a), crownInSource(*o)), 5.0);
  const auto boxes = tissueVoxelBoxes(a->voxels);
  double tooth_lo = 1e9, tooth_hi = -1e9;
  for (uint32_t m = DS_MAT_ENAMEL; m <= DS_MAT_PULP; ++m)
    if (!boxes[m].empty()) {
      tooth_lo = std::min(tooth_lo, a->frame.origin_mm[0] + double(boxes[m].lo[0]) * a->frame.voxel_mm);
      tooth_hi = std::max(tooth_hi, a->frame.origin_mm[0] + double(boxes[m].hi[0] + 1) * a->frame.voxel_mm);
    }
  const double centre_x = a->frame.tooth.occlusal_centre_mm[0];
  EXPECT_GT(centre_x, tooth_lo);
  EXPECT_LT(centre_x, tooth_hi);
  // info's tooth bounds are those of every tissue; the neighbour row is there apart.
  EXPECT_GT(infoJson(with)["tissues"]["neighbour"]["voxels"].get<uint64_t>(), 0u);
}

TEST(WholeToothCli, NeighbourMistakesFailInOneLineAndWriteNothing) {
  const std::string stl = sharedTooth("chai3d_molar_tooth.stl");
  if (stl.empty()) GTEST_SKIP() << "no shared teeth (DENTSIM_DATA_DIR)";
  TempDir dir;
  const std::string out = dir.file("never.dvol");
  test::expectCleanFailure(runDentsim("voxelize --labels x.nii.gz --label-map 1=dentin --neighbour " + stl + " -o " + out),
                           "--neighbour", "--label-map", out);
  test::expectCleanFailure(runDentsim("voxelize --ct x.nrrd --neighbour " + stl + " -o " + out), "--neighbour",
                           "STL layers", out);
  test::expectCleanFailure(runDentsim("voxelize --tooth " + stl + kChaiScale + " --neighbour " + dir.file("gone.stl") +
                                      " --level 6 --cpu -o " + out),
                           "gone.stl", "", out);
  test::expectCleanFailure(runDentsim("voxelize --neighbour " + stl + " --level 6 --cpu -o " + out), "--neighbour",
                           "give --tooth", out);
  test::expectCleanFailure(runDentsim("voxelize --tooth " + stl + " --tooth-type wisdom --cpu -o " + out), "--tooth-type",
                           "'wisdom'", out);
  test::expectCleanFailure(runDentsim("voxelize --tooth " + stl + " --tooth-type molar --tooth-material dentin --cpu -o " + out),
                           "--tooth-type", "keeps one tissue", out);
  test::expectCleanFailure(runDentsim("voxelize --tooth " + stl + " --tooth-material neighbour --cpu -o " + out),
                           "--tooth-material", "--neighbour", out);
  // The tissue table's neighbour row has no layer flag of its own.
  const auto help = runDentsim("voxelize --help");
  EXPECT_NE(help.output.find("--neighbour"), std::string::npos);
  EXPECT_EQ(help.output.find("Neighbour surface (STL)"), std::string::npos) << help.output;
}

// A label volume names its neighbours through --label-map instead: the tissue is known to it.
TEST(WholeToothCli, ALabelMapsToNeighbour) {
  const std::filesystem::path labels = test::dataDir() / "ct" / "tooth_2.nii.gz";
  if (!std::filesystem::exists(labels)) GTEST_SKIP() << "no shared CT labels (DENTSIM_DATA_DIR)";
  TempDir dir;
  const auto r = runDentsim("voxelize --labels " + labels.string() +
                            " --label-map 1=neighbour,2=enamel,3=dentin --voxel-size 0.034 --level 6 -o " + dir.file("l.dvol"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto t = loadTooth(dir.file("l.dvol"));
  ASSERT_TRUE(t.ok());
  const MaterialTotals totals = t->voxels.materialTotals();
  EXPECT_GT(totals.voxels[DS_MAT_NEIGHBOUR], 0u);
  EXPECT_EQ(totals.voxels[DS_MAT_CARIES], 0u);
}

// What a teacher does with a tooth from a library: voxelize it, write a cavity task on it, and a
// student's run of that task starts and ends cleanly.
TEST(WholeToothCli, AWholeToothBecomesATaskThatRuns) {
  const std::string stl = sharedTooth("chai3d_molar_tooth.stl");
  if (stl.empty()) GTEST_SKIP() << "no shared teeth (DENTSIM_DATA_DIR)";
  TempDir dir;
  std::filesystem::create_directories(dir.file("course"));
  const std::string dvol = dir.file("course/molar.dvol"), task = dir.file("course/molar_cavity.json");
  const auto made = runDentsim("voxelize --tooth " + stl + kChaiScale + " --level 7 --cpu -o " + dvol);
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const auto created = runDentsim("task new --kind cavity --tooth " + dvol + " -o " + task);
  ASSERT_EQ(created.exit_code, 0) << created.output;
  const auto checked = runDentsim("task check " + task);
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
  const test::NoLeakCheckForGpuChild no_leak_check;
  const auto ran = runDentsim("run --headless --task " + task + " --no-sound --mirror none --exit-after 1 --out " +
                              dir.file("run"));
  EXPECT_EQ(ran.exit_code, 0) << ran.output;
}

}  // namespace
}  // namespace dentsim
