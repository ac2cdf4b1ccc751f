// Tests of `dentsim voxelize` with STL layers: the GPU and the CPU reference agree, and bad files or flags fail in one line.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "io/stl_file.h"
#include "test_meshes.h"
#include "test_support.h"
#include "volume/tissue_table.h"
#include "volume/tooth_file.h"

namespace dentsim {
namespace {

using test::NoLeakCheckForGpuChild;
using test::runDentsim;
using test::TempDir;
using test::writeBytes;


// Two nested layers in cm, as a scanner might export them: a 1 cm cube of enamel around a
// 0.5 cm sphere of pulp.
class VoxelizeStlCli : public ::testing::Test {
 protected:
  void SetUp() override {
    writeBytes(dir_.file("outer.stl"), encodeStlBinary(test::box({0, 0, 0}, {1, 1, 1}), "outer"));
    writeBytes(dir_.file("inner.stl"), encodeStlBinary(test::uvSphere({0.5, 0.5, 0.5}, 0.25, 48, 24), "inner"));
  }
  std::string layers() const {
    return "--enamel " + dir_.file("outer.stl") + " --pulp " + dir_.file("inner.stl") + " --units cm --level 6";
  }
  TempDir dir_;
};

TEST_F(VoxelizeStlCli, GpuAndCpuWriteTheSameVoxels) {
  const NoLeakCheckForGpuChild no_leak_check;
  const auto gpu = runDentsim("voxelize " + layers() + " -o " + dir_.file("gpu.dvol"));
  ASSERT_EQ(gpu.exit_code, 0) << gpu.output;
  const auto cpu = runDentsim("voxelize " + layers() + " --cpu -o " + dir_.file("cpu.dvol"));
  ASSERT_EQ(cpu.exit_code, 0) << cpu.output;
  EXPECT_NE(cpu.output.find("CPU reference"), std::string::npos) << cpu.output;
  auto a = loadTooth(dir_.file("gpu.dvol"));
  auto b = loadTooth(dir_.file("cpu.dvol"));
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_TRUE(a->voxels == b->voxels);
  // 10 mm cube minus a sphere of 2.5 mm radius, in mm^3: the units were applied.
  const double vox = a->frame.voxel_mm;
  const MaterialTotals t = a->voxels.materialTotals();
  const double sphere = test::sphereVolume(2.5);
  EXPECT_NEAR(t.volumeMm3(Material::Pulp, vox) / sphere, 1.0, 0.02);
  EXPECT_NEAR(t.volumeMm3(Material::Enamel, vox) / (1000.0 - sphere), 1.0, 0.01);
}

TEST_F(VoxelizeStlCli, BadInputFailsInOneLineAndWritesNothing) {
  const std::string out = dir_.file("never.dvol");
  auto bytes = encodeStlBinary(test::box({0, 0, 0}, {1, 1, 1}), "cut");
  bytes.resize(bytes.size() - 30);
  writeBytes(dir_.file("cut.stl"), bytes);
  struct Case {
    std::string args, expect;
  };
  const Case cases[] = {
      {"--tooth " + dir_.file("cut.stl") + " --cpu", "cut.stl"},
      {"--tooth " + dir_.file("missing.stl") + " --cpu", "missing.stl"},
      {"--tooth " + dir_.file("outer.stl") + " --units parsec --cpu", "--units"},
      {layers() + " --labels x.nii.gz --cpu", "give one source: STL layers, --labels, --dicom or --ct"},
      {layers() + " --dicom scans/ --cpu", "give one source"},
      {layers() + " --min-piece 3 --cpu", "apply to --labels"},
      {layers() + " --fill-enclosed pulp --cpu", "apply to --labels"},
      {"--cpu", "nothing to voxelize"},
      {layers() + " --scale -2 --cpu", "scale"},
  };
  for (const Case& c : cases) {
    const auto r = runDentsim("voxelize " + c.args + " -o " + out);
    EXPECT_NE(r.exit_code, 0) << c.args << "\n" << r.output;  // 1, or CLI11's code for a refused number
    EXPECT_EQ(r.output.rfind("dentsim: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
  }
}

// Every tissue of the table has its STL flag, named as the table names it, that fills the layer with
// that tissue; the message for no input names them all. A tissue added to the table gets its flag
// without another list to edit; the neighbour, an adjacent tooth whole, has --neighbour instead.
TEST_F(VoxelizeStlCli, EveryTissueOfTheTableHasItsLayerFlag) {
  std::string flags;
  for (const TissueRow& row : kTissueTable) {
    if (row.material == Material::Neighbour) continue;  // no layer flag: --neighbour adds whole teeth
    const std::string out = dir_.file(std::string(row.name) + ".dvol");
    const auto r = runDentsim("voxelize --" + std::string(row.name) + " " + dir_.file("outer.stl") +
                              " --units cm --level 5 --cpu -o " + out);
    ASSERT_EQ(r.exit_code, 0) << row.name << "\n" << r.output;
    EXPECT_NE(r.output.find("  layer " + std::string(row.name)), std::string::npos) << r.output;
    auto t = loadTooth(out);
    ASSERT_TRUE(t.ok()) << row.name;
    const MaterialTotals totals = t->voxels.materialTotals();
    EXPECT_NEAR(totals.volumeMm3(row.material, t->frame.voxel_mm) / 1000.0, 1.0, 0.02) << row.name;
    flags += (flags.empty() ? "--" : "/--") + std::string(row.name);
  }
  const auto none = runDentsim("voxelize --cpu -o " + dir_.file("never.dvol"));
  EXPECT_NE(none.output.find("give " + flags + " STL layers"), std::string::npos) << none.output;
}

TEST_F(VoxelizeStlCli, OpenMeshAndOddUnitsAreVoxelizedWithWarnings) {
  TriangleMesh open = test::uvSphere({0, 0, 0}, 5.0, 48, 24);
  open.triangles.resize(open.triangles.size() - 48);  // the north polar fan
  writeBytes(dir_.file("open.stl"), encodeStlBinary(open, "open"));
  const auto r = runDentsim("voxelize --tooth " + dir_.file("open.stl") + " --tooth-material dentin --level 6 --cpu -o " +
                            dir_.file("open.dvol"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("48 open edges"), std::string::npos) << r.output;
  auto t = loadTooth(dir_.file("open.dvol"));
  ASSERT_TRUE(t.ok());
  EXPECT_NEAR(t->voxels.materialTotals().volumeMm3(Material::Dentin, t->frame.voxel_mm) / test::sphereVolume(5.0), 1.0,
              0.03);
  // A 10 um tooth draws a units warning but is still voxelized.
  const auto tiny = runDentsim("voxelize --tooth " + dir_.file("open.stl") + " --units um --level 5 --cpu -o " +
                               dir_.file("tiny.dvol"));
  EXPECT_EQ(tiny.exit_code, 0) << tiny.output;
  EXPECT_NE(tiny.output.find("does not look like a tooth"), std::string::npos) << tiny.output;
}

TEST_F(VoxelizeStlCli, LevelThirteenBeyondTheMemoryBudgetIsRefusedBeforeItAllocates) {
  // The 1 cm cube at level 13: its faces cross about 6.3 million bricks, some 10 GB. With a 4 GB
  // budget the plan refuses in one line naming the estimate, the budget and the flag, before the
  // rays or the bricks are made: the child's peak stays that of a program that only read its meshes.
  const std::string output = dir_.file("huge.dvol");
  const auto r = runDentsim("--max-memory-mb 4096 voxelize --enamel " + dir_.file("outer.stl") + " --pulp " +
                            dir_.file("inner.stl") + " --units cm --level 13 --cpu -o " + output);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const size_t at = r.output.find("dentsim: voxelize: level 13 (8192^3 voxels): about ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const std::string refusal = r.output.substr(at);
  EXPECT_EQ(std::count(refusal.begin(), refusal.end(), '\n'), 1) << refusal;
  EXPECT_NE(refusal.find(" GB of memory"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("beyond the memory budget of 4.3 GB (set with --max-memory-mb)"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("--force"), std::string::npos) << refusal;
  EXPECT_FALSE(std::filesystem::exists(output));
  struct rusage children {};
  ASSERT_EQ(::getrusage(RUSAGE_CHILDREN, &children), 0);
  EXPECT_LT(children.ru_maxrss, 1024L * 1024) << "KiB: the refused run allocated what it planned";
}

}  // namespace
}  // namespace dentsim
