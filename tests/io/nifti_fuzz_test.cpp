// Bounded, deterministic mutation fuzzing of readNiftiLabels: hostile bytes never crash it, and every failure is one clear line.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <random>

#include "io/nifti_labels.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readBytes;
LabelImage seedImage() {
  LabelImage im;
  im.dims = {6, 5, 4};
  im.pitch_mm = {0.5, 0.5, 0.5};
  im.scanner_from_voxel = {-0.5, 0, 0, 1, 0, -0.5, 0, 2, 0, 0, 0.5, 3};
  im.labels.resize(120);
  for (size_t i = 0; i < im.labels.size(); ++i) im.labels[i] = Label(i % 4);
  return im;
}

// One random change: flip bits, overwrite a byte with a boundary value, insert or delete a run, or cut
// the tail. Half of the positions fall in the header, where the interesting fields are.
void mutate(std::vector<uint8_t>& bytes, std::mt19937& rng, size_t header_bytes) {
  auto pick = [&](size_t n) { return n == 0 ? size_t(0) : size_t(rng() % n); };
  auto position = [&] {
    const size_t limit = (rng() % 2 == 0) ? std::min(header_bytes, bytes.size()) : bytes.size();
    return pick(limit);
  };
  static const uint8_t kBoundary[] = {0x00, 0x01, 0x7f, 0x80, 0xff, 0xfe, 0x03, 0x04};
  switch (rng() % 6) {
    case 0:
      if (!bytes.empty()) bytes[position()] ^= uint8_t(1u << (rng() % 8));
      break;
    case 1:
      if (!bytes.empty()) bytes[position()] = kBoundary[rng() % 8];
      break;
    case 2: {
      const size_t at = bytes.empty() ? 0 : position();
      const size_t n = 1 + pick(16);
      std::vector<uint8_t> run(n);
      for (uint8_t& b : run) b = uint8_t(rng());
      bytes.insert(bytes.begin() + std::ptrdiff_t(at), run.begin(), run.end());
      break;
    }
    case 3: {
      if (bytes.empty()) break;
      const size_t at = position();
      const size_t n = std::min(bytes.size() - at, 1 + pick(32));
      bytes.erase(bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + n));
      break;
    }
    case 4:
      bytes.resize(pick(bytes.size() + 1));
      break;
    default:
      if (bytes.size() >= 4) {  // a random 32-bit word: dims, offsets and codes change together
        const size_t at = pick(std::min(header_bytes, bytes.size() - 3));
        const uint32_t w = uint32_t(rng());
        for (size_t k = 0; k < 4; ++k) bytes[at + k] = uint8_t(w >> (8 * k));
      }
      break;
  }
}

void fuzzSeed(const std::string& extension, uint32_t seed, int iterations) {
  test::TempDir dir;
  const std::string seed_path = dir.file("seed" + extension);
  ASSERT_TRUE(writeNiftiLabels(seed_path, seedImage()).ok());
  const std::vector<uint8_t> original = readBytes(seed_path);
  const std::string path = dir.file("case" + extension);
  NiftiReadLimits limits;  // tight, so that a forged header cannot make the test allocate much
  limits.max_voxels = int64_t{1} << 20;
  limits.max_bytes = uint64_t{1} << 23;

  std::mt19937 rng(seed);
  int accepted = 0, rejected = 0;
  for (int it = 0; it < iterations; ++it) {
    std::vector<uint8_t> bytes = original;
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits; ++e) mutate(bytes, rng, 352);
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    Result<LabelImage> r = readNiftiLabels(path, limits);
    if (r.ok()) {
      ++accepted;
      ASSERT_GT(r->dims[0], 0);
      ASSERT_GT(r->dims[1], 0);
      ASSERT_GT(r->dims[2], 0);
      ASSERT_LE(r->voxelCount(), limits.max_voxels);
      ASSERT_EQ(r->labels.size(), size_t(r->voxelCount())) << "iteration " << it;
    } else {
      ++rejected;
      ASSERT_FALSE(r.message().empty()) << "iteration " << it;
      ASSERT_EQ(r.message().rfind(path + ": ", 0), 0u) << r.message();
      ASSERT_EQ(r.message().find('\n'), std::string::npos) << r.message();
      ASSERT_GT(r.message().size(), path.size() + 2) << "iteration " << it;
    }
  }
  // Both outcomes must occur, or the mutations are not exercising the reader.
  EXPECT_GT(accepted, 0) << extension;
  EXPECT_GT(rejected, 0) << extension;
}

TEST(NiftiFuzzTest, MutatedUncompressedFiles) {
  fuzzSeed(".nii", 20240611u, 2500);
}

TEST(NiftiFuzzTest, MutatedGzipFiles) {
  fuzzSeed(".nii.gz", 7u, 1500);
}

}  // namespace
}  // namespace dentsim
