// Tests of `dentsim mesh`: voxelized solids come back as closed STL and PLY meshes of the right volume, with normals and colours; bad input fails in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "io/mesh_topology.h"
#include "io/ply_file.h"
#include "io/stl_file.h"
#include "test_meshes.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::runDentsim;
using test::TempDir;
using test::writeBytes;


// The palette cmd_mesh.cpp documents, for the tissues these tests build.
constexpr Rgb8 kEnamel{240, 238, 228};
constexpr Rgb8 kDentin{222, 196, 128};
constexpr Rgb8 kPulp{200, 40, 50};

// Small teeth built once for the whole suite with the CPU voxelizer (a 32^3 or 64^3 grid, well under
// a second each): a 10 mm dentin cube, a 5 mm radius dentin sphere, and a 10 mm enamel cube around
// a 2.5 mm radius pulp sphere.
class MeshCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    writeBytes(dir_->file("cube.stl"), encodeStlBinary(test::box({0, 0, 0}, {10, 10, 10}), "cube"));
    writeBytes(dir_->file("sphere.stl"), encodeStlBinary(test::uvSphere({0, 0, 0}, 5.0), "sphere"));
    writeBytes(dir_->file("pulp.stl"), encodeStlBinary(test::uvSphere({5, 5, 5}, 2.5), "pulp"));
    voxelize("--tooth " + dir_->file("cube.stl") + " --tooth-material dentin --level 5", "cube.dvol");
    voxelize("--tooth " + dir_->file("sphere.stl") + " --tooth-material dentin --level 5", "sphere.dvol");
    voxelize("--enamel " + dir_->file("cube.stl") + " --pulp " + dir_->file("pulp.stl") + " --level 6", "layered.dvol");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static void voxelize(const std::string& args, const std::string& out) {
    const auto r = runDentsim("voxelize " + args + " --cpu -o " + dir_->file(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static std::string file(const std::string& name) { return dir_->file(name); }

  // `dentsim mesh` runs on the GPU where there is one; the driver's own allocations are not ours.
  const test::NoLeakCheckForGpuChild no_leak_check_;

  static TempDir* dir_;
};
TempDir* MeshCli::dir_ = nullptr;

double mag(const Vec3f& v) { return std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]); }

// A closed, outward mesh; its volume against the solid's [mm^3].
void expectClosedWithVolume(const TriangleMesh& mesh, double solid_mm3, double tolerance) {
  const MeshTopology topo = analyzeTopology(mesh);
  EXPECT_TRUE(topo.closed()) << topo.open_edges << " open, " << topo.nonmanifold_edges << " non-manifold edges";
  EXPECT_TRUE(topo.consistent()) << topo.flipped_edges << " flipped edges";
  EXPECT_NEAR(mesh.signedVolume() / solid_mm3, 1.0, tolerance);
}

TEST_F(MeshCli, SphereToPlyHasOutwardNormalsAndDentinColour) {
  const std::string out = file("sphere.ply");
  const auto r = runDentsim("mesh " + file("sphere.dvol") + " -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("triangles"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("vertices"), std::string::npos) << r.output;
  Result<PlyMesh> ply = readPly(out);
  ASSERT_TRUE(ply.ok()) << ply.message();
  EXPECT_EQ(ply->info.format, PlyFormat::BinaryLittleEndian);
  ASSERT_GT(ply->mesh.triangleCount(), 100u);
  expectClosedWithVolume(ply->mesh, test::sphereVolume(5.0), 0.03);
  // The counts printed are the file's.
  EXPECT_NE(r.output.find(std::to_string(ply->mesh.triangleCount()) + " triangles"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(std::to_string(ply->mesh.vertexCount()) + " vertices"), std::string::npos) << r.output;

  ASSERT_TRUE(ply->normals.has_value());
  ASSERT_TRUE(ply->colours.has_value());
  size_t outward = 0;
  for (size_t v = 0; v < ply->mesh.vertexCount(); ++v) {
    const Vec3f& n = (*ply->normals)[v];
    const Vec3f& p = ply->mesh.positions[v];
    EXPECT_NEAR(mag(n), 1.0, 1e-3) << "vertex " << v;
    // The sphere is centred at the origin: the radius direction is the true normal.
    const double cosine = (double(n[0]) * p[0] + double(n[1]) * p[1] + double(n[2]) * p[2]) / (mag(n) * mag(p));
    outward += cosine > 0.9 ? 1 : 0;
    EXPECT_EQ((*ply->colours)[v], kDentin) << "vertex " << v;
  }
  EXPECT_EQ(outward, ply->mesh.vertexCount());
}

TEST_F(MeshCli, CubeToStlAndPlyAgree) {
  const auto stl_run = runDentsim("mesh " + file("cube.dvol") + " --normals 64 -o " + file("cube_mesh.stl"));
  ASSERT_EQ(stl_run.exit_code, 0) << stl_run.output;
  const auto ply_run = runDentsim("mesh " + file("cube.dvol") + " --normals 216 --tissue dentin -o " + file("cube.PLY"));
  ASSERT_EQ(ply_run.exit_code, 0) << ply_run.output;

  Result<StlMesh> stl = readStl(file("cube_mesh.stl"));
  ASSERT_TRUE(stl.ok()) << stl.message();
  Result<PlyMesh> ply = readPly(file("cube.PLY"));
  ASSERT_TRUE(ply.ok()) << ply.message();
  // The normal mode changes normals only; the STL welds the same corners back together.
  EXPECT_EQ(stl->info.file_triangles, ply->mesh.triangleCount());
  EXPECT_TRUE(stl->info.topology.closed());
  expectClosedWithVolume(stl->mesh, 1000.0, 0.03);
  expectClosedWithVolume(ply->mesh, 1000.0, 0.03);
  EXPECT_NEAR(stl->mesh.signedVolume(), ply->mesh.signedVolume(), 1e-3 * 1000.0);
}

// Each tissue alone, and the outer surface coloured by the tissue it touches.
TEST_F(MeshCli, TissuesAreMeshedAndColouredApart) {
  const auto all = runDentsim("mesh " + file("layered.dvol") + " -o " + file("all.ply"));
  ASSERT_EQ(all.exit_code, 0) << all.output;
  const auto pulp = runDentsim("mesh " + file("layered.dvol") + " --tissue pulp -o " + file("pulp.ply"));
  ASSERT_EQ(pulp.exit_code, 0) << pulp.output;

  Result<PlyMesh> outer = readPly(file("all.ply"));
  ASSERT_TRUE(outer.ok()) << outer.message();
  expectClosedWithVolume(outer->mesh, 1000.0, 0.03);
  ASSERT_TRUE(outer->colours.has_value());
  EXPECT_TRUE(std::all_of(outer->colours->begin(), outer->colours->end(), [](const Rgb8& c) { return c == kEnamel; }));

  Result<PlyMesh> inner = readPly(file("pulp.ply"));
  ASSERT_TRUE(inner.ok()) << inner.message();
  expectClosedWithVolume(inner->mesh, test::sphereVolume(2.5), 0.05);
  ASSERT_TRUE(inner->colours.has_value());
  EXPECT_TRUE(std::all_of(inner->colours->begin(), inner->colours->end(), [](const Rgb8& c) { return c == kPulp; }));
}

// The layered view: the enamel shell (the cube with the pulp's cavity) and the pulp, each closed; the
// pulp wall appears in both, facing opposite ways, so the enamel's volume is the cube less the pulp.
TEST_F(MeshCli, InterfacesGiveEachTissueItsOwnClosedSurface) {
  const auto r = runDentsim("mesh " + file("layered.dvol") + " --interfaces -o " + file("layers.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("enamel"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("pulp"), std::string::npos) << r.output;
  Result<PlyMesh> layers = readPly(file("layers.ply"));
  ASSERT_TRUE(layers.ok()) << layers.message();
  ASSERT_TRUE(layers->colours.has_value());
  // Split by colour and check each shell.
  for (const auto& [colour, volume] : {std::pair{kEnamel, 1000.0 - test::sphereVolume(2.5)},
                                       std::pair{kPulp, test::sphereVolume(2.5)}}) {
    TriangleMesh part;
    std::vector<int64_t> remap(layers->mesh.positions.size(), -1);
    for (const auto& t : layers->mesh.triangles) {
      if (!((*layers->colours)[t[0]] == colour)) continue;
      std::array<uint32_t, 3> out{};
      for (int k = 0; k < 3; ++k) {
        if (remap[t[size_t(k)]] < 0) {
          remap[t[size_t(k)]] = int64_t(part.positions.size());
          part.positions.push_back(layers->mesh.positions[t[size_t(k)]]);
        }
        out[size_t(k)] = uint32_t(remap[t[size_t(k)]]);
      }
      part.triangles.push_back(out);
    }
    ASSERT_FALSE(part.triangles.empty());
    expectClosedWithVolume(part, volume, 0.05);
  }
  // Refused together with --tissue, in one line.
  const auto both = runDentsim("mesh " + file("layered.dvol") + " --interfaces --tissue pulp -o " + file("x.ply"));
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.output.find("--interfaces"), std::string::npos) << both.output;
}

// Where a Vulkan device exists the default path meshes on the GPU; it must give the CPU reference's
// triangles. Without one, both runs take the CPU path and the test still checks the fallback works.
TEST_F(MeshCli, GpuAndCpuPathsGiveTheSameTriangles) {
  const auto gpu = runDentsim("mesh " + file("sphere.dvol") + " --normals 64 -o " + file("g.stl"));
  ASSERT_EQ(gpu.exit_code, 0) << gpu.output;
  const auto cpu = runDentsim("mesh " + file("sphere.dvol") + " --normals 64 --cpu -o " + file("c.stl"));
  ASSERT_EQ(cpu.exit_code, 0) << cpu.output;
  Result<StlMesh> g = readStl(file("g.stl"));
  Result<StlMesh> c = readStl(file("c.stl"));
  ASSERT_TRUE(g.ok() && c.ok());
  ASSERT_EQ(g->mesh.triangles.size(), c->mesh.triangles.size());
  for (size_t i = 0; i < c->mesh.positions.size(); ++i)
    for (size_t a = 0; a < 3; ++a) ASSERT_NEAR(g->mesh.positions[i][a], c->mesh.positions[i][a], 1e-5);
}

TEST_F(MeshCli, BadInputFailsInOneLineAndWritesNothing) {
  struct Case {
    std::string args, output, expect;
  };
  const std::string cube = file("cube.dvol");
  const Case cases[] = {
      {file("missing.dvol"), "never.ply", "missing.dvol"},
      {file("cube.stl"), "never.ply", "cube.stl"},  // not a volume
      {cube, "never.obj", "unknown mesh format"},
      {cube, "never", "unknown mesh format"},
      {cube + " --normals 5", "never.ply", "--normals 5"},
      {cube + " --normals abc", "never.ply", "--normals abc"},
      {cube + " --tissue bone", "never.stl", "unknown tissue 'bone'"},
      {cube + " --tissue caries", "never.ply", "no surface"},  // the cube is dentin only
  };
  for (const Case& c : cases) {
    const std::string out = file(c.output);
    const auto r = runDentsim("mesh " + c.args + " -o " + out);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
  }
}

}  // namespace
}  // namespace dentsim
