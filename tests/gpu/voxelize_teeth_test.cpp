// Real and built-in teeth voxelized on the GPU at level 9: per-tissue volumes against the exact mesh volumes.
#include <gtest/gtest.h>

#include <filesystem>

#include "gpu/gpu_voxelizer.h"
#include "gpu_fixture.h"
#include "io/stl_file.h"
#include "model/builtin_assets.h"
#include "test_support.h"

namespace dentsim::gpu::test {
namespace {

class ToothVolumeTest : public GpuTest {
 protected:
  // Tissue volumes [mm^3] of the layers voxelized together on one grid fitted to `bounds`.
  MaterialTotals voxelizeOn(const std::vector<MeshLayer>& layers, const VolumeFrame& frame) {
    auto setup = makeRaySetup(layers, frame, {});
    EXPECT_TRUE(setup.ok());
    auto v = voxelizeGpu(ctx(), *setup, {});
    EXPECT_TRUE(v.ok()) << (v ? "" : v.message());
    return v ? v->materialTotals() : MaterialTotals{};
  }
};

// The fraction by which `got` misses `want`.
double relativeError(double got, double want) { return std::abs(got - want) / want; }

TEST_F(ToothVolumeTest, Chai3dMolarWithPulpWithinHalfPercentAtLevel9) {
  const auto dir = dentsim::test::dataDir() / "teeth";
  if (!std::filesystem::exists(dir / "chai3d_molar_tooth.stl")) GTEST_SKIP() << "no tooth data in " << dir;
  auto tooth = readStl((dir / "chai3d_molar_tooth.stl").string());
  auto pulp = readStl((dir / "chai3d_molar_pulp.stl").string());
  ASSERT_TRUE(tooth.ok() && pulp.ok());
  tooth->mesh.scale(0.04);
  pulp->mesh.scale(0.04);
  const double vt = tooth->mesh.signedVolume(), vp = pulp->mesh.signedVolume();
  Bounds3 b = tooth->mesh.bounds();
  b.add(pulp->mesh.bounds());
  auto frame = fitGridToLevel(b, 9);
  ASSERT_TRUE(frame.ok());
  const double vox = frame->voxel_mm;

  // Each layer alone, then both: the pulp (nested, genus 2) wins inside the tooth.
  const MaterialTotals t_alone = voxelizeOn({{Material::Dentin, &tooth->mesh, "tooth"}}, *frame);
  const MaterialTotals p_alone = voxelizeOn({{Material::Pulp, &pulp->mesh, "pulp"}}, *frame);
  const MaterialTotals both =
      voxelizeOn({{Material::Dentin, &tooth->mesh, "tooth"}, {Material::Pulp, &pulp->mesh, "pulp"}}, *frame);
  const double t1 = t_alone.volumeMm3(Material::Dentin, vox), p1 = p_alone.volumeMm3(Material::Pulp, vox);
  const double d2 = both.volumeMm3(Material::Dentin, vox), p2 = both.volumeMm3(Material::Pulp, vox);
  std::printf("chai3d molar, level 9 (voxel %.4f mm): tooth %.3f vs mesh %.3f; pulp %.3f vs %.3f; "
              "dentin in the pair %.3f vs %.3f\n", vox, t1, vt, p1, vp, d2, vt - vp);
  EXPECT_LT(relativeError(t1, vt), 0.005);
  EXPECT_LT(relativeError(p1, vp), 0.005);
  EXPECT_LT(relativeError(p2, vp), 0.005);
  EXPECT_LT(relativeError(d2, vt - vp), 0.005);
}

TEST_F(ToothVolumeTest, BuiltInMolarWithinHalfPercentAtLevel9) {
  auto molar = loadBuiltinMolar();
  ASSERT_TRUE(molar.ok()) << molar.message();
  const TriangleMesh* meshes[4] = {&molar->enamel, &molar->dentin, &molar->pulp, &molar->caries};
  const Material tissues[4] = {Material::Enamel, Material::Dentin, Material::Pulp, Material::Caries};
  Bounds3 b;
  for (const TriangleMesh* m : meshes) b.add(m->bounds());
  auto frame = fitGridToLevel(b, 9);
  ASSERT_TRUE(frame.ok());
  const double vox = frame->voxel_mm;
  double exact[4];
  std::vector<MeshLayer> all;
  for (int i = 0; i < 4; ++i) {
    exact[i] = meshes[i]->signedVolume();
    const MaterialTotals alone = voxelizeOn({{tissues[i], meshes[i], materialName(tissues[i])}}, *frame);
    const double got = alone.volumeMm3(tissues[i], vox);
    std::printf("molar %-6s alone: %.3f mm^3 vs mesh %.3f (%+.3f%%)\n", materialName(tissues[i]).c_str(), got,
                exact[i], 100.0 * (got - exact[i]) / exact[i]);
    EXPECT_LT(relativeError(got, exact[i]), 0.005) << materialName(tissues[i]);
    all.push_back({tissues[i], meshes[i], materialName(tissues[i])});
  }
  // Together: the enamel shell and the dentin share the DEJ and do not overlap, the pulp lies in
  // the dentin and the lesion in enamel and dentin, so the divergence theorem gives the pulp, the
  // caries, and enamel + dentin outside them exactly.
  const MaterialTotals t = voxelizeOn(all, *frame);
  const double e = t.volumeMm3(Material::Enamel, vox), d = t.volumeMm3(Material::Dentin, vox);
  const double p = t.volumeMm3(Material::Pulp, vox), c = t.volumeMm3(Material::Caries, vox);
  std::printf("molar together: enamel %.3f, dentin %.3f, pulp %.3f (mesh %.3f), caries %.3f (mesh %.3f), "
              "enamel+dentin %.3f (meshes %.3f)\n", e, d, p, exact[2], c, exact[3], e + d,
              exact[0] + exact[1] - exact[2] - exact[3]);
  EXPECT_LT(relativeError(p, exact[2]), 0.005);
  EXPECT_LT(relativeError(c, exact[3]), 0.005);
  EXPECT_LT(relativeError(e + d, exact[0] + exact[1] - exact[2] - exact[3]), 0.005);
}

}  // namespace
}  // namespace dentsim::gpu::test
