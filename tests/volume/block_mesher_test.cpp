// The fast block mesher against the reference meshBlockCpu: same vertices bit for bit, same indices, counts that match.
#include "volume/block_mesher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "test_volumes.h"
#include "volume/volume_fixtures.h"

namespace dentsim {
namespace {

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
    const BrickVolume vol = test::randomVolume(5, seed, test::NoiseMaterials::AnyCode);
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
