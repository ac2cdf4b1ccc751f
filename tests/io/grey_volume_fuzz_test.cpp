// Bounded, deterministic mutation fuzzing of the scanner readers (a DICOM series with one damaged slice, NRRD files): never a crash, every failure one line.
#include <gtest/gtest.h>

#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "fuzz_mutations.h"
#include "io/dicom_series.h"
#include "io/grey_volume_file.h"
#include "test_support.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;

void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// A number in a header's text swapped for a boundary one: sizes, lengths and counts.
void mutateNumber(std::vector<uint8_t>& bytes, std::mt19937& rng, size_t header_bytes) {
  static const char* kNumbers[] = {"0", "-1", "65535", "4294967295", "1e308", "nan", "3", "99999999"};
  const size_t at = test::pick(rng, std::min(header_bytes, bytes.size()));
  const std::string n = kNumbers[rng() % std::size(kNumbers)];
  bytes.insert(bytes.begin() + std::ptrdiff_t(at), n.begin(), n.end());
}

TEST(GreyVolumeFuzz, MutatedDicomSliceInASeries) {
  test::TempDir tmp;
  GreyImage g;
  g.dims = {8, 6, 3};
  g.scanner_from_voxel = {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0};
  g.values.assign(size_t(g.voxelCount()), 100.0f);
  const std::string seed_dir = tmp.file("seed");
  auto files = writeDicomSeries(seed_dir, g);
  ASSERT_TRUE(files) << files.message();
  const std::vector<uint8_t> original = test::readBytes((*files)[1]);
  const std::string dir = tmp.file("case");
  fs::copy(seed_dir, dir);
  const std::string victim = dir + "/slice-0002.dcm";
  DicomReadOptions tight;
  tight.max_bytes = uint64_t{1} << 24;
  std::mt19937 rng(20261128u);
  int accepted = 0, rejected = 0;
  for (int it = 0; it < 300; ++it) {
    std::vector<uint8_t> bytes = original;
    for (int e = 1 + int(rng() % 3); e > 0; --e)
      if (!test::mutateBytesGeneric(bytes, rng)) mutateNumber(bytes, rng, 600);
    writeBytes(victim, bytes);
    Result<GreyImage> r = readDicomSeries(dir, tight);
    if (r) {
      ++accepted;
      ASSERT_EQ(r->values.size(), size_t(r->voxelCount()));
    } else {
      ++rejected;
      ASSERT_EQ(r.message().rfind(dir, 0), 0u) << r.message();
      ASSERT_EQ(r.message().find('\n'), std::string::npos) << "iteration " << it << ": " << r.message();
    }
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

std::vector<uint8_t> nrrdSeed(bool gzip) {
  std::string header =
      "NRRD0004\ntype: short\ndimension: 3\nspace: left-posterior-superior\nsizes: 4 3 2\n"
      "space directions: (0.5,0,0) (0,0.25,0) (0,0,2)\nspace origin: (1,2,3)\nendian: little\nencoding: ";
  header += gzip ? "gzip\n\n" : "raw\n\n";
  std::vector<uint8_t> bytes(header.begin(), header.end());
  std::vector<uint8_t> data(48);
  for (size_t i = 0; i < 24; ++i) data[2 * i] = uint8_t(i);
  if (!gzip) {
    bytes.insert(bytes.end(), data.begin(), data.end());
    return bytes;
  }
  // A gzip stream (zlib's deflate with a gzip wrapper), as Teem expects after the header.
  z_stream z{};
  deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
  std::vector<uint8_t> out(256);
  z.next_in = data.data();
  z.avail_in = uInt(data.size());
  z.next_out = out.data();
  z.avail_out = uInt(out.size());
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  bytes.insert(bytes.end(), out.begin(), out.end());
  return bytes;
}

TEST(GreyVolumeFuzz, MutatedNrrdFiles) {
  test::TempDir tmp;
  const std::string path = tmp.file("case.nrrd");
  for (bool gzip : {false, true}) {
    const std::vector<uint8_t> original = nrrdSeed(gzip);
    writeBytes(path, original);
    Result<GreyImage> seed = readNrrdGrey(path);
    ASSERT_TRUE(seed) << seed.message();
    std::mt19937 rng(gzip ? 11u : 12u);
    int accepted = 0, rejected = 0;
    for (int it = 0; it < 1500; ++it) {
      std::vector<uint8_t> bytes = original;
      for (int e = 1 + int(rng() % 3); e > 0; --e)
        if (!test::mutateBytesGeneric(bytes, rng)) mutateNumber(bytes, rng, 200);
      writeBytes(path, bytes);
      Result<GreyImage> r = readNrrdGrey(path, uint64_t{1} << 24);
      if (r) {
        ++accepted;
        ASSERT_EQ(r->values.size(), size_t(r->voxelCount()));
      } else {
        ++rejected;
        test::assertOneLineRejection(r.message(), path, it);
      }
    }
    EXPECT_GT(accepted, 0) << (gzip ? "gzip" : "raw");
    EXPECT_GT(rejected, 0) << (gzip ? "gzip" : "raw");
  }
}

}  // namespace
}  // namespace dentsim
