// Tests of the meshing benchmark on tiny voxelized solids, with the CPU reference mesher as dentsim's runner.
#include "bench/mesh_bench.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "test_support.h"
#include "volume/surface_mesher.h"
#include "volume/volume_edit.h"

namespace dentsim::bench {
namespace {

// A 12.8 mm grid at every level holding an enamel ball of radius 0.4 x 12.8 = 5.12 mm: big enough
// for a 1 mm bur, small enough to mesh in milliseconds at levels 5 and 6.
constexpr double kGridMm = 12.8;

ToothVolume ballTooth(int level) {
  return analyticTooth(sphereForLevel(level), level, Material::Enamel, 4, kGridMm / double(1u << level));
}

// The CPU reference, counting its calls and keeping the dirty sets it was given.
struct CountingRunner {
  int full_calls = 0;
  int update_calls = 0;
  std::vector<std::vector<BrickCoord>> dirty_sets;

  MeshRunner runner() {
    MeshRunner cpu = cpuReferenceRunner();
    MeshRunner r;
    r.name = cpu.name;
    r.full = [this, cpu](const ToothVolume& t, int normals) {
      ++full_calls;
      return cpu.full(t, normals);
    };
    r.update = [this, cpu](const ToothVolume& t, std::span<const BrickCoord> dirty, int normals) {
      ++update_calls;
      dirty_sets.emplace_back(dirty.begin(), dirty.end());
      return cpu.update(t, dirty, normals);
    };
    return r;
  }
};

MeshBenchSettings tinySettings() {
  MeshBenchSettings s;
  s.levels = {5, 6};
  s.repeats = 2;
  s.bur_path.level = 6;
  s.bur_path.frames = 4;
  s.bur_path.normals = 64;
  s.normals.levels = {6};
  s.normals.samples = 2;
  return s;
}

// Cells (corner lattice of voxel centres, the grid padded by one empty voxel as the mesher sees it)
// with at least one face whose inside corners sit diagonally: the only cells where two marching-cubes
// tables may join the same crossing edges into different loops.
uint64_t ambiguousCells(const BrickVolume& v) {
  const int64_t dim = v.dim();
  auto inside = [&](int64_t x, int64_t y, int64_t z) {
    if (x < 0 || y < 0 || z < 0 || x >= dim || y >= dim || z >= dim) return false;
    return 2 * voxelFill(v.voxel(uint32_t(x), uint32_t(y), uint32_t(z))) > DS_FILL_FULL;
  };
  uint64_t count = 0;
  for (int64_t z = -1; z < dim; ++z)
    for (int64_t y = -1; y < dim; ++y)
      for (int64_t x = -1; x < dim; ++x) {
        bool c[8];
        for (int k = 0; k < 8; ++k) c[k] = inside(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1));
        bool ambiguous = false;
        for (int axis = 0; axis < 3 && !ambiguous; ++axis)
          for (int side = 0; side < 2 && !ambiguous; ++side) {
            const int u = 1 << ((axis + 1) % 3), w = 1 << ((axis + 2) % 3), base = side << axis;
            // The face's corners in cyclic order: base, +u, +u+w, +w.
            const bool a = c[base], b = c[base | u], d = c[base | u | w], e = c[base | w];
            ambiguous = a == d && b == e && a != b;
          }
        count += ambiguous;
      }
  return count;
}

TEST(MeshBenchTest, SurfacePartSitsOnTopOfTheSolid) {
  // Level 6: the ball's centre column tops out at z = centre + r = 32.31 + 25.6 = 57.9 voxels, so the
  // topmost solid voxel (centre over the 0.5 level) is voxel 57, in brick 7 on z.
  const ToothVolume t = ballTooth(6);
  auto part = surfacePart(t.voxels);
  ASSERT_TRUE(part.ok()) << part.message();
  EXPECT_EQ(part->anchor[2], 57u);
  EXPECT_EQ(part->side_voxels, 2u);  // 64 / 32
  EXPECT_EQ(part->side_bricks, 1u);
  ASSERT_EQ(part->bricks.size(), 1u);
  EXPECT_EQ(part->bricks[0].z, part->anchor[2] / 8);
  EXPECT_EQ(part->bricks[0].x, part->anchor[0] / 8);

  // A coarser divisor gives a cube of 2^3 bricks around the anchor, sorted (z, y, x), in the grid.
  part = surfacePart(t.voxels, 4);
  ASSERT_TRUE(part.ok());
  EXPECT_EQ(part->side_bricks, 2u);
  ASSERT_EQ(part->bricks.size(), 8u);
  for (size_t i = 0; i < 8; ++i) {
    const BrickCoord& c = part->bricks[i];
    EXPECT_LT(c.z, 8u);
    EXPECT_EQ(c.x, part->lo.x + i % 2);
    EXPECT_EQ(c.y, part->lo.y + (i / 2) % 2);
    EXPECT_EQ(c.z, part->lo.z + i / 4);
  }
  for (size_t a = 0; a < 3; ++a) {
    const uint32_t lo = a == 0 ? part->lo.x : a == 1 ? part->lo.y : part->lo.z;
    EXPECT_GE(part->anchor[a], 8 * lo);
    EXPECT_LT(part->anchor[a], 8 * (lo + 2));
  }

  EXPECT_FALSE(surfacePart(BrickVolume(5)).ok());  // no solid, no surface
}

TEST(MeshBenchTest, Figure15RowsRunWarmupRepeatsAndTheParts) {
  CountingRunner counting;
  const MeshRunner runner = counting.runner();
  MeshBenchSettings s = tinySettings();
  s.peers = false;
  auto row = measureMeshLevel(ballTooth(5), s, runner);
  ASSERT_TRUE(row.ok()) << row.message();
  // Per mode: one warm-up and two timed full runs, then one warm-up and two timed part updates.
  EXPECT_EQ(counting.full_calls, 3 * 3);
  EXPECT_EQ(counting.update_calls, 3 * 3);
  for (const auto& dirty : counting.dirty_sets) {
    ASSERT_EQ(dirty.size(), 1u);  // level 5: dim / 32 = 1 voxel, one brick
  }
  EXPECT_EQ(row->level, 5);
  EXPECT_NEAR(row->voxel_mm, 0.4, 1e-12);
  ASSERT_EQ(row->modes.size(), 3u);
  uint64_t triangles = 0;
  for (const ModeTiming& m : row->modes) {
    EXPECT_EQ(m.full_runs_ms.size(), 2u);
    EXPECT_EQ(m.part_runs_ms.size(), 2u);
    EXPECT_GT(m.triangles, 0u);
    if (triangles) {
      EXPECT_EQ(m.triangles, triangles);  // the normal mode changes normals only
    }
    triangles = m.triangles;
    EXPECT_EQ(m.vtk_ratio, 0.0);
  }
  EXPECT_FALSE(row->vtk.available);
  EXPECT_NE(row->vtk.skipped.find("--no-peers"), std::string::npos);
}

TEST(MeshBenchTest, RunnerErrorsPassThrough) {
  MeshRunner failing = cpuReferenceRunner();
  failing.update = [](const ToothVolume&, std::span<const BrickCoord>, int) -> Result<MeshTiming> {
    return Error{"gpu: device lost"};
  };
  auto row = measureMeshLevel(ballTooth(5), tinySettings(), failing);
  ASSERT_FALSE(row.ok());
  EXPECT_EQ(row.message(), "gpu: device lost");
}

TEST(MeshBenchTest, BurPathFollowsTheTopAndCutsInsideTheGrid) {
  const ToothVolume t = ballTooth(6);  // 0.2 mm voxels
  BurPathSettings s;
  s.level = 6;
  s.frames = 4;
  s.normals = 8;
  auto path = burPath(t, s);
  ASSERT_TRUE(path.ok()) << path.message();
  ASSERT_EQ(path->size(), 4u);
  // Ball centre (32.23, 32.17, 32.31) voxels x 0.2 mm = (6.446, 6.434, 6.462) mm, r = 5.12 mm.
  const double cx = 6.446, cy = 6.434, cz = 6.462, r = 5.12;
  for (size_t k = 0; k < 4; ++k) {
    const Vec3d& p = (*path)[k];
    // 5 mm/s at 60 frames/s: 1/12 mm a frame, from the start of the middle 60% of the ball in x.
    EXPECT_NEAR(p[0] - (*path)[0][0], double(k) / 12.0, 1e-9);
    EXPECT_LT(std::abs(p[0] - cx), 0.3 * 2 * r + 0.2);
    EXPECT_NEAR(p[1], cy, 0.2);  // the middle column in y
    // Resting on a sphere, the ball's centre is r + 0.5 mm from the sphere's; then it sinks 0.3 mm.
    // The surface is read per column of 0.2 mm voxels, to a fraction of a voxel.
    const double rest = cz + std::sqrt((r + 0.5) * (r + 0.5) - (p[0] - cx) * (p[0] - cx) - (p[1] - cy) * (p[1] - cy));
    EXPECT_NEAR(p[2], rest - 0.3, 0.06) << "frame " << k;
  }

  CountingRunner counting;
  auto bur = measureBurPath(t, s, counting.runner());
  ASSERT_TRUE(bur.ok()) << bur.message();
  EXPECT_EQ(counting.full_calls, 1);  // the build the updates start from
  ASSERT_EQ(bur->frames.size(), 4u);
  EXPECT_EQ(bur->frames_cut, counting.update_calls);
  EXPECT_GE(bur->frames_cut, 1);
  EXPECT_GT(bur->frames[0].dirty_bricks, 0u);  // the first frame sinks into untouched enamel
  EXPECT_GT(bur->mean_dirty_bricks, 0.0);
  EXPECT_GT(bur->removed_mm3, 0.0);
  for (const auto& dirty : counting.dirty_sets) {
    EXPECT_FALSE(dirty.empty());
    for (const BrickCoord& c : dirty) {
      EXPECT_LT(c.x, t.voxels.brickDim());
      EXPECT_LT(c.y, t.voxels.brickDim());
      EXPECT_LT(c.z, t.voxels.brickDim());
    }
  }
  EXPECT_LE(bur->p50_ms, bur->p95_ms);
  EXPECT_LE(bur->p95_ms, bur->max_ms);
  // The carving went to a copy: the caller's tooth still has its material.
  EXPECT_EQ(t.voxels, ballTooth(6).voxels);
}

TEST(MeshBenchTest, NormalErrorsFallWithWiderNeighbourhoods) {
  // The paper's claim, 216 < 64 < 8 neighbours, on the mean error, for the sphere at level 6 (r 25.6
  // voxels) and the torus at level 7 (R 38.4, r 14.1). At level 6 the torus' tube is 7 voxels thick
  // in radius and the 6^3 window averages across its curvature, so there 216 loses to 64 (1.6 against
  // 1.2 degrees); the benchmark's table shows that row, the claim is about resolved surfaces.
  const std::vector<std::pair<AnalyticSolid, int>> cases{{sphereForLevel(6), 6}, {torusForLevel(7), 7}};
  for (const auto& [solid, level] : cases) {
    const ToothVolume t = analyticTooth(solid, level, Material::Enamel, 4);
    NormalErrorRow r[3];
    const int modes[3] = {8, 64, 216};
    for (int k = 0; k < 3; ++k) {
      auto row = measureNormalError(t, solid, modes[k]);
      ASSERT_TRUE(row.ok()) << row.message();
      r[k] = *row;
      EXPECT_EQ(r[k].normals, modes[k]);
      EXPECT_EQ(r[k].level, level);
      EXPECT_LE(r[k].mean_deg, r[k].p95_deg);
      EXPECT_LE(r[k].p95_deg, r[k].max_deg);
    }
    std::printf("%s level %d: mean / p95 normal error 8: %.3f / %.3f deg, 64: %.3f / %.3f deg, 216: %.3f / %.3f deg\n",
                r[0].solid.c_str(), level, r[0].mean_deg, r[0].p95_deg, r[1].mean_deg, r[1].p95_deg, r[2].mean_deg,
                r[2].p95_deg);
    EXPECT_EQ(r[0].vertices, r[2].vertices);  // the mode changes the normals only
    EXPECT_LT(r[1].mean_deg, r[0].mean_deg) << r[0].solid;
    EXPECT_LT(r[2].mean_deg, r[1].mean_deg) << r[0].solid;
  }
}

TEST(MeshBenchTest, NormalTableHasEverySolidLevelAndMode) {
  NormalsSettings s;
  s.levels = {5, 6};
  s.samples = 2;
  auto rows = measureNormalErrors(s);
  ASSERT_TRUE(rows.ok()) << rows.message();
  ASSERT_EQ(rows->size(), 2u * 2u * 3u);  // sphere then torus, level 5 then 6, modes 8, 64, 216
  EXPECT_EQ((*rows)[0].solid, "sphere r 12.8");
  EXPECT_EQ((*rows)[3].level, 6);
  EXPECT_EQ((*rows)[5].normals, 216);
  EXPECT_EQ((*rows)[6].solid, "torus R 9.6 r 3.5");
  for (const NormalErrorRow& r : *rows) EXPECT_GT(r.vertices, 0u);
}

TEST(MeshBenchTest, VtkFlyingEdgesMatchesTheCpuMesher) {
  // Both are marching cubes on the same crossings of phi = 0.5 (15.5 on the 0..31 fill; no sample
  // equals it), and both make exactly one vertex per crossed lattice edge: the vertex counts agree
  // exactly (the solids keep clear of the grid border, where only dentsim sees the empty outside).
  // A cell's triangle count is (its crossed edges) - 2 x (its loops), so the tables can only differ
  // where they join the crossings into different loops, i.e. in cells with an ambiguous face, by at
  // most 2 x 3 triangles each (1 to 4 loops in a cube).
  for (const AnalyticSolid& solid : {sphereForLevel(6), torusForLevel(6)}) {
    const ToothVolume t = analyticTooth(solid, 6, Material::Dentin, 4);
    const PeerMesh vtk = vtkFlyingEdges(t.voxels, Material::Empty, 2);
#ifndef DENTSIM_HAVE_VTK
    EXPECT_FALSE(vtk.available);
    EXPECT_FALSE(vtk.skipped.empty());
    GTEST_SKIP() << vtk.skipped;
#endif
    ASSERT_TRUE(vtk.available) << vtk.skipped;
    auto cpu = meshVolumeCpu(t, SurfaceOptions{});
    ASSERT_TRUE(cpu.ok());
    const uint64_t ambiguous = ambiguousCells(t.voxels);
    const auto diff = int64_t(vtk.triangles) - int64_t(cpu->triangleCount());
    std::printf("%s level 6: dentsim %zu triangles %zu vertices, %s %llu triangles %llu points, %llu ambiguous cells\n",
                solid.describe().c_str(), cpu->triangleCount(), cpu->positions.size(), vtk.name.c_str(),
                static_cast<unsigned long long>(vtk.triangles), static_cast<unsigned long long>(vtk.points),
                static_cast<unsigned long long>(ambiguous));
    EXPECT_EQ(vtk.points, cpu->positions.size()) << solid.describe();
    EXPECT_LE(std::abs(diff), int64_t(6 * ambiguous)) << solid.describe();
    EXPECT_LT(std::abs(double(diff)), 0.02 * double(cpu->triangleCount())) << solid.describe();
    EXPECT_EQ(vtk.runs_ms.size(), 2u);
    EXPECT_EQ(vtk.image_bytes, 64u * 64u * 64u);
    EXPECT_GE(vtk.threads, 1);
  }
}

TEST(MeshBenchTest, VtkFlyingEdgesOnRandomVoxelsStaysWithinTheAmbiguityBound) {
  // Random fills in a 10^3 block make ambiguous faces by the hundred, where the two tables may differ.
  std::mt19937 rng(11);
  ToothVolume t{VolumeFrame::axisAligned(4, 1.0, {0, 0, 0}), BrickVolume(4)};
  for (uint32_t z = 3; z < 13; ++z)
    for (uint32_t y = 3; y < 13; ++y)
      for (uint32_t x = 3; x < 13; ++x)
        if (const uint32_t fill = rng() % 32) t.voxels.setVoxel(x, y, z, makeVoxel(Material::Dentin, fill));
  const PeerMesh vtk = vtkFlyingEdges(t.voxels);
  if (!vtk.available) GTEST_SKIP() << vtk.skipped;
  auto cpu = meshVolumeCpu(t, SurfaceOptions{});
  ASSERT_TRUE(cpu.ok());
  const uint64_t ambiguous = ambiguousCells(t.voxels);
  const auto diff = int64_t(vtk.triangles) - int64_t(cpu->triangleCount());
  std::printf("random block: dentsim %zu triangles, VTK %llu, %llu ambiguous cells\n", cpu->triangleCount(),
              static_cast<unsigned long long>(vtk.triangles), static_cast<unsigned long long>(ambiguous));
  EXPECT_GT(ambiguous, 50u);
  EXPECT_EQ(vtk.points, cpu->positions.size());
  EXPECT_LE(std::abs(diff), int64_t(6 * ambiguous));
}

TEST(MeshBenchTest, VtkSeesOnlyTheChosenTissue) {
  // A dentin ball with no enamel: the enamel surface is empty, the dentin one is the whole ball.
  const ToothVolume t = analyticTooth(sphereForLevel(5), 5, Material::Dentin, 4);
  const PeerMesh enamel = vtkFlyingEdges(t.voxels, Material::Enamel);
  if (!enamel.available) GTEST_SKIP() << enamel.skipped;
  EXPECT_EQ(enamel.triangles, 0u);
  EXPECT_EQ(vtkFlyingEdges(t.voxels, Material::Dentin).triangles, vtkFlyingEdges(t.voxels).triangles);
  EXPECT_GT(vtkFlyingEdges(t.voxels, Material::Dentin).triangles, 0u);
}

TEST(MeshBenchTest, WholeRunWritesJsonMarkdownAndSvg) {
  CountingRunner counting;
  MeshReportInfo info;
  info.settings = tinySettings();
  info.model = "enamel ball";
  info.runner = "CPU reference";
  info.device = "none";
  std::vector<std::string> log;
  auto report = runMeshBench(info.settings, ballTooth, counting.runner(),
                             [&](const std::string& line) { log.push_back(line); });
  ASSERT_TRUE(report.ok()) << report.message();
  ASSERT_EQ(report->levels.size(), 2u);
  EXPECT_TRUE(report->has_bur);
  EXPECT_EQ(report->bur.frames.size(), 4u);
  EXPECT_EQ(report->normals.size(), 6u);
  EXPECT_EQ(log.size(), 2u + 1u + 6u);  // two levels, the bur path, six normal rows

  test::TempDir dir;
  const Status written = writeMeshReport(dir.path().string(), info, *report);
  ASSERT_TRUE(written.ok()) << written.message();
  auto slurp = [&](const std::string& name) {
    std::ifstream in(dir.file(name));
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  const nlohmann::json j = nlohmann::json::parse(slurp("mesh.json"));
  EXPECT_EQ(j["benchmark"], "mesh");
  ASSERT_EQ(j["figure15"].size(), 2u);
  EXPECT_EQ(j["figure15"][1]["level"], 6);
  EXPECT_EQ(j["figure15"][1]["modes"].size(), 3u);
  EXPECT_EQ(j["figure15"][1]["modes"][2]["normals"], 216);
  EXPECT_EQ(j["figure15"][1]["modes"][2]["full"]["runs_ms"].size(), 2u);
  EXPECT_TRUE(j["figure15"][0]["vtk"].contains("available"));
  EXPECT_EQ(j["bur_path"]["per_frame"].size(), 4u);
  EXPECT_EQ(j["bur_path"]["level"], 6);
  EXPECT_TRUE(j["goals"]["bur_p95_met"].is_boolean());
  EXPECT_TRUE(j["goals"]["level10_full_faster_than_vtk"].is_null());  // level 10 not measured
  EXPECT_EQ(j["normal_errors"].size(), 6u);

  const std::string md = slurp("mesh.md");
  EXPECT_NE(md.find("| level | voxel [mm] | normals | full [ms]"), std::string::npos) << md;
  EXPECT_NE(md.find("| 6 | 0.2000 | 216 |"), std::string::npos) << md;
  EXPECT_NE(md.find("One frame of drilling"), std::string::npos) << md;
  EXPECT_NE(md.find("| sphere r 25.6 | 6 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| yes |"), std::string::npos) << md;  // the normal rows are ordered

  const std::string svg = slurp("mesh.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("full, 216 normals"), std::string::npos);
  EXPECT_NE(svg.find("part, 8 normals"), std::string::npos);
  if (report->levels[0].vtk.available) {
    EXPECT_NE(svg.find("VTK Flying Edges"), std::string::npos);
  }
  EXPECT_NE(slurp("mesh_bur.svg").find("target p95"), std::string::npos);
}

}  // namespace
}  // namespace dentsim::bench
