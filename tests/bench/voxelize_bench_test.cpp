// Tests of the voxelization benchmark's measurement and report, with a fake dentsim voxelizer.
#include "bench/voxelize_bench.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "test_meshes.h"
#include "test_support.h"

namespace dentsim::bench {
namespace {

// An axis-aligned cube [lo, hi]^3 [mm].
TriangleMesh box(float lo, float hi) { return test::box({lo, lo, lo}, {hi, hi, hi}); }

// Times 30, 10, 20, ... ms in turn, so the median of three runs after the warm-up is known.
DentsimVoxelizer fakeVoxelizer(int* calls) {
  return [calls](const std::vector<MeshLayer>& layers, const VolumeFrame&) -> Result<DentsimRun> {
    const double ms[] = {99.0, 30.0, 10.0, 20.0};  // warm-up first
    DentsimRun run;
    run.ms = ms[*calls % 4];
    run.kernel_ms = run.ms / 2;
    run.dense_bricks = layers.size();
    run.totals.fill_sum[size_t(Material::Enamel)] = 31 * 64;  // 64 full voxels
    ++*calls;
    return run;
  };
}

TEST(VoxelizeBenchTest, MediansRatioAndVolumes) {
  const TriangleMesh outer = box(0.0f, 1.0f);
  const TriangleMesh inner = box(0.25f, 0.75f);
  const std::vector<MeshLayer> layers{{Material::Enamel, &outer, "enamel"}, {Material::Dentin, &inner, "dentin"}};
  const DecimatedModel model = decimateModel(layers, 1.0);
  EXPECT_EQ(model.triangles(), 24u);
  const VolumeFrame frame = VolumeFrame::axisAligned(4, 0.125, {-0.5, -0.5, -0.5});  // 16 x 0.125 = 2 mm
  int calls = 0;
  auto row = measureVoxelize(model, frame, VoxelizeBenchSettings{}, fakeVoxelizer(&calls));
  ASSERT_TRUE(row.ok()) << row.message();
  EXPECT_EQ(calls, 4);  // one warm-up, three timed
  EXPECT_EQ(row->dentsim_runs_ms, (std::vector<double>{30.0, 10.0, 20.0}));
  EXPECT_EQ(row->dentsim_ms, 20.0);
  EXPECT_EQ(row->dentsim_kernel_ms, 10.0);
  ASSERT_EQ(row->tissues.size(), 2u);
  EXPECT_NEAR(row->tissues[0].mesh_mm3, 1.0, 1e-6);
  EXPECT_NEAR(row->tissues[1].mesh_mm3, 0.125, 1e-6);
  EXPECT_NEAR(row->tissues[0].dentsim_mm3, 64 * 0.125 * 0.125 * 0.125, 1e-12);
  if (row->openvdb.available) {
    // Centres at -0.5 + 0.0625 + 0.125 i: 8 per axis inside [0, 1], 4 inside [0.25, 0.75], the
    // same whether the inside is stored (filled) or known by sign (narrow band).
    EXPECT_NEAR(row->tissues[0].openvdb_mm3, 512 * 0.125 * 0.125 * 0.125, 1e-9);
    EXPECT_NEAR(row->tissues[1].openvdb_mm3, 64 * 0.125 * 0.125 * 0.125, 1e-9);
    EXPECT_NEAR(row->tissues[0].openvdb_band_mm3, 512 * 0.125 * 0.125 * 0.125, 1e-9);
    EXPECT_NEAR(row->tissues[1].openvdb_band_mm3, 64 * 0.125 * 0.125 * 0.125, 1e-9);
    EXPECT_EQ(row->openvdb.runs_ms.size(), 3u);
    EXPECT_NEAR(row->openvdb.ratio, row->openvdb.ms / 20.0, 1e-12);
    ASSERT_TRUE(row->openvdb_band.available);
    EXPECT_NEAR(row->openvdb_band.ratio, row->openvdb_band.ms / 20.0, 1e-12);
  } else {
    EXPECT_EQ(row->openvdb.ratio, 0.0);
  }
}

TEST(VoxelizeBenchTest, NoPeersSaysSo) {
  const TriangleMesh outer = box(0.0f, 1.0f);
  const DecimatedModel model = decimateModel({{Material::Enamel, &outer, "enamel"}}, 1.0);
  int calls = 0;
  VoxelizeBenchSettings s;
  s.peers = false;
  s.repeats = 1;
  s.warmup = false;
  auto row = measureVoxelize(model, VolumeFrame::axisAligned(3, 0.25, {0, 0, 0}), s, fakeVoxelizer(&calls));
  ASSERT_TRUE(row.ok());
  EXPECT_EQ(calls, 1);
  EXPECT_FALSE(row->openvdb.available);
  EXPECT_FALSE(row->openvdb_band.available);
  EXPECT_NE(row->openvdb.name.find("--no-peers"), std::string::npos);
}

TEST(VoxelizeBenchTest, ErrorsOfDentsimPassThrough) {
  const TriangleMesh outer = box(0.0f, 1.0f);
  const DecimatedModel model = decimateModel({{Material::Enamel, &outer, "enamel"}}, 1.0);
  auto failing = [](const std::vector<MeshLayer>&, const VolumeFrame&) -> Result<DentsimRun> {
    return Error{"gpu: out of memory"};
  };
  auto row = measureVoxelize(model, VolumeFrame::axisAligned(3, 0.25, {0, 0, 0}), {}, failing);
  ASSERT_FALSE(row.ok());
  EXPECT_EQ(row.message(), "gpu: out of memory");
}

TEST(VoxelizeBenchTest, MedianOfEvenCountIsMeanOfMiddle) {
  EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(median({7.0}), 7.0);
}

TEST(VoxelizeBenchTest, ReportHasEveryRowAndBothSystems) {
  VoxelizeRow a;
  a.level = 8;
  a.voxel_mm = 0.05;
  a.fraction = 0.25;
  a.triangles = 1234567;
  a.dentsim_ms = 12.5;
  a.openvdb = PeerTiming{true, "OpenVDB test, filled", 2, {250.0}, 250.0, 20.0};
  a.openvdb_band = PeerTiming{true, "OpenVDB test, band", 2, {50.0}, 50.0, 4.0};
  a.tissues.push_back(TissueRow{"enamel", Material::Enamel, 1234567, "simplify", 0, 0.001, 10.0, 9.0, 9.9, 9.9, 250.0});
  VoxelizeRow b = a;
  b.fraction = 1.0;
  b.triangles = 4938268;
  b.openvdb = b.openvdb_band = PeerTiming{};
  VoxelizeReportInfo info;
  info.model = "two boxes";
  info.device = "llvmpipe";
  info.subsamples = 2;
  const std::string md = voxelizeReportMarkdown(info, {a, b});
  EXPECT_NE(md.find("| 8 | 0.0500 | 25 | 1,234,567 | 12.5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 250.0 | 20.00 | 50.0 | 4.00 |"), std::string::npos) << md;
  EXPECT_NE(md.find("OpenVDB test on 2 TBB threads"), std::string::npos) << md;
  EXPECT_NE(md.find("| n/a |"), std::string::npos) << md;  // row b has no peer
  const nlohmann::json j = voxelizeReportJson(info, {a, b});
  ASSERT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["rows"][0]["ratio_openvdb_over_dentsim"], 20.0);
  EXPECT_EQ(j["rows"][1]["openvdb"]["available"], false);
  const std::string svg = voxelizeRowsSvg({a, b});
  EXPECT_NE(svg.find("dentsim L8"), std::string::npos);
  EXPECT_NE(svg.find("OpenVDB filled L8"), std::string::npos);
  EXPECT_NE(svg.find("OpenVDB band L8"), std::string::npos);
  EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos);
}

TEST(VoxelizeBenchTest, RunIsEveryLevelTimesEveryShareAndWritesThreeFiles) {
  const TriangleMesh outer = box(0.0f, 1.0f);
  const std::vector<MeshLayer> layers{{Material::Enamel, &outer, "enamel"}};
  Bounds3 bounds;
  bounds.add(outer.bounds());
  VoxelizeBenchSettings settings;
  settings.peers = false;
  int calls = 0;
  std::vector<std::string> lines;
  // Two levels x two shares: four rows, one progress line each, level-major.
  auto rows = runVoxelizeBench(layers, bounds, {4, 5}, {50.0, 100.0}, settings, fakeVoxelizer(&calls),
                               [&](const std::string& line) { lines.push_back(line); });
  ASSERT_TRUE(rows.ok()) << rows.message();
  ASSERT_EQ(rows->size(), 4u);
  EXPECT_EQ((*rows)[0].level, 4);
  EXPECT_EQ((*rows)[3].level, 5);
  EXPECT_EQ((*rows)[1].fraction, 1.0);
  EXPECT_EQ(calls, 16);  // each row: one warm-up, three timed
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[1].rfind("level 4, 100% (12 triangles): dentsim ", 0), 0u) << lines[1];

  test::TempDir dir;
  VoxelizeReportInfo info;
  info.settings = settings;
  ASSERT_TRUE(writeVoxelizeReport(dir.path().string(), info, *rows).ok());
  for (const char* name : {"voxelize.json", "voxelize.md", "voxelize.svg"})
    EXPECT_GT(std::filesystem::file_size(dir.file(name)), 0u) << name;
  // Only the three reports: the atomic writer leaves no temporary beside them.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator{}), 3);
}

}  // namespace
}  // namespace dentsim::bench
