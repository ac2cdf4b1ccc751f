// Bounded mutation fuzzing of the .dvol reader and the brick-index validation: never crash, always a one-line error or a valid volume.
#include <gtest/gtest.h>

#include <xxhash.h>

#include <cstring>
#include <random>

#include "io/dvol_file.h"
#include "volume/brick_volume.h"
#include "volume/tooth_file.h"
#include "test_support.h"

namespace dentsim {
namespace {

std::vector<uint8_t> seedFile() {
  BrickVolume v(7);
  std::mt19937 rng(5);
  for (int i = 0; i < 400; ++i)
    v.setVoxel(rng() % 128, rng() % 128, rng() % 128, makeVoxel(Material(1 + rng() % 4), 1 + rng() % 31));
  v.compact();
  VolumeFileData d;
  d.frame = VolumeFrame::axisAligned(7, 0.05, {0, 0, 0});
  d.chunks.assign(v.chunkWords().begin(), v.chunkWords().end());
  d.blocks.assign(v.blockWords().begin(), v.blockWords().end());
  d.bricks.assign(v.brickWords().begin(), v.brickWords().end());
  return encodeVolumeFile(d);
}

// Parses and validates like loadTooth() does, from memory.
void parseAndValidate(const std::vector<uint8_t>& bytes) {
  auto file = parseVolumeFile(bytes, "fuzz.dvol", uint64_t{64} << 20);
  if (!file) {
    EXPECT_FALSE(file.message().empty());
    EXPECT_EQ(file.message().find('\n'), std::string::npos);
    return;
  }
  auto v = BrickVolume::fromWords(file->frame.level, file->chunks, file->blocks, file->bricks, "fuzz.dvol");
  if (v) {
    (void)v->materialTotals();  // a volume that validates can be walked entirely
  } else {
    EXPECT_EQ(v.message().rfind("fuzz.dvol: ", 0), 0u);
  }
}

TEST(DvolFuzz, RandomMutationsNeverCrash) {
  const std::vector<uint8_t> seed = seedFile();
  std::mt19937 rng(1234);
  for (int iter = 0; iter < 3000; ++iter) {
    std::vector<uint8_t> b = seed;
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      switch (rng() % 4) {
        case 0: b[rng() % b.size()] ^= uint8_t(1u << (rng() % 8)); break;
        case 1: b.resize(rng() % b.size()); break;
        case 2: b.insert(b.begin() + std::ptrdiff_t(rng() % b.size()), uint8_t(rng())); break;
        default: b[rng() % b.size()] = uint8_t(rng()); break;
      }
      if (b.empty()) b.push_back(0);
    }
    // Half the time repair the header hash so that mutations reach the deeper checks.
    if (iter % 2 == 0 && b.size() >= 224) {
      const uint64_t h = XXH64(b.data(), 216, 0);
      std::memcpy(b.data() + 216, &h, 8);
    }
    parseAndValidate(b);
  }
}

TEST(DvolFuzz, ValidPayloadWithCorruptIndexIsRejectedByLoadTooth) {
  // Build a file whose checksums are right but whose chunk entry points nowhere.
  BrickVolume v(7);
  v.setVoxel(3, 3, 3, makeVoxel(Material::Enamel));
  v.compact();
  VolumeFileData d;
  d.frame = VolumeFrame::axisAligned(7, 0.05, {0, 0, 0});
  d.chunks.assign(v.chunkWords().begin(), v.chunkWords().end());
  d.chunks[0] = 99;
  d.blocks.assign(v.blockWords().begin(), v.blockWords().end());
  d.bricks.assign(v.brickWords().begin(), v.brickWords().end());
  test::TempDir dir;
  ASSERT_TRUE(writeVolumeFile(dir.file("bad.dvol"), d).ok());
  auto t = loadTooth(dir.file("bad.dvol"));
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.message().find("bad.dvol: chunk 0 points at index block 99"), std::string::npos) << t.message();
}

TEST(ToothFile, SaveThenLoadGivesTheSameVoxels) {
  ToothVolume t{VolumeFrame::axisAligned(8, 0.04, {1, 2, 3}), BrickVolume(8)};
  std::mt19937 rng(9);
  for (int i = 0; i < 2000; ++i)
    t.voxels.setVoxel(rng() % 256, rng() % 256, rng() % 256, makeVoxel(Material(1 + rng() % 4), 1 + rng() % 31));
  test::TempDir dir;
  ASSERT_TRUE(saveTooth(dir.file("t.dvol"), t).ok());
  auto back = loadTooth(dir.file("t.dvol"));
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(back->voxels == t.voxels);
  EXPECT_EQ(back->frame.origin_mm, t.frame.origin_mm);
  EXPECT_EQ(back->voxels.materialTotals().fill_sum, t.voxels.materialTotals().fill_sum);
}

}  // namespace
}  // namespace dentsim
