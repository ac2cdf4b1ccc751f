// The fast block mesher against the reference meshBlockCpu: same vertices bit for bit, same indices, counts that match.
#include "volume/block_mesher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "volume/volume_fixtures.h"

namespace dentsim {
namespace {

// Random bricks: empty, tiles of each tissue, planes of rising fill through a brick, noise of every
// fill and tissue (including the spare material codes 5..7, which no importer writes but a byte can
// hold), so every corner configuration, tissue pairing and the grid's borders turn up.
BrickVolume randomVolume(int level, uint32_t seed) {
  BrickVolume vol(level);
  std::mt19937 rng(seed);
  const uint32_t bd = vol.brickDim();
  std::array<Voxel, DS_BRICK_VOXELS> buf{};
  for (uint32_t z = 0; z < bd; ++z)
    for (uint32_t y = 0; y < bd; ++y)
      for (uint32_t x = 0; x < bd; ++x) {
        const uint32_t kind = rng() % 6;
        if (kind == 0) continue;
        if (kind == 1) {
          vol.setBrickUniform({x, y, z}, makeVoxel(Material(1 + rng() % 4)));
          continue;
        }
        const double n[3] = {double(rng() % 200) - 100, double(rng() % 200) - 100, double(rng() % 200) - 100};
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) + 1e-9;
        const double off = double(rng() % 80) / 10.0 - 4.0;
        for (uint32_t k = 0; k < 8; ++k)
          for (uint32_t j = 0; j < 8; ++j)
            for (uint32_t i = 0; i < 8; ++i) {
              const double d = ((i - 3.5) * n[0] + (j - 3.5) * n[1] + (k - 3.5) * n[2]) / len - off;
              int fill = int(std::lround(std::clamp(0.5 - d, 0.0, 1.0) * 31.0));
              if (kind == 5) fill = int(rng() % 32);
              const uint32_t material = kind == 5 ? rng() % 8 : 1 + rng() % 4;
              buf[layout::brickCoordToOffset(i, j, k)] = fill ? Voxel(layout::makeVoxel(material, uint32_t(fill))) : Voxel(0);
            }
        vol.setBrick({x, y, z}, buf.data());
      }
  return vol;
}

::testing::AssertionResult sameBlock(const BlockMesh& fast, const BlockMesh& ref) {
  const MeshBlock& b = ref.block;
  const std::string where = "block (" + std::to_string(b.x) + "," + std::to_string(b.y) + "," + std::to_string(b.z) + ")";
  if (!(fast.block == ref.block)) return ::testing::AssertionFailure() << where << ": wrong block";
  if (fast.vertices.size() != ref.vertices.size())
    return ::testing::AssertionFailure() << where << ": " << fast.vertices.size() << " vertices, reference "
                                         << ref.vertices.size();
  for (size_t i = 0; i < ref.vertices.size(); ++i)
    if (std::memcmp(&fast.vertices[i], &ref.vertices[i], sizeof(layout::MeshVertex)) != 0)
      return ::testing::AssertionFailure() << where << ": vertex " << i << " differs: (" << fast.vertices[i].x << ", "
                                           << fast.vertices[i].y << ", " << fast.vertices[i].z << ", " << std::hex
                                           << fast.vertices[i].packed << std::dec << ") against (" << ref.vertices[i].x
                                           << ", " << ref.vertices[i].y << ", " << ref.vertices[i].z << ", " << std::hex
                                           << ref.vertices[i].packed << std::dec << ")";
  if (fast.indices != ref.indices) return ::testing::AssertionFailure() << where << ": indices differ";
  return ::testing::AssertionSuccess();
}

// Every block of the grid (0..brickDim per axis, active or not), meshed both ways and counted.
void expectSameAsReference(const BrickVolume& vol, Material tissue, NormalMode mode) {
  const uint32_t side = normalBoxSide(mode);
  BlockMesher mesher(tissue, side);
  size_t with_surface = 0;
  for (uint32_t z = 0; z <= vol.brickDim(); ++z)
    for (uint32_t y = 0; y <= vol.brickDim(); ++y)
      for (uint32_t x = 0; x <= vol.brickDim(); ++x) {
        const MeshBlock b{x, y, z};
        const BlockMesh ref = meshBlockCpu(vol, b, tissue, side);
        const BlockCounts counts = mesher.count(vol, b);
        EXPECT_EQ(counts.vertices, ref.vertices.size()) << "block " << x << "," << y << "," << z;
        EXPECT_EQ(counts.triangles * 3u, ref.indices.size()) << "block " << x << "," << y << "," << z;
        ASSERT_TRUE(sameBlock(mesher.mesh(vol, b), ref));
        with_surface += !ref.indices.empty();
      }
  EXPECT_GT(with_surface, 10u) << "the volume should hold surface in many blocks";
}

TEST(BlockMesher, EqualsTheReferenceOnRandomBlocksInEveryModeAndTissue) {
  for (uint32_t seed : {11u, 12u}) {
    const BrickVolume vol = randomVolume(5, seed);
    for (NormalMode mode : kNormalModes)
      for (Material tissue : {Material::Empty, Material::Enamel, Material::Dentin, Material::Pulp, Material::Caries}) {
        SCOPED_TRACE("seed " + std::to_string(seed) + ", " + normalModeName(mode) + " normals, tissue " +
                     materialName(tissue));
        expectSameAsReference(vol, tissue, mode);
      }
  }
}

// One solid voxel: its six edges to the neighbours are crossed, and the cells around it close an
// octahedron of 8 triangles. The voxel sits on a block's corner, so several blocks share it.
TEST(BlockMesher, OneFullVoxelCountsAnOctahedron) {
  BrickVolume vol(4);
  vol.setVoxel(7, 7, 7, makeVoxel(Material::Enamel));
  BlockMesher mesher(Material::Empty, DS_MESH_SIDE_8);
  // Voxel 7 is corner 8 of block 0 and corner 0 of block 1 on each axis: block (1,1,1) holds the
  // cells whose lower corner is the voxel itself, and its three edges from it.
  const BlockCounts n = mesher.count(vol, MeshBlock{1, 1, 1});
  EXPECT_EQ(n.vertices, 3u);
  EXPECT_EQ(n.triangles, 1u);
  uint64_t vertices = 0, triangles = 0;
  for (uint32_t z = 0; z <= 2; ++z)
    for (uint32_t y = 0; y <= 2; ++y)
      for (uint32_t x = 0; x <= 2; ++x) {
        const BlockCounts c = mesher.count(vol, MeshBlock{x, y, z});
        vertices += c.vertices;
        triangles += c.triangles;
        EXPECT_TRUE(sameBlock(mesher.mesh(vol, MeshBlock{x, y, z}), meshBlockCpu(vol, {x, y, z}, Material::Empty, 2)));
      }
  EXPECT_EQ(triangles, 8u) << "one octahedron, each face in one cell";
  // The 6 crossed edges, each copied into every block whose corner lattice holds it.
  EXPECT_GE(vertices, 6u);
}

// A block in the middle of a solid or of empty space has nothing to mesh and costs only its corners.
TEST(BlockMesher, UniformRegionsHaveNoSurface) {
  BrickVolume vol(5);
  test::setBox(vol, {0, 0, 0}, {32, 32, 16}, makeVoxel(Material::Dentin));
  BlockMesher mesher(Material::Empty, DS_MESH_SIDE_216);
  EXPECT_EQ(mesher.count(vol, MeshBlock{1, 1, 1}).vertices, 0u);   // inside the slab
  EXPECT_EQ(mesher.count(vol, MeshBlock{1, 1, 3}).vertices, 0u);   // above it
  EXPECT_GT(mesher.count(vol, MeshBlock{1, 1, 2}).triangles, 0u);  // its top face at z = 16
  const BlockMesh none = mesher.mesh(vol, MeshBlock{1, 1, 1});
  EXPECT_TRUE(none.vertices.empty());
  EXPECT_TRUE(none.indices.empty());
}

}  // namespace
}  // namespace dentsim
