// Tests of src/render/look_params.cpp: the defaults from the tissue table, the "looks" and "view" sections read, checked and skipped.
#include "render/look_params.h"

#include <gtest/gtest.h>

#include <string>

#include "volume/tissue_table.h"

namespace dentsim {
namespace {

const std::string kWhere = "t.json";

// A preset holding `body` after the format and version lines.
std::string preset(const std::string& body) {
  return std::string(R"({"format": "dentsim-params", "version": 1)") + (body.empty() ? "" : ", " + body) + "}";
}

TEST(LookParams, DefaultsComeFromTheTissueTable) {
  const LookParams d = defaultLookParams();
  for (const TissueRow& row : kTissueTable) {
    const TissueLook& l = d.look(row.material);
    EXPECT_EQ(l.diffuse_r, row.look.diffuse[0]) << row.name;
    EXPECT_EQ(l.specular_b, row.look.specular[2]) << row.name;
    EXPECT_EQ(l.alpha, row.look.alpha) << row.name;
    EXPECT_EQ(l.shininess, row.look.shininess) << row.name;
  }
  EXPECT_EQ(d.view.normals, NormalMode::Box216);
}

// The visual half of a preset: a partial "looks" entry overrides only its keys, and the ranges hold.
TEST(LookParams, LooksAndViewOverrideAndValidate) {
  auto p = parseLookParams(preset(R"("looks": {"enamel": {"alpha": 0.4, "diffuse_r": 0.5}}, "view": {"normal_neighbours": 64})"),
                           kWhere);
  ASSERT_TRUE(p.ok()) << p.message();
  LookParams expected = defaultLookParams();
  expected.look(Material::Enamel).alpha = 0.4;
  expected.look(Material::Enamel).diffuse_r = 0.5;
  expected.view.normals = NormalMode::Box64;
  EXPECT_TRUE(*p == expected);
  EXPECT_FALSE(*p == defaultLookParams());

  auto alpha = parseLookParams(preset(R"("looks": {"pulp": {"alpha": 1.2}})"), kWhere);
  ASSERT_FALSE(alpha.ok());
  EXPECT_EQ(alpha.message(), "t.json: looks.pulp.alpha: 1.2 is not in [0, 1]");
  auto shiny = parseLookParams(preset(R"("looks": {"dentin": {"shininess": 0.5}})"), kWhere);
  ASSERT_FALSE(shiny.ok());
  EXPECT_EQ(shiny.message(), "t.json: looks.dentin.shininess: 0.5 is not in [1, 512]");
  auto mode = parseLookParams(preset(R"("view": {"normal_neighbours": 100})"), kWhere);
  ASSERT_FALSE(mode.ok());
  EXPECT_EQ(mode.message(), "t.json: view.normal_neighbours: 100.0 is not 8, 64 or 216");
  auto tissue = parseLookParams(preset(R"("looks": {"bone": {}})"), kWhere);
  ASSERT_FALSE(tissue.ok());
  EXPECT_NE(tissue.message().find("looks"), std::string::npos) << tissue.message();
  // Every default look is opaque except the enamel, which lets the layers beneath show.
  const LookParams d = defaultLookParams();
  EXPECT_LT(d.look(Material::Enamel).alpha, 1.0);
  for (Material m : {Material::Dentin, Material::Pulp, Material::Caries}) EXPECT_EQ(d.look(m).alpha, 1.0);
}

// The tactile sections are sim's: accepted here and not read; the header is still checked.
TEST(LookParams, SkipsTheTactileSectionsAndChecksTheHeader) {
  auto p = parseLookParams(preset(R"("tissues": {"enamel": {"hardness": 0.3}}, "burs": {"x": {}})"), kWhere);
  ASSERT_TRUE(p.ok()) << p.message();
  EXPECT_TRUE(*p == defaultLookParams());
  auto format = parseLookParams(R"({"format": "dentsim-task", "version": 1})", kWhere);
  ASSERT_FALSE(format.ok());
  EXPECT_EQ(format.message(), "t.json: format: \"dentsim-task\" is not \"dentsim-params\"");
  auto other = parseLookParams(preset(R"("colours": {})"), kWhere);
  ASSERT_FALSE(other.ok());
  EXPECT_NE(other.message().find("colours"), std::string::npos) << other.message();
}

}  // namespace
}  // namespace dentsim
