// Tests for src/volume/tissue_table.h: the rows are unique, cover every tissue code, and derive the lists.
#include "volume/tissue_table.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace dentsim {
namespace {

TEST(TissueTable, NamesCodesAndLabelsAreUnique) {
  std::set<std::string> names;
  std::set<Material> codes;
  std::set<int32_t> labels;
  for (const TissueRow& row : kTissueTable) {
    EXPECT_TRUE(names.insert(row.name).second) << row.name;
    EXPECT_TRUE(codes.insert(row.material).second) << row.name;
    EXPECT_TRUE(labels.insert(row.nifti_label).second) << row.name;
    // Label 0 is empty in every label volume.
    EXPECT_NE(row.nifti_label, 0) << row.name;
    EXPECT_NE(std::string(row.name), "empty");
  }
}

TEST(TissueTable, EveryTissueCodeTheVolumeUsesHasARow) {
  // DS_TISSUE_COUNT counts empty and the tissues; codes above it are spare and have none.
  for (uint32_t m = 1; m < DS_TISSUE_COUNT; ++m) EXPECT_NE(findTissue(Material(m)), nullptr) << m;
  for (uint32_t m = DS_TISSUE_COUNT; m < DS_MATERIAL_COUNT; ++m) EXPECT_EQ(findTissue(Material(m)), nullptr) << m;
  EXPECT_EQ(findTissue(Material::Empty), nullptr);
  for (Material m : {Material::Enamel, Material::Dentin, Material::Pulp, Material::Caries})
    EXPECT_NE(findTissue(m), nullptr) << materialName(m);
}

TEST(TissueTable, DrawOrderIsAPermutation) {
  std::set<Material> drawn;
  for (Material m : tissuesInDrawOrder()) drawn.insert(m);
  EXPECT_EQ(drawn.size(), kTissueCount);
  std::set<int> orders;
  for (const TissueRow& row : kTissueTable) orders.insert(row.draw_order);
  ASSERT_EQ(orders.size(), kTissueCount);
  EXPECT_EQ(*orders.begin(), 0);
  EXPECT_EQ(*orders.rbegin(), int(kTissueCount) - 1);
}

TEST(TissueTable, NamesAndIndicesComeFromTheRows) {
  for (size_t i = 0; i < kTissueCount; ++i) {
    const TissueRow& row = kTissueTable[i];
    EXPECT_EQ(materialName(row.material), row.name);
    Material parsed = Material::Empty;
    ASSERT_TRUE(parseMaterial(row.name, &parsed)) << row.name;
    EXPECT_EQ(parsed, row.material);
    EXPECT_EQ(tissueIndex(row.material), int(i));
    EXPECT_EQ(kTissues[i], row.material);
  }
  EXPECT_EQ(tissueIndex(Material::Empty), -1);
  EXPECT_EQ(materialName(Material::Empty), "empty");
  EXPECT_EQ(materialName(Material(6)), "material6");
}

TEST(TissueTable, DefaultsAreInTheirRanges) {
  // The preset reader's ranges (sim_params.cpp), so that the built-in defaults always save and load.
  for (const TissueRow& row : kTissueTable) {
    EXPECT_GT(row.touch.stiffness_n_per_mm3, 0.0) << row.name;
    EXPECT_GE(row.touch.damping_s_per_mm, 0.0) << row.name;
    EXPECT_GE(row.touch.friction, 0.0) << row.name;
    EXPECT_LE(row.touch.friction, 2.0) << row.name;
    EXPECT_GE(row.touch.hardness, 0.0) << row.name;
    EXPECT_LE(row.touch.hardness, 1.0) << row.name;
    EXPECT_GE(row.look.alpha, 0.0) << row.name;
    EXPECT_LE(row.look.alpha, 1.0) << row.name;
    EXPECT_GE(row.look.shininess, 1.0) << row.name;
    EXPECT_LE(row.look.shininess, 512.0) << row.name;
  }
}

}  // namespace
}  // namespace dentsim
