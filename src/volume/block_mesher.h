// BlockMesher: the fast CPU block mesher, giving exactly meshBlockCpu's vertices and triangles, for meshing on CPU threads.
//
// meshBlockCpu is the reference: it reads voxels one by one and tests every edge and cell. The
// BlockMesher finds the same edges and cells from 9-bit inside masks of the block's 81 corner rows
// (as compute/surface_mesh.comp.glsl does), copies the 18^3 voxels it reads in rows from the
// bricks, and builds the prefix sums for the normals only when the block has a vertex. The float
// arithmetic of a vertex is the reference's own (internal::meshVertex), so the output is the same
// bit for bit. Tests compare the two over random blocks (tests/volume/block_mesher_test.cpp).
//
// One BlockMesher holds about 50 KiB of scratch and allocates nothing per block: give each thread
// its own. It never changes the volume, so several may read one volume at once.
#pragma once

#include <cstdint>
#include <memory>

#include "volume/brick_volume.h"
#include "volume/surface_mesher.h"

namespace dentsim {

// A block's share of the surface: what its slot must hold.
struct BlockCounts {
  uint32_t vertices = 0;   // at most kMaxBlockVertices
  uint32_t triangles = 0;  // at most DS_MESH_MAX_TRIANGLES
};

// Worst cases for the caller's buffers: every lattice edge of the block crossed, five triangles a cell.
inline constexpr uint32_t kMaxBlockVertices = 3u * DS_MESH_BLOCK_CELLS * DS_MESH_CORNER_DIM * DS_MESH_CORNER_DIM;
inline constexpr uint32_t kMaxBlockTriangles = DS_MESH_MAX_TRIANGLES;

class BlockMesher {
 public:
  // tissue: Empty for the outer surface, else that tissue alone; side: the normal box side 2, 4 or
  // 6 (normalBoxSide).
  BlockMesher(Material tissue, uint32_t side);
  ~BlockMesher();
  BlockMesher(BlockMesher&&) noexcept;
  BlockMesher& operator=(BlockMesher&&) noexcept;

  // The vertices and triangles block b will have: reads only its 9^3 corner voxels.
  BlockCounts count(const BrickVolume& volume, MeshBlock b);

  // Meshes block b into the caller's buffers, which hold at least count(volume, b) entries
  // (vertices) and 3 x triangles words (indices, local to the block); returns what it wrote.
  BlockCounts emit(const BrickVolume& volume, MeshBlock b, layout::MeshVertex* vertices, uint32_t* indices);

  // emit into a BlockMesh, for tests and callers that keep blocks on the host.
  BlockMesh mesh(const BrickVolume& volume, MeshBlock b);

  struct Scratch;  // voxels, masks and prefix sums of the block at hand (block_mesher.cpp)

 private:
  std::unique_ptr<Scratch> s_;
};

}  // namespace dentsim
