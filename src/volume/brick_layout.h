// Brick-volume layout shared by C++ and GLSL: constants, GPU structs and the one coordinate-to-offset map.
//
// The CPU mirror and the GPU pool hold the same bytes, as three arrays of 32-bit words:
//   chunks  (chunkDim^3 entries)        one entry per chunk of 8^3 bricks (64^3 voxels)
//   blocks  (blockCount x 512 entries)  brick index blocks, one per chunk that is not uniform
//   bricks  (brickCount x 128 words)    dense bricks of 8^3 one-byte voxels, 4 voxels a word
// An entry with DS_ENTRY_UNIFORM set is a tile: the whole chunk or brick holds the voxel value in
// its low 8 bits and costs no storage. Otherwise its low 31 bits index a block (chunk entries) or a
// brick (block entries). This two-level index is the coarse hierarchy above the bricks: a query
// skips an empty or solid 64^3 region after one read.
//
// A voxel is one byte: the material in bits 5..7 and the fill in bits 0..4, fill/31 of the voxel
// being solid. The value 0 is empty. Fill lets cut surfaces and marching cubes sit below one voxel.
//
// Only defines, 32-bit scalars and plain structs appear here, so that GLSL compiles it unchanged.
#ifndef DENTSIM_BRICK_LAYOUT_H
#define DENTSIM_BRICK_LAYOUT_H

#ifdef __cplusplus
#include <cstdint>
namespace dentsim::layout {
using uint = std::uint32_t;
#define DS_FN inline constexpr
#else
#define DS_FN
#endif

// ---- voxels ---------------------------------------------------------------------------------
#define DS_MATERIAL_SHIFT 5u
#define DS_FILL_MASK 31u          // fill in bits 0..4
#define DS_FILL_FULL 31u          // fill of a wholly solid voxel
#define DS_MATERIAL_COUNT 8u      // materials representable in 3 bits
#define DS_MAT_EMPTY 0u
#define DS_MAT_ENAMEL 1u
#define DS_MAT_DENTIN 2u
#define DS_MAT_PULP 3u
#define DS_MAT_CARIES 4u
#define DS_MAT_NEIGHBOUR 5u       // an adjacent tooth, whole: not the tooth being treated
#define DS_TISSUE_COUNT 6u        // empty + the five tissues above

// ---- bricks, chunks and index entries --------------------------------------------------------
#define DS_BRICK_LOG2 3u          // 8 voxels per brick side
#define DS_BRICK_DIM 8u
#define DS_BRICK_VOXELS 512u
#define DS_BRICK_WORDS 128u       // 32-bit words per dense brick
#define DS_CHUNK_LOG2 3u          // 8 bricks per chunk side
#define DS_CHUNK_DIM 8u
#define DS_CHUNK_BRICKS 512u      // entries per index block
#define DS_CHUNK_VOXEL_LOG2 6u    // 64 voxels per chunk side
#define DS_ENTRY_UNIFORM 0x80000000u
#define DS_ENTRY_INDEX_MASK 0x7fffffffu
#define DS_MIN_LEVEL 3            // one brick
#define DS_MAX_LEVEL 13           // 8192^3 voxels

// ---- compute bindings of a brick volume (descriptor set 0) -----------------------------------
#define DS_BINDING_CHUNKS 0
#define DS_BINDING_BLOCKS 1
#define DS_BINDING_BRICKS 2

// ---- material counts kernel ------------------------------------------------------------------
#define DS_COUNT_GROUP_SIZE 64u   // bricks per workgroup; one invocation per brick
#define DS_BINDING_COUNT_OUT 3

// Grid description pushed to every kernel that reads a brick volume.     size 16, align 4
struct GridInfo {
  uint level;      // offset  0: octree level L, grid 2^L voxels per side
  uint brickDim;   // offset  4: bricks per side, 2^(L-3)
  uint chunkDim;   // offset  8: chunks per side, max(1, 2^(L-6))
  uint brickCount; // offset 12: bricks in the whole grid, brickDim^3
};

// Push constants of material_counts.comp.glsl.                           size 32, align 4
struct MaterialCountParams {
  GridInfo grid;   // offset  0
  uint firstBrick; // offset 16: linear brick index of invocation 0 of this dispatch
  uint brickLimit; // offset 20: one past the last linear brick index to count
  uint pad0;       // offset 24
  uint pad1;       // offset 28
};

// Per workgroup the kernel writes one of these (DS_MATERIAL_COUNT x 2 words):
// fillSum[m] = sum of fill over voxels of material m (at most 64 x 512 x 31 < 2^32),
// voxels[m]  = count of voxels of material m.
#define DS_COUNT_OUT_WORDS (2u * DS_MATERIAL_COUNT)

// ---- voxel encoding --------------------------------------------------------------------------
DS_FN uint voxelMaterial(uint v) { return (v >> DS_MATERIAL_SHIFT) & 7u; }
DS_FN uint voxelFill(uint v) { return v & DS_FILL_MASK; }
DS_FN uint makeVoxel(uint material, uint fill) { return (material << DS_MATERIAL_SHIFT) | fill; }

// ---- coordinates -----------------------------------------------------------------------------
// The one map from a position inside an 8^3 cube to its offset: voxels in a brick and bricks in a
// chunk both use it, x fastest.
DS_FN uint brickCoordToOffset(uint x, uint y, uint z) {
  return x | (y << DS_BRICK_LOG2) | (z << (2u * DS_BRICK_LOG2));
}
// Chunk (cx,cy,cz) to its entry in the chunk table, x fastest.
DS_FN uint chunkCoordToIndex(uint cx, uint cy, uint cz, uint chunkDim) {
  return cx + chunkDim * (cy + chunkDim * cz);
}
// Linear brick index over the whole grid, x fastest, as the count kernel enumerates bricks.
DS_FN uint brickLinearIndex(uint bx, uint by, uint bz, uint brickDim) {
  return bx + brickDim * (by + brickDim * bz);
}

#ifdef __cplusplus
static_assert(sizeof(GridInfo) == 16, "GridInfo layout is pinned for GLSL");
static_assert(sizeof(MaterialCountParams) == 32, "MaterialCountParams layout is pinned for GLSL");
static_assert(DS_BRICK_DIM == DS_CHUNK_DIM, "brickCoordToOffset serves bricks in chunks too");
}  // namespace dentsim::layout
#endif

#endif  // DENTSIM_BRICK_LAYOUT_H
