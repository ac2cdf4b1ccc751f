// Real micro-CT teeth (shared/data/ct): import at the true 0.034 mm pitch keeps every label, and export gives them back.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdio>

#include "io/nifti_labels.h"
#include "test_support.h"
#include "volume/label_import.h"

namespace dentsim {
namespace {

constexpr double kPitchMm = 0.034;  // the real pitch; the headers say 1.0 (data README)

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void checkTooth(const std::string& name, uint64_t expected_caries) {
  const std::filesystem::path data = test::dataDir();
  if (data.empty() || !std::filesystem::exists(data / "ct" / name))
    GTEST_SKIP() << "real CT data not found in " << (data.empty() ? std::string("../shared/data") : data.string());
  const std::string path = (data / "ct" / name).string();

  auto t = std::chrono::steady_clock::now();
  Result<LabelImage> image = readNiftiLabels(path);
  ASSERT_TRUE(image.ok()) << image.message();
  const double read_s = secondsSince(t);
  ASSERT_EQ(image->dims, (std::array<int32_t, 3>{600, 600, 400}));

  // Label counts, computed here from the image alone.
  std::array<uint64_t, 4> count{};
  for (Label l : image->labels) {
    ASSERT_TRUE(l >= 0 && l <= 3) << "unexpected label " << l;
    ++count[size_t(l)];
  }
  EXPECT_EQ(count[1], expected_caries);  // the data README's caries count

  LabelImportOptions opt;
  opt.map = parseLabelMap("1=caries,2=enamel,3=dentin").value();
  opt.source_pitch_mm = kPitchMm;
  opt.where = path;
  t = std::chrono::steady_clock::now();
  Result<ToothVolume> tooth = importLabels(*image, opt);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  const double import_s = secondsSince(t);
  EXPECT_EQ(tooth->frame.level, 10);
  EXPECT_DOUBLE_EQ(tooth->frame.voxel_mm, kPitchMm);

  const double voxel_mm3 = kPitchMm * kPitchMm * kPitchMm;
  const MaterialTotals totals = tooth->voxels.materialTotals();
  const std::array<std::pair<Material, uint64_t>, 3> tissues = {
      {{Material::Caries, count[1]}, {Material::Enamel, count[2]}, {Material::Dentin, count[3]}}};
  for (const auto& [m, n] : tissues) {
    EXPECT_EQ(totals.voxels[size_t(m)], n) << materialName(m);
    EXPECT_NEAR(totals.volumeMm3(m, kPitchMm), double(n) * voxel_mm3, 1e-9 * double(n) * voxel_mm3)
        << materialName(m);
  }
  EXPECT_EQ(totals.voxels[DS_MAT_PULP], 0u);

  t = std::chrono::steady_clock::now();
  const LabelImage back = exportLabels(*tooth);
  const double export_s = secondsSince(t);
  ASSERT_EQ(back.dims, image->dims);
  const Label renumber[4] = {0, DS_MAT_CARIES, DS_MAT_ENAMEL, DS_MAT_DENTIN};
  size_t mismatches = 0;
  for (size_t i = 0; i < back.labels.size(); ++i) mismatches += back.labels[i] != renumber[image->labels[i]];
  EXPECT_EQ(mismatches, 0u);
  for (size_t i = 0; i < 12; ++i) {
    // The header's flipped unit matrix with the pitch replaced: diag(-0.034, -0.034, 0.034).
    const double expected = (i == 0 || i == 5) ? -kPitchMm : (i == 10 ? kPitchMm : 0.0);
    EXPECT_NEAR(back.scanner_from_voxel[i], i % 4 == 3 ? image->scanner_from_voxel[i] : expected, 1e-12) << i;
  }
  tooth = Error{};  // free before the second import

  // The pulp is the empty space the tooth encloses. The canals open at the root apices, so the
  // dentin is closed by 0.2 mm first (what `voxelize --fill-enclosed pulp` does by default).
  opt.fill_enclosed = Material::Pulp;
  opt.seal_mm = 0.2;
  t = std::chrono::steady_clock::now();
  Result<ToothVolume> filled = importLabels(*image, opt);
  ASSERT_TRUE(filled.ok()) << filled.message();
  const double fill_s = secondsSince(t);
  const MaterialTotals ft = filled->voxels.materialTotals();
  // Molar pulp chambers with canals hold tens of mm^3; an unsealed flood finds under 0.01 mm^3 here.
  EXPECT_GT(ft.volumeMm3(Material::Pulp, kPitchMm), 5.0);
  EXPECT_LT(ft.volumeMm3(Material::Pulp, kPitchMm), 100.0);
  for (const auto& [m, n] : tissues) EXPECT_EQ(ft.voxels[size_t(m)], n) << materialName(m);
  std::printf("%s: read %.2f s, import %.2f s, export %.2f s, import with pulp fill %.2f s; pulp %.3f mm^3\n",
              name.c_str(), read_s, import_s, export_s, fill_s, ft.volumeMm3(Material::Pulp, kPitchMm));
}

TEST(CtTeethTest, Tooth2) { checkTooth("tooth_2.nii.gz", 163638); }
TEST(CtTeethTest, Tooth3) { checkTooth("tooth_3.nii.gz", 91460); }

}  // namespace
}  // namespace dentsim
