// GPU marching cubes against the CPU reference on lavapipe; incremental re-meshing against full builds; slot pages; the CPU mesher against the kernel.
#include "gpu/gpu_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <random>

#include "gpu_fixture.h"
#include "test_volumes.h"
#include "io/mesh_topology.h"
#include "volume/surface_mesher.h"
#include "volume/volume_edit.h"

namespace dentsim::gpu::test {
namespace {

using dentsim::test::NoiseMaterials;
using dentsim::test::randomVolume;

// A ball of `material` with fill from the distance to its sphere (a one-voxel ramp).
void addBall(BrickVolume& vol, double cx, double cy, double cz, double r, Material material) {
  const uint32_t dim = vol.dim();
  for (uint32_t z = 0; z < dim; ++z)
    for (uint32_t y = 0; y < dim; ++y)
      for (uint32_t x = 0; x < dim; ++x) {
        const double d = std::sqrt((x + 0.5 - cx) * (x + 0.5 - cx) + (y + 0.5 - cy) * (y + 0.5 - cy) +
                                   (z + 0.5 - cz) * (z + 0.5 - cz)) - r;
        const int fill = int(std::lround(std::clamp(0.5 - d, 0.0, 1.0) * 31.0));
        if (fill > 0) vol.setVoxel(x, y, z, makeVoxel(material, uint32_t(fill)));
      }
}

// A fresh surface's blocks after a build; the kernel's unless the options name the CPU mesher.
Result<std::vector<BlockMesh>> gpuBlocks(Context& ctx, const BrickVolume& vol, GpuSurfaceOptions options,
                                         SurfaceUpdateStats* stats = nullptr) {
  if (options.mesher == MesherKind::Auto) options.mesher = MesherKind::Gpu;
  auto surface = GpuSurface::create(ctx, options);
  if (!surface) return surface.error();
  if (auto s = surface->build(vol, stats); !s) return s.error();
  return surface->downloadBlocks();
}

std::vector<BlockMesh> cpuBlocks(const BrickVolume& vol, Material tissue, int normals) {
  std::vector<BlockMesh> out;
  for (const MeshBlock& b : activeMeshBlocks(vol, tissue)) {
    BlockMesh m = meshBlockCpu(vol, b, tissue, normalBoxSide(*normalModeFromNeighbours(normals)));
    if (!m.indices.empty()) out.push_back(std::move(m));
  }
  return out;
}

double angleDeg(Vec3f a, Vec3f b) {
  const double d = double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2];
  return std::acos(std::clamp(d, -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// The GPU normalizes in float and the CPU in double, so a packed coordinate may round one 12-bit step
// apart: (2 / 4095) of the octahedron's side, which its stretch near the folds makes up to about
// 0.12 deg for each of the two coordinates.
constexpr double kNormalStepDeg = 0.25;

// Same blocks, same vertex order and triangles; positions to the rounding of one division, normals
// to their 12-bit packing, tissue bits exactly.
::testing::AssertionResult sameAsCpu(const std::vector<BlockMesh>& gpu, const std::vector<BlockMesh>& cpu) {
  if (gpu.size() != cpu.size())
    return ::testing::AssertionFailure() << "GPU " << gpu.size() << " blocks, CPU " << cpu.size();
  for (size_t b = 0; b < gpu.size(); ++b) {
    const BlockMesh &g = gpu[b], &c = cpu[b];
    if (!(g.block == c.block)) return ::testing::AssertionFailure() << "block " << b << " differs";
    if (g.vertices.size() != c.vertices.size() || g.indices != c.indices)
      return ::testing::AssertionFailure() << "block (" << c.block.x << "," << c.block.y << "," << c.block.z
                                           << "): GPU " << g.vertices.size() << " vertices, CPU " << c.vertices.size()
                                           << "; indices " << (g.indices == c.indices ? "equal" : "differ");
    for (size_t i = 0; i < g.vertices.size(); ++i) {
      const auto &gv = g.vertices[i], &cv = c.vertices[i];
      const double dp = std::max({std::fabs(gv.x - cv.x), std::fabs(gv.y - cv.y), std::fabs(gv.z - cv.z)});
      const double dn = angleDeg(unpackMeshNormal(gv.packed), unpackMeshNormal(cv.packed));
      if (dp > 1e-4 || dn > kNormalStepDeg || (gv.packed >> 24) != (cv.packed >> 24))
        return ::testing::AssertionFailure() << "block (" << c.block.x << "," << c.block.y << "," << c.block.z
                                             << ") vertex " << i << ": position off by " << dp << " voxel, normal by "
                                             << dn << " deg, tissue bits GPU " << (gv.packed >> 24) << " CPU "
                                             << (cv.packed >> 24);
    }
  }
  return ::testing::AssertionSuccess();
}

// Bit-for-bit equality of two GPU results (incremental against full).
::testing::AssertionResult identical(const std::vector<BlockMesh>& a, const std::vector<BlockMesh>& b) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << a.size() << " blocks against " << b.size();
  for (size_t i = 0; i < a.size(); ++i) {
    if (!(a[i].block == b[i].block) || a[i].indices != b[i].indices || a[i].vertices.size() != b[i].vertices.size() ||
        std::memcmp(a[i].vertices.data(), b[i].vertices.data(), a[i].vertices.size() * sizeof(layout::MeshVertex)) != 0)
      return ::testing::AssertionFailure() << "block (" << a[i].block.x << "," << a[i].block.y << "," << a[i].block.z
                                           << ") differs";
  }
  return ::testing::AssertionSuccess();
}

// The draw records name exactly the live blocks, each with its triangles' index count.
::testing::AssertionResult drawsMatch(GpuSurface& surface, const std::vector<BlockMesh>& blocks) {
  std::map<uint32_t, uint32_t> expected;  // packed block -> index count
  for (const BlockMesh& b : blocks) expected[b.block.packed()] = uint32_t(b.indices.size());
  std::map<uint32_t, uint32_t> seen;
  for (uint32_t p = 0; p < surface.pageCount(); ++p) {
    const auto* draws = static_cast<const SurfaceDraw*>(surface.draws(p).mapped());
    for (uint32_t i = 0; i < surface.drawCount(p); ++i) {
      if (draws[i].index_count == 0) continue;
      if (draws[i].instance_count != 1) return ::testing::AssertionFailure() << "record " << i << " has no instance";
      seen[draws[i].first_instance] = draws[i].index_count;
    }
  }
  if (seen != expected)
    return ::testing::AssertionFailure() << "the live draw records (" << seen.size() << ") do not name the live blocks ("
                                         << expected.size() << ") with their index counts";
  return ::testing::AssertionSuccess();
}

class GpuSurfaceTest : public GpuTest {};

TEST_F(GpuSurfaceTest, MatchesTheCpuReferenceOnRandomVolumes) {
  for (uint32_t seed : {1u, 2u}) {
    const BrickVolume vol = randomVolume(5, seed, NoiseMaterials::Tissues);
    for (int normals : {8, 64, 216})
      for (Material tissue : {Material::Empty, Material::Dentin}) {
        SCOPED_TRACE("seed " + std::to_string(seed) + ", " + std::to_string(normals) + " normals, tissue " +
                     materialName(tissue));
        auto gpu = gpuBlocks(ctx(), vol, {.normal_neighbours = normals, .tissue = tissue});
        ASSERT_TRUE(gpu.ok()) << gpu.message();
        const auto cpu = cpuBlocks(vol, tissue, normals);
        EXPECT_GT(cpu.size(), 20u);
        EXPECT_TRUE(sameAsCpu(*gpu, cpu));
      }
  }
}

TEST_F(GpuSurfaceTest, SplitDispatchesSmallPoolsAndManyPagesGiveTheSameSurface) {
  const BrickVolume vol = randomVolume(5, 3, NoiseMaterials::Tissues);
  auto reference = gpuBlocks(ctx(), vol, {.normal_neighbours = 64});
  ASSERT_TRUE(reference.ok()) << reference.message();
  SurfaceUpdateStats stats;
  auto tight = gpuBlocks(ctx(), vol,
                         {.normal_neighbours = 64, .initial_pool_bytes = 4096, .max_groups_per_dispatch = 7,
                          .max_page_bytes = 64 << 10},
                         &stats);
  ASSERT_TRUE(tight.ok()) << tight.message();
  EXPECT_TRUE(stats.pool_grew);
  EXPECT_GT(stats.pool_bytes, uint64_t{64} << 10) << "the surface should need several 64 KiB pages";
  EXPECT_TRUE(identical(*tight, *reference));
}

TEST_F(GpuSurfaceTest, ClosedSolidIsWatertightWithTheSphereAreaAndVolume) {
  BrickVolume vol(6);
  const double r = 21.3, c = 32.2;
  addBall(vol, c, c - 0.4, c + 0.3, r, Material::Enamel);
  auto blocks = gpuBlocks(ctx(), vol, {.normal_neighbours = 216});
  ASSERT_TRUE(blocks.ok()) << blocks.message();
  const VolumeFrame frame = VolumeFrame::axisAligned(6, 1.0, {0, 0, 0});
  const SurfaceMesh mesh = weldBlockMeshes(*blocks, frame);
  const MeshTopology t = analyzeTopology(mesh.geometry());
  EXPECT_EQ(t.open_edges, 0u);
  EXPECT_EQ(t.nonmanifold_edges, 0u);
  EXPECT_EQ(t.flipped_edges, 0u);
  EXPECT_EQ(int64_t(mesh.positions.size()) - int64_t(mesh.triangles.size()) / 2, 2) << "one sphere-like shell";
  const double volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  EXPECT_NEAR(t.signed_volume_mm3, volume, 0.01 * volume);
  // Marching cubes over-estimates a smooth surface's area by a few percent (facets cut across the
  // lattice); the CPU reference tests bound this the same way.
  double area = 0;
  for (const auto& tri : mesh.triangles) {
    const Vec3f &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &d = mesh.positions[tri[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    area += 0.5 * std::hypot(u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]);
  }
  const double sphere_area = 4.0 * std::numbers::pi * r * r;
  EXPECT_GT(area, 0.99 * sphere_area);
  EXPECT_LT(area, 1.08 * sphere_area);
  // Normals point out of the ball.
  size_t outward = 0;
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3f& p = mesh.positions[i];
    const double d[3] = {p[0] - c, p[1] - (c - 0.4), p[2] - (c + 0.3)};
    outward += d[0] * mesh.normals[i][0] + d[1] * mesh.normals[i][1] + d[2] * mesh.normals[i][2] > 0;
  }
  EXPECT_EQ(outward, mesh.positions.size());
}

TEST_F(GpuSurfaceTest, IncrementalUpdatesEqualFullBuildsAfterRandomEdits) {
  const VolumeFrame frame = VolumeFrame::axisAligned(6, 0.05, {0, 0, 0});
  BrickVolume vol(6);
  addBall(vol, 30.5, 33.1, 31.7, 24.0, Material::Enamel);
  addBall(vol, 30.5, 33.1, 31.7, 14.0, Material::Dentin);
  auto surface =
      GpuSurface::create(ctx(), {.normal_neighbours = 216, .initial_pool_bytes = 16 << 10, .mesher = MesherKind::Gpu});
  ASSERT_TRUE(surface.ok()) << surface.message();
  ASSERT_TRUE(surface->build(vol).ok());
  std::mt19937 rng(5);
  uint64_t first_pool = 0, last_pool = 0;
  for (int edit = 0; edit < 12; ++edit) {
    // Balls on and around the surface, 1 to 6 voxels in radius, some cutting deep, some missing.
    const double theta = double(rng() % 1000) / 1000.0 * std::numbers::pi;
    const double phi = double(rng() % 1000) / 1000.0 * 2.0 * std::numbers::pi;
    const double rr = 16.0 + double(rng() % 120) / 10.0;
    const std::array<double, 3> centre{(30.5 + rr * std::sin(theta) * std::cos(phi)) * frame.voxel_mm,
                                       (33.1 + rr * std::sin(theta) * std::sin(phi)) * frame.voxel_mm,
                                       (31.7 + rr * std::cos(theta)) * frame.voxel_mm};
    const double radius = (1.0 + double(rng() % 50) / 10.0) * frame.voxel_mm;
    const EditResult e = carveBall(vol, frame, centre, radius);
    SurfaceUpdateStats stats;
    ASSERT_TRUE(surface->update(vol, e.dirty, &stats).ok());
    auto incremental = surface->downloadBlocks();
    ASSERT_TRUE(incremental.ok()) << incremental.message();
    auto full = gpuBlocks(ctx(), vol, {.normal_neighbours = 216});
    ASSERT_TRUE(full.ok()) << full.message();
    EXPECT_TRUE(identical(*incremental, *full)) << "after edit " << edit << " (" << e.dirty.size() << " dirty bricks)";
    EXPECT_TRUE(drawsMatch(*surface, *incremental)) << "after edit " << edit;
    if (!e.dirty.empty()) {
      EXPECT_GT(stats.blocks_meshed, 0u);
    }
    if (edit == 0) first_pool = stats.pool_bytes;
    last_pool = stats.pool_bytes;
    EXPECT_LE(stats.used_bytes, stats.slot_bytes);
    EXPECT_LE(stats.slot_bytes, stats.pool_bytes);
  }
  // Slots are reused and reclaimed: twelve edits of a surface that hardly changes in size do not
  // keep growing the pool.
  EXPECT_LE(last_pool, 2 * first_pool);
}

TEST_F(GpuSurfaceTest, RemovingTheSolidFreesEverySlot) {
  for (MesherKind mesher : {MesherKind::Gpu, MesherKind::Cpu}) {
    SCOPED_TRACE(mesherKindName(mesher) + " mesher");
    BrickVolume vol(5);
    addBall(vol, 16, 16, 16, 6, Material::Dentin);
    auto surface = GpuSurface::create(ctx(), {.normal_neighbours = 8, .mesher = mesher});
    ASSERT_TRUE(surface.ok());
    ASSERT_TRUE(surface->build(vol).ok());
    EXPECT_GT(surface->liveBlocks(), 0u);
    std::vector<BrickCoord> all;
    for (uint32_t z = 0; z < 4; ++z)
      for (uint32_t y = 0; y < 4; ++y)
        for (uint32_t x = 0; x < 4; ++x) {
          vol.setBrickUniform({x, y, z}, 0);
          all.push_back({x, y, z});
        }
    SurfaceUpdateStats stats;
    ASSERT_TRUE(surface->update(vol, all, &stats).ok());
    EXPECT_EQ(surface->liveBlocks(), 0u);
    EXPECT_EQ(stats.triangles, 0u);
    EXPECT_EQ(stats.slot_bytes, 0u);
    for (uint32_t p = 0; p < surface->pageCount(); ++p) {
      ASSERT_GE(surface->draws(p).size(), surface->drawCount(p) * sizeof(SurfaceDraw));
      const auto* draws = static_cast<const SurfaceDraw*>(surface->draws(p).mapped());
      for (uint32_t i = 0; i < surface->drawCount(p); ++i) EXPECT_EQ(draws[i].index_count, 0u);
    }
  }
}

TEST_F(GpuSurfaceTest, RefusesBadModesAndUpdatesBeforeABuild) {
  auto bad = GpuSurface::create(ctx(), {.normal_neighbours = 27});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("27"), std::string::npos);
  auto surface = GpuSurface::create(ctx(), {});
  ASSERT_TRUE(surface.ok());
  BrickVolume vol(4);
  const BrickCoord c{0, 0, 0};
  const Status s = surface->update(vol, std::span<const BrickCoord>(&c, 1));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("before build"), std::string::npos);
}


// ---- the CPU mesher ---------------------------------------------------------------------------------

TEST(MesherKind, ParsesPrintsAndResolvesAutoByDeviceType) {
  for (MesherKind k : kMesherKinds) EXPECT_EQ(parseMesherKind(mesherKindName(k)), k);
  EXPECT_FALSE(parseMesherKind("GPU").has_value());
  EXPECT_FALSE(parseMesherKind("").has_value());
  EXPECT_EQ(resolveMesher(MesherKind::Auto, VK_PHYSICAL_DEVICE_TYPE_CPU), MesherKind::Cpu);
  for (VkPhysicalDeviceType t : {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU,
                                 VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU, VK_PHYSICAL_DEVICE_TYPE_OTHER})
    EXPECT_EQ(resolveMesher(MesherKind::Auto, t), MesherKind::Gpu);
  // An explicit choice stands on any device.
  EXPECT_EQ(resolveMesher(MesherKind::Gpu, VK_PHYSICAL_DEVICE_TYPE_CPU), MesherKind::Gpu);
  EXPECT_EQ(resolveMesher(MesherKind::Cpu, VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU), MesherKind::Cpu);
}

TEST_F(GpuSurfaceTest, AutoPicksTheCpuMesherOnACpuDevice) {
  auto surface = GpuSurface::create(ctx(), {});
  ASSERT_TRUE(surface.ok()) << surface.message();
  const bool cpu_device = ctx().device().type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  EXPECT_EQ(surface->mesher(), cpu_device ? MesherKind::Cpu : MesherKind::Gpu) << ctx().device().name;
  auto gpu = GpuSurface::create(ctx(), {.mesher = MesherKind::Gpu});
  ASSERT_TRUE(gpu.ok());
  EXPECT_EQ(gpu->mesher(), MesherKind::Gpu);
}

TEST_F(GpuSurfaceTest, CpuMesherEqualsTheReferenceBitForBitAndTheKernelToItsRounding) {
  const BrickVolume vol = randomVolume(5, 4, NoiseMaterials::Tissues);
  for (int normals : {8, 64, 216})
    for (Material tissue : {Material::Empty, Material::Enamel, Material::Dentin}) {
      SCOPED_TRACE(std::to_string(normals) + " normals, tissue " + materialName(tissue));
      SurfaceUpdateStats stats;
      auto cpu_mesher = gpuBlocks(ctx(), vol, {.normal_neighbours = normals, .tissue = tissue, .mesher = MesherKind::Cpu},
                                  &stats);
      ASSERT_TRUE(cpu_mesher.ok()) << cpu_mesher.message();
      EXPECT_FALSE(stats.timestamps);
      EXPECT_EQ(stats.upload_ms, 0.0) << "the CPU mesher uploads nothing";
      auto kernel = gpuBlocks(ctx(), vol, {.normal_neighbours = normals, .tissue = tissue, .mesher = MesherKind::Gpu});
      ASSERT_TRUE(kernel.ok()) << kernel.message();
      const auto reference = cpuBlocks(vol, tissue, normals);
      EXPECT_GT(reference.size(), 20u);
      EXPECT_TRUE(identical(*cpu_mesher, reference));
      EXPECT_TRUE(sameAsCpu(*kernel, *cpu_mesher));
    }
}

// Both meshers through a build and a series of cuts, with pages small enough that the surface grows
// its first page and opens several: after each update the CPU mesher's slots hold the kernel's
// surface, and its draw records name its live blocks.
TEST_F(GpuSurfaceTest, CpuMesherUpdatesEqualTheKernelsAcrossPageGrowthAndManyPages) {
  const VolumeFrame frame = VolumeFrame::axisAligned(6, 0.05, {0, 0, 0});
  BrickVolume vol(6);
  addBall(vol, 30.5, 33.1, 31.7, 24.0, Material::Enamel);
  addBall(vol, 30.5, 33.1, 31.7, 14.0, Material::Dentin);
  GpuSurfaceOptions options{.normal_neighbours = 216, .initial_pool_bytes = 4096, .max_page_bytes = 64 << 10};
  options.mesher = MesherKind::Gpu;
  auto kernel = GpuSurface::create(ctx(), options);
  options.mesher = MesherKind::Cpu;
  options.cpu_threads = 3;  // more threads than this machine may have cores: pieces interleave
  auto cpu = GpuSurface::create(ctx(), options);
  ASSERT_TRUE(kernel.ok() && cpu.ok());
  ASSERT_EQ(cpu->mesher(), MesherKind::Cpu);
  SurfaceUpdateStats built;
  ASSERT_TRUE(kernel->build(vol).ok());
  ASSERT_TRUE(cpu->build(vol, &built).ok());
  EXPECT_TRUE(built.pool_grew);
  EXPECT_GT(cpu->pageCount(), 2u) << "the surface should need several 64 KiB pages";
  EXPECT_FALSE(cpu->downloadVolume().ok()) << "the CPU mesher keeps no device copy of the voxels";

  std::mt19937 rng(9);
  for (int edit = 0; edit < 10; ++edit) {
    const double theta = double(rng() % 1000) / 1000.0 * std::numbers::pi;
    const double phi = double(rng() % 1000) / 1000.0 * 2.0 * std::numbers::pi;
    const double rr = 18.0 + double(rng() % 80) / 10.0;
    const std::array<double, 3> centre{(30.5 + rr * std::sin(theta) * std::cos(phi)) * frame.voxel_mm,
                                       (33.1 + rr * std::sin(theta) * std::sin(phi)) * frame.voxel_mm,
                                       (31.7 + rr * std::cos(theta)) * frame.voxel_mm};
    // Big balls now and then, so blocks outgrow their slots and pages fill.
    const double radius = (edit % 3 == 2 ? 9.0 : 1.0 + double(rng() % 50) / 10.0) * frame.voxel_mm;
    const EditResult e = carveBall(vol, frame, centre, radius);
    SurfaceUpdateStats ks, cs;
    ASSERT_TRUE(kernel->update(vol, e.dirty, &ks).ok());
    ASSERT_TRUE(cpu->update(vol, e.dirty, &cs).ok());
    EXPECT_EQ(cs.triangles, ks.triangles) << "after edit " << edit;
    EXPECT_EQ(cs.blocks_meshed, ks.blocks_meshed) << "after edit " << edit;
    auto from_kernel = kernel->downloadBlocks();
    auto from_cpu = cpu->downloadBlocks();
    ASSERT_TRUE(from_kernel.ok() && from_cpu.ok());
    EXPECT_TRUE(sameAsCpu(*from_kernel, *from_cpu)) << "after edit " << edit;
    EXPECT_TRUE(identical(*from_cpu, cpuBlocks(vol, Material::Empty, 216))) << "after edit " << edit;
    EXPECT_TRUE(drawsMatch(*cpu, *from_cpu)) << "after edit " << edit;
  }
}

}  // namespace
}  // namespace dentsim::gpu::test
