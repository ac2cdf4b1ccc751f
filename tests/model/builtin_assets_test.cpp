// Tests of the embedded assets: regenerated files equal the checked-in and embedded bytes; they parse back.
#include "model/builtin_assets.h"

#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "io/mesh_topology.h"
#include "model/tool_generator.h"

namespace dentsim {
namespace {

std::vector<uint8_t> readSourceAsset(const std::string& relative) {
  std::ifstream in(std::string(DENTSIM_SOURCE_DIR) + "/assets/" + relative, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(BuiltinAssets, RegeneratedFilesEqualCheckedInAndEmbeddedBytes) {
  // The one full-resolution run of the suite.
  const GeneratedAssets g = generateAssets();
  std::vector<std::string> paths;
  for (const AssetFile& f : g.files) {
    paths.push_back(f.path);
    const std::vector<uint8_t> checked_in = readSourceAsset(f.path);
    EXPECT_TRUE(checked_in == f.bytes) << f.path << " differs from assets/; run `dentsim make-tooth --out assets`";
    const std::span<const uint8_t> embedded = builtinAssetBytes(f.path);
    EXPECT_TRUE(std::equal(embedded.begin(), embedded.end(), f.bytes.begin(), f.bytes.end()))
        << f.path << " differs from the embedded copy; rebuild";
  }
  std::sort(paths.begin(), paths.end());
  // Every embedded file is generated, except the presets: generateAssets() does not make them
  // (src/sim writes them; tests/sim/sim_params_test.cpp checks the default against its bytes).
  std::vector<std::string> embedded_generated;
  for (const std::string& p : builtinAssetPaths())
    if (p.rfind("presets/", 0) != 0 && p.rfind("tasks/", 0) != 0) embedded_generated.push_back(p);
  EXPECT_EQ(embedded_generated, paths);
  // Within the budget: about 80k-150k molar triangles, all assets under 10 MB.
  const size_t triangles = g.molar.enamel.triangleCount() + g.molar.dentin.triangleCount() +
                           g.molar.pulp.triangleCount() + g.molar.caries.triangleCount();
  EXPECT_GE(triangles, 80'000u);
  EXPECT_LE(triangles, 150'000u);
  // The neighbours, on their coarser lattice: about 39k triangles for both.
  const size_t neighbours = g.neighbours.premolar.triangleCount() + g.neighbours.second_molar.triangleCount();
  EXPECT_GE(neighbours, 20'000u);
  EXPECT_LE(neighbours, 60'000u);
  size_t bytes = 0;
  for (const AssetFile& f : g.files) bytes += f.bytes.size();
  EXPECT_LT(bytes, 10'000'000u);
}

TEST(BuiltinAssets, MolarParsesBackClosedAndOutward) {
  auto molar = loadBuiltinMolar();
  ASSERT_TRUE(molar.ok()) << molar.message();
  for (const TriangleMesh* m : {&molar->enamel, &molar->dentin, &molar->pulp, &molar->caries}) {
    const MeshTopology t = analyzeTopology(*m);
    EXPECT_TRUE(t.closed());
    EXPECT_EQ(t.orientation(), "outward");
  }
}

TEST(BuiltinAssets, NeighboursParseBackClosedAndOutward) {
  auto teeth = loadBuiltinNeighbours();
  ASSERT_TRUE(teeth.ok()) << teeth.message();
  for (const NeighbourRow& row : kNeighbourTeeth) {
    const MeshTopology t = analyzeTopology((*teeth).*row.mesh);
    EXPECT_TRUE(t.closed()) << row.name;
    EXPECT_EQ(t.orientation(), "outward") << row.name;
  }
}

TEST(BuiltinAssets, ToolsLoadByName) {
  for (const ToolSpec& t : toolCatalog()) {
    auto mesh = loadBuiltinTool(t.name);
    ASSERT_TRUE(mesh.ok()) << mesh.message();
    EXPECT_EQ(mesh->triangleCount(), generateTool(t).triangleCount()) << t.name;
  }
  auto missing = loadBuiltinTool("no_such_bur");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("round_bur_010"), std::string::npos) << "lists the known tools";
}

}  // namespace
}  // namespace dentsim
