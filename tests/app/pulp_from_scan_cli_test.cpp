// Tests of `dentsim voxelize --tooth T.stl --pulp-from SCAN`: the pulp of a whole-tooth surface taken from a grey-value scan of the same tooth, the enamel still synthesized.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "core/triangle_mesh.h"
#include "io/nifti_labels.h"
#include "io/stl_file.h"
#include "test_support.h"
#include "volume/tooth_file.h"
#include "volume/tooth_frame.h"

namespace dentsim {
namespace {

using test::runDentsim;

// A molar-sized tooth on a 0.25 mm scan grid, crown up along k, voxel (i, j, k) centred at
// (10, 20, 30) + 0.25 (i, j, k) mm: a root tapering from radius 2 mm (k 4) to 4 mm (k 49) under a
// crown of radius 5 mm (k 50..79) whose outer 1.2 mm is enamel. Its pulp is no synthesizer's: a
// chamber of radius 2.5 mm from k 44 to 65 (well above the CEJ, where the synthesized roof lies),
// and a canal of radius 0.6 mm from the chamber down to the apex.
enum ScanTissue : uint8_t { kEmpty, kEnamel, kDentin, kPulp };
constexpr int kNi = 48, kNj = 48, kNk = 88;
constexpr double kPitch = 0.25, kX0 = 10, kY0 = 20, kZ0 = 30;
constexpr double kAxisX = kX0 + kPitch * 23.5, kAxisY = kY0 + kPitch * 23.5;

double rootRadius(double k) { return 2.0 + 2.0 * (k - 4.0) / 45.0; }

ScanTissue tissueAt(int i, int j, int k) {
  const double r = kPitch * std::hypot(i - 23.5, j - 23.5);
  if (k < 4 || k >= 80) return kEmpty;
  if (k >= 44 && k <= 65 && r < 2.5) return kPulp;
  if (k < 44 && r < 0.6) return kPulp;
  if (k < 50) return r < rootRadius(k) ? kDentin : kEmpty;
  if (r >= 5.0) return kEmpty;
  return r < 3.8 && k < 76 ? kDentin : kEnamel;
}

// The pulp's volume in the scan: its voxels counted [mm^3].
double realPulpMm3() {
  int64_t n = 0;
  for (int k = 0; k < kNk; ++k)
    for (int j = 0; j < kNj; ++j)
      for (int i = 0; i < kNi; ++i) n += tissueAt(i, j, k) == kPulp;
  return double(n) * kPitch * kPitch * kPitch;
}

void put(std::vector<uint8_t>& h, size_t at, const void* v, size_t n) { std::memcpy(h.data() + at, v, n); }

// The scan as an uncompressed NIfTI-1 of floats, in HU by hand: enamel 2500, dentin 1500, pulp 30,
// air -1000. The sform places it (pitch on the diagonal, the origin above); little-endian host.
void writeGreyScan(const std::string& path, double x0) {
  std::vector<uint8_t> h(352, 0);
  const int32_t hdr = 348;
  put(h, 0, &hdr, 4);
  const int16_t dim[8] = {3, kNi, kNj, kNk, 1, 1, 1, 1};
  put(h, 40, dim, sizeof dim);
  const int16_t datatype = 16, bitpix = 32;  // float32
  put(h, 70, &datatype, 2);
  put(h, 72, &bitpix, 2);
  const float pixdim[8] = {1, float(kPitch), float(kPitch), float(kPitch), 1, 1, 1, 1};
  put(h, 76, pixdim, sizeof pixdim);
  const float vox_offset = 352, slope = 1, inter = 0;
  put(h, 108, &vox_offset, 4);
  put(h, 112, &slope, 4);
  put(h, 116, &inter, 4);
  const int16_t qform = 0, sform = 1;
  put(h, 252, &qform, 2);
  put(h, 254, &sform, 2);
  const float srow[12] = {float(kPitch), 0, 0, float(x0), 0, float(kPitch), 0, float(kY0), 0, 0, float(kPitch), float(kZ0)};
  put(h, 280, srow, sizeof srow);
  put(h, 344, "n+1", 4);
  std::vector<float> values;
  values.reserve(size_t(kNi) * kNj * kNk);
  const float hu[4] = {-1000.0f, 2500.0f, 1500.0f, 30.0f};
  for (int k = 0; k < kNk; ++k)
    for (int j = 0; j < kNj; ++j)
      for (int i = 0; i < kNi; ++i) values.push_back(hu[tissueAt(i, j, k)]);
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(h.data()), std::streamsize(h.size()));
  out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
}

// The same tooth's outer surface in the scan's mm, as a segmentation of the scan exports it: a
// surface of revolution about its axis, the root's cone (to the voxel faces at k 3.5 and 49.5)
// under the crown's cylinder (to k 79.5), 96 sides.
TriangleMesh toothSurface() {
  const auto z = [](double k) { return kZ0 + kPitch * k; };
  const std::vector<std::pair<double, double>> profile = {  // (z [mm], radius [mm]) from the apex up
      {z(3.5), 0.0}, {z(3.5), rootRadius(3.5)}, {z(49.5), rootRadius(49.5)}, {z(49.5), 5.0}, {z(79.5), 5.0}, {z(79.5), 0.0}};
  constexpr int kSides = 96;
  TriangleMesh mesh;
  for (const auto& [pz, r] : profile)
    for (int s = 0; s < kSides; ++s) {
      const double a = 2.0 * std::numbers::pi * s / kSides;
      mesh.positions.push_back(Vec3f{float(kAxisX + r * std::cos(a)), float(kAxisY + r * std::sin(a)), float(pz)});
    }
  // Outward winding: counter-clockwise seen from outside (the profile runs upward, the angle anticlockwise).
  for (uint32_t ring = 0; ring + 1 < profile.size(); ++ring)
    for (uint32_t s = 0; s < kSides; ++s) {
      const uint32_t a = ring * kSides + s, b = ring * kSides + (s + 1) % kSides, c = a + kSides, d = b + kSides;
      mesh.triangles.push_back({a, b, d});
      mesh.triangles.push_back({a, d, c});
    }
  return mesh;
}

class PulpFromScanCli : public ::testing::Test {
 protected:
  void SetUp() override {
    writeGreyScan(scan(), kX0);
    ASSERT_TRUE(writeStl(stl(), toothSurface(), "tooth of the grey scan"));
  }
  std::string scan() const { return dir_.file("grey.nii"); }
  std::string stl() const { return dir_.file("tooth.stl"); }
  test::TempDir dir_;
};

// The pulp comes from the scan, within 15 % of its true volume and reaching as high as the scan's
// chamber, where the synthesized one differs by more than a third; the enamel is the synthesized
// one, voxel for voxel, and the lines and the file say where the pulp came from.
TEST_F(PulpFromScanCli, ThePulpIsTheScansAndTheEnamelSynthesized) {
  const std::string with = dir_.file("with.dvol"), without = dir_.file("without.dvol");
  const auto r = runDentsim("voxelize --tooth " + stl() + " --pulp-from " + scan() + " --level 7 --cpu -o " + with);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("pulp from the scan " + scan() + " ("), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("mm^3), enamel synthesized"), std::string::npos) << r.output;
  const auto s = runDentsim("voxelize --tooth " + stl() + " --level 7 --cpu -o " + without);
  ASSERT_EQ(s.exit_code, 0) << s.output;
  auto a = loadTooth(with);
  auto b = loadTooth(without);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_NE(a->source_note.find("pulp from the scan"), std::string::npos) << a->source_note;
  EXPECT_EQ(a->layers, LayerSource::Synthesized);

  const double real = realPulpMm3();
  const MaterialTotals ta = a->voxels.materialTotals(), tb = b->voxels.materialTotals();
  const double scanned = ta.volumeMm3(Material::Pulp, a->frame.voxel_mm);
  const double synthesized = tb.volumeMm3(Material::Pulp, b->frame.voxel_mm);
  std::printf("pulp: real %.2f mm^3, from the scan %.2f mm^3, synthesized %.2f mm^3\n", real, scanned, synthesized);
  EXPECT_NEAR(scanned / real, 1.0, 0.15);
  EXPECT_GT(std::abs(synthesized / real - 1.0), 0.35);
  EXPECT_EQ(ta.voxels[DS_MAT_ENAMEL], tb.voxels[DS_MAT_ENAMEL]);
  // Tooth voxels are the same; what is not enamel or pulp is dentin.
  EXPECT_EQ(ta.voxels[DS_MAT_ENAMEL] + ta.voxels[DS_MAT_DENTIN] + ta.voxels[DS_MAT_PULP],
            tb.voxels[DS_MAT_ENAMEL] + tb.voxels[DS_MAT_DENTIN] + tb.voxels[DS_MAT_PULP]);

  // The scan's chamber reaches k 65 of the tooth's 4..79: 81.6 % of the way up from the apex.
  const auto boxes = tissueVoxelBoxes(a->voxels);
  const VoxelBox tooth = boxes[0], pulp = boxes[DS_MAT_PULP];
  ASSERT_FALSE(pulp.empty());
  const double up = double(pulp.hi[2] + 1 - tooth.lo[2]) / double(tooth.hi[2] + 1 - tooth.lo[2]);
  EXPECT_NEAR(up, (65.5 - 3.5) / (79.5 - 3.5), 0.04);
}

// A DICOM series of the same tooth, as `make-scan` writes it from the tooth's labels with a
// scanner's blur and 60 HU of noise, gives the same pulp within 15 %.
TEST_F(PulpFromScanCli, ADicomSeriesWithNoiseGivesThePulpToo) {
  LabelImage labels;
  labels.dims = {kNi, kNj, kNk};
  labels.pitch_mm = {kPitch, kPitch, kPitch};
  labels.scanner_from_voxel = {kPitch, 0, 0, kX0, 0, kPitch, 0, kY0, 0, 0, kPitch, kZ0};
  labels.labels.assign(size_t(labels.voxelCount()), 0);
  for (int k = 0; k < kNk; ++k)
    for (int j = 0; j < kNj; ++j)
      for (int i = 0; i < kNi; ++i) labels.labels[labels.index(i, j, k)] = Label(tissueAt(i, j, k));
  ASSERT_TRUE(writeNiftiLabels(dir_.file("labels.nii.gz"), labels));
  const auto made = runDentsim("make-scan --labels " + dir_.file("labels.nii.gz") +
                               " --label-map 1=enamel,2=dentin,3=pulp --noise-hu 60 -o " + dir_.file("series"));
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const std::string out = dir_.file("dicom.dvol");
  const auto r = runDentsim("voxelize --tooth " + stl() + " --pulp-from " + dir_.file("series") + " --level 7 --cpu -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("pulp from the scan " + dir_.file("series") + " ("), std::string::npos) << r.output;
  auto t = loadTooth(out);
  ASSERT_TRUE(t.ok()) << t.message();
  const double scanned = t->voxels.materialTotals().volumeMm3(Material::Pulp, t->frame.voxel_mm);
  std::printf("pulp: real %.2f mm^3, from the DICOM series %.2f mm^3\n", realPulpMm3(), scanned);
  EXPECT_NEAR(scanned / realPulpMm3(), 1.0, 0.15);
}

// A scan that does not hold the tooth, one that cannot be read, and --pulp-from where no pulp is
// synthesized each fail in one line, and nothing is written.
TEST_F(PulpFromScanCli, MistakesFailInOneLineAndWriteNothing) {
  const std::string out = dir_.file("never.dvol");
  // The tooth half again as large reaches outside the scan; the plan goes to stdout, the error alone to stderr.
  const auto outside = test::runCommand("{ " + std::string(DENTSIM_BINARY) + " voxelize --tooth " + stl() +
                                        " --scale 1.5 --pulp-from " + scan() + " --level 7 --cpu -o " + out +
                                        " >/dev/null; }");
  test::expectCleanFailure(outside, "the tooth's box ", "does not lie inside the scan's ", out);
  EXPECT_NE(outside.output.find(scan()), std::string::npos) << outside.output;
  // The same scan moved 30 mm along x: both boxes are named.
  writeGreyScan(dir_.file("moved.nii"), kX0 + 30.0);
  const auto moved = test::runCommand("{ " + std::string(DENTSIM_BINARY) + " voxelize --tooth " + stl() + " --pulp-from " +
                                      dir_.file("moved.nii") + " --level 7 --cpu -o " + out + " >/dev/null; }");
  test::expectCleanFailure(moved, "10.9..20.9, 20.9..30.9", "39.9..51.9, 19.9..31.9", out);

  test::expectCleanFailure(runDentsim("voxelize --tooth " + stl() + " --pulp-from " + dir_.file("gone.nii") +
                                      " --level 7 --cpu -o " + out),
                           "gone.nii", "", out);
  test::expectCleanFailure(runDentsim("voxelize --tooth " + stl() + " --tooth-material dentin --pulp-from " + scan() +
                                      " --level 7 --cpu -o " + out),
                           "--pulp-from", "--tooth-material keeps one tissue", out);
  test::expectCleanFailure(runDentsim("voxelize --dentin " + stl() + " --pulp-from " + scan() + " --level 7 --cpu -o " + out),
                           "--pulp-from", "no --tooth is given", out);
}

}  // namespace
}  // namespace dentsim
