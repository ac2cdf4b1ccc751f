// Tests for src/volume/brick_volume.cpp: voxel and brick access, tiles, compaction, raw-word validation.
#include "volume/brick_volume.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <tuple>

namespace dentsim {
namespace {

using Key = std::tuple<uint32_t, uint32_t, uint32_t>;

Voxel randomVoxel(std::mt19937& rng) {
  const auto m = Material(rng() % DS_TISSUE_COUNT);
  return makeVoxel(m, 1 + rng() % DS_FILL_FULL);
}

TEST(BrickVolume, NewGridIsEmptyAndCostsOneChunkEntry) {
  BrickVolume v(5);
  EXPECT_EQ(v.dim(), 32u);
  EXPECT_EQ(v.brickDim(), 4u);
  EXPECT_EQ(v.chunkDim(), 1u);
  EXPECT_EQ(v.voxel(31, 0, 17), 0);
  const BrickStats s = v.stats();
  EXPECT_EQ(s.chunks, 1u);
  EXPECT_EQ(s.uniform_chunks, 1u);
  EXPECT_EQ(s.dense_bricks, 0u);
  EXPECT_EQ(s.bytes, 4u);  // one chunk entry
}

TEST(BrickVolume, ChunkDimensionsFollowLevel) {
  EXPECT_EQ(BrickVolume(6).chunkDim(), 1u);
  EXPECT_EQ(BrickVolume(7).chunkDim(), 2u);
  EXPECT_EQ(BrickVolume(10).chunkDim(), 16u);
  EXPECT_EQ(BrickVolume(10).gridInfo().brickCount, 128u * 128u * 128u);
}

TEST(BrickVolume, SetVoxelMatchesAMapReference) {
  // Level 7 has 2x2x2 chunks, so writes cross chunk and brick borders.
  BrickVolume v(7);
  std::map<Key, Voxel> ref;
  std::mt19937 rng(7);
  for (int i = 0; i < 20000; ++i) {
    const uint32_t x = rng() % 128, y = rng() % 128, z = rng() % 128;
    const Voxel val = (rng() % 4 == 0) ? Voxel(0) : randomVoxel(rng);
    v.setVoxel(x, y, z, val);
    ref[{x, y, z}] = val;
  }
  for (const auto& [k, val] : ref) ASSERT_EQ(v.voxel(std::get<0>(k), std::get<1>(k), std::get<2>(k)), val);
  v.compact();
  for (const auto& [k, val] : ref) ASSERT_EQ(v.voxel(std::get<0>(k), std::get<1>(k), std::get<2>(k)), val);
  const Key corner{127, 127, 127};
  EXPECT_EQ(v.voxel(127, 127, 127), ref.count(corner) ? ref[corner] : Voxel(0));
}

TEST(BrickVolume, UniformBrickBecomesATileAndFreesStorage) {
  BrickVolume v(4);  // 2x2x2 bricks
  std::array<Voxel, DS_BRICK_VOXELS> voxels{};
  voxels.fill(makeVoxel(Material::Dentin));
  voxels[5] = makeVoxel(Material::Enamel);
  v.setBrick({1, 0, 1}, voxels.data());
  EXPECT_EQ(v.stats().dense_bricks, 1u);
  voxels[5] = makeVoxel(Material::Dentin);
  v.setBrick({1, 0, 1}, voxels.data());
  const BrickStats s = v.stats();
  EXPECT_EQ(s.dense_bricks, 0u);
  EXPECT_EQ(s.uniform_bricks, 8u);  // all 8 bricks of the one block are tiles
  EXPECT_EQ(v.voxel(8, 0, 8), makeVoxel(Material::Dentin));
  EXPECT_EQ(v.voxel(0, 0, 0), 0);
}

TEST(BrickVolume, MaterialTotalsCountedByHand) {
  BrickVolume v(7);
  // One uniform chunk of enamel: 64^3 voxels, full.
  for (uint32_t bz = 0; bz < 8; ++bz)
    for (uint32_t by = 0; by < 8; ++by)
      for (uint32_t bx = 0; bx < 8; ++bx) v.setBrickUniform({bx, by, bz}, makeVoxel(Material::Enamel));
  v.compact();
  EXPECT_EQ(v.stats().uniform_chunks, 8u);  // the enamel chunk collapsed to a tile
  // Two caries voxels at fill 10 and 31, and one pulp voxel replacing enamel.
  v.setVoxel(100, 100, 100, makeVoxel(Material::Caries, 10));
  v.setVoxel(101, 100, 100, makeVoxel(Material::Caries, 31));
  v.setVoxel(3, 3, 3, makeVoxel(Material::Pulp, 31));
  const MaterialTotals t = v.materialTotals();
  EXPECT_EQ(t.voxels[DS_MAT_ENAMEL], 64u * 64u * 64u - 1u);
  EXPECT_EQ(t.fill_sum[DS_MAT_ENAMEL], (64u * 64u * 64u - 1u) * 31u);
  EXPECT_EQ(t.voxels[DS_MAT_CARIES], 2u);
  EXPECT_EQ(t.fill_sum[DS_MAT_CARIES], 41u);
  EXPECT_EQ(t.voxels[DS_MAT_PULP], 1u);
  EXPECT_EQ(t.voxels[DS_MAT_EMPTY], 128u * 128u * 128u - 64u * 64u * 64u - 2u);
  EXPECT_DOUBLE_EQ(t.volumeMm3(Material::Caries, 0.5), 41.0 / 31.0 * 0.125);
}

TEST(BrickVolume, CompactGivesTheSameWordsWhateverTheWriteOrder) {
  BrickVolume a(7), b(7);
  std::vector<std::pair<Key, Voxel>> writes;
  std::mt19937 rng(3);
  for (int i = 0; i < 3000; ++i) writes.push_back({{rng() % 128, rng() % 128, rng() % 128}, randomVoxel(rng)});
  // Later writes win, so keep only the last per voxel before reversing.
  std::map<Key, Voxel> last;
  for (auto& [k, val] : writes) last[k] = val;
  for (auto& [k, val] : last) a.setVoxel(std::get<0>(k), std::get<1>(k), std::get<2>(k), val);
  for (auto it = last.rbegin(); it != last.rend(); ++it)
    b.setVoxel(std::get<0>(it->first), std::get<1>(it->first), std::get<2>(it->first), it->second);
  a.compact();
  b.compact();
  EXPECT_TRUE(a == b);
  EXPECT_TRUE(std::ranges::equal(a.chunkWords(), b.chunkWords()));
  EXPECT_TRUE(std::ranges::equal(a.blockWords(), b.blockWords()));
  EXPECT_TRUE(std::ranges::equal(a.brickWords(), b.brickWords()));
}

TEST(BrickVolume, CompactCollapsesAChunkBackToATile) {
  BrickVolume v(8);
  v.setVoxel(70, 5, 5, makeVoxel(Material::Enamel));
  v.setVoxel(70, 5, 5, 0);  // back to empty: the brick is dense but uniform
  EXPECT_EQ(v.stats().blocks, 1u);
  v.compact();
  const BrickStats s = v.stats();
  EXPECT_EQ(s.blocks, 0u);
  EXPECT_EQ(s.dense_bricks, 0u);
  EXPECT_EQ(s.bytes, 64u * 4u);  // the 4x4x4 chunk table alone
  EXPECT_TRUE(v.blockWords().empty());
}

TEST(BrickVolume, FromWordsAcceptsItsOwnWords) {
  BrickVolume v(7);
  std::mt19937 rng(11);
  for (int i = 0; i < 500; ++i) v.setVoxel(rng() % 128, rng() % 128, rng() % 128, randomVoxel(rng));
  v.compact();
  auto copy = [](std::span<const uint32_t> s) { return std::vector<uint32_t>(s.begin(), s.end()); };
  auto back = BrickVolume::fromWords(7, copy(v.chunkWords()), copy(v.blockWords()), copy(v.brickWords()), "t");
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_TRUE(*back == v);
}

TEST(BrickVolume, FromWordsRejectsBadEntries) {
  BrickVolume v(7);
  v.setVoxel(1, 2, 3, makeVoxel(Material::Enamel));
  v.compact();
  auto copy = [](std::span<const uint32_t> s) { return std::vector<uint32_t>(s.begin(), s.end()); };
  {  // chunk pointing past the blocks
    auto c = copy(v.chunkWords());
    c[0] = 5;
    auto r = BrickVolume::fromWords(7, c, copy(v.blockWords()), copy(v.brickWords()), "f.dvol");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.message().find("f.dvol: chunk 0 points at index block 5"), std::string::npos) << r.message();
  }
  {  // two chunks sharing one block
    auto c = copy(v.chunkWords());
    c[1] = c[0];
    EXPECT_FALSE(BrickVolume::fromWords(7, c, copy(v.blockWords()), copy(v.brickWords()), "f").ok());
  }
  {  // an empty voxel with fill
    auto b = copy(v.brickWords());
    b[0] = 0x01010101u;
    auto r = BrickVolume::fromWords(7, copy(v.chunkWords()), copy(v.blockWords()), b, "f");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.message().find("invalid voxel code 1"), std::string::npos) << r.message();
  }
  {  // a tile entry with stray bits
    auto c = copy(v.chunkWords());
    c[3] = DS_ENTRY_UNIFORM | 0x100u;
    EXPECT_FALSE(BrickVolume::fromWords(7, c, copy(v.blockWords()), copy(v.brickWords()), "f").ok());
  }
  // wrong chunk count, bad level, an unreferenced brick
  EXPECT_FALSE(BrickVolume::fromWords(8, copy(v.chunkWords()), copy(v.blockWords()), copy(v.brickWords()), "f").ok());
  EXPECT_FALSE(BrickVolume::fromWords(2, {}, {}, {}, "f").ok());
  auto extra = copy(v.brickWords());
  extra.resize(extra.size() + DS_BRICK_WORDS, 0);
  EXPECT_FALSE(BrickVolume::fromWords(7, copy(v.chunkWords()), copy(v.blockWords()), extra, "f").ok());
}

TEST(BrickVolume, ForEachDenseBrickVisitsEachDenseBrickOnce) {
  BrickVolume v(8);
  v.setVoxel(0, 0, 0, makeVoxel(Material::Pulp));
  v.setVoxel(255, 255, 255, makeVoxel(Material::Pulp));
  v.setVoxel(1, 1, 1, makeVoxel(Material::Pulp));  // same brick as the first
  int seen = 0;
  v.forEachDenseBrick([&](const BrickView& b) {
    EXPECT_FALSE(b.uniform);
    EXPECT_TRUE((b.coord.x == 0 && b.coord.z == 0) || (b.coord.x == 31 && b.coord.z == 31));
    ++seen;
  });
  EXPECT_EQ(seen, 2);
}

TEST(BrickVolume, MaterialNamesRoundTrip) {
  for (uint32_t m = 0; m < DS_TISSUE_COUNT; ++m) {
    Material parsed{};
    ASSERT_TRUE(parseMaterial(materialName(Material(m)), &parsed));
    EXPECT_EQ(uint32_t(parsed), m);
  }
  Material unused{};
  EXPECT_FALSE(parseMaterial("bone", &unused));
}

}  // namespace
}  // namespace dentsim
