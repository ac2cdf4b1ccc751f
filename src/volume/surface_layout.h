// Surface-mesh layout shared by the CPU reference mesher and the GPU marching-cubes kernels.
//
// The surface is made per cell block. Block b = (bx,by,bz), each in [0, brickDim], holds the 8^3
// cells whose lower corners are the voxel centres lo + (0..7) with lo = 8b - 1, so its corners lie
// in bricks b-1 and b. Its vertices sit on the lattice edges that its cells cross: edge (p, axis a)
// joins corner p to p + e_a, with p in lo + [0,8]^3 and p_a - lo_a <= 7. The edge's local index is
// ((pz * 9 + py) * 9 + px) * 3 + a (p local), and a block's vertices appear in that order; its
// triangles follow cell order (x fastest) and, within a cell, the case table's order. Every block
// keeps its own copy of the vertices on its faces, computed from the same voxels by the same
// arithmetic, so copies agree to the bit and the surface has no cracks.
//
// A vertex's position is in voxel units of the grid (voxel (i,j,k) has its centre at i+0.5...);
// the renderer maps it to millimetres with the volume's frame. Its normal comes from integer box
// sums of the fill (see docs/MESHING.md), so both meshers compute the same direction exactly.
//
// Only defines, 32-bit scalars and plain structs appear here, so that GLSL compiles it unchanged.
#ifndef DENTSIM_SURFACE_LAYOUT_H
#define DENTSIM_SURFACE_LAYOUT_H

#include "brick_layout.h"

#ifdef __cplusplus
#include <cstdint>
namespace dentsim::layout {
using uint = std::uint32_t;
#ifndef DS_FN
#define DS_FN inline constexpr
#endif
#else
#ifndef DS_FN
#define DS_FN
#endif
#endif

#define DS_MESH_BLOCK_CELLS 8u      // cells per block side
#define DS_MESH_CORNER_DIM 9u       // corner lattice per block side
#define DS_MESH_EDGES 2187u         // 9^3 corners x 3 axes: local edge ids
#define DS_MESH_APRON 5u            // voxels read below lo+1 (and above lo+8) for 216-neighbour normals
#define DS_MESH_LOCAL_DIM 18u       // voxels per side a block reads: 8b-5 .. 8b+12
#define DS_MESH_MAX_TRIANGLES 2560u // 512 cells x at most 5 triangles

// One vertex as the GPU stores it and the renderer reads it.                        size 16
struct MeshVertex {
  float x;      // offset  0: position [voxel units of the grid]
  float y;      // offset  4
  float z;      // offset  8
  uint packed;  // offset 12: bits 0..11 and 12..23 octahedral normal (unorm12 u, v),
                //            bits 24..27 tissue at the surface, 28..31 the tissue across it when
                //            one tissue is meshed and another meets it there (else empty)
};
#define DS_MESH_VERTEX_WORDS 4u

// Normal modes: gradient averaged over side^3 voxel centres (the paper's 8, 64, 216 neighbours).
#define DS_MESH_SIDE_8 2u
#define DS_MESH_SIDE_64 4u
#define DS_MESH_SIDE_216 6u

// Bindings of the mesh kernels (set 0); 0..2 are the brick volume (brick_layout.h).
#define DS_MESH_BINDING_JOBS 3      // MeshJob per workgroup
#define DS_MESH_BINDING_COUNTS 4    // count pass: uvec2 (vertices, triangles) per job
#define DS_MESH_BINDING_SURFACE 5   // emit pass: the slot pool, words
#define DS_MESH_BINDING_CASES 6    // the case table, DS_MESH_CASE_WORDS per configuration
#define DS_MESH_BINDING_COUNT 7

// Case table entry: word 0 the triangle count, then two triangles per word, 12 bits each, as three
// 4-bit cell-edge indices (edges 0..3 along x from corners 0,2,4,6; 4..7 along y from 0,1,4,5;
// 8..11 along z from 0,1,2,3; corner c sits at (c & 1, c >> 1 & 1, c >> 2 & 1)).
#define DS_MESH_CASE_WORDS 8u

#define DS_MESH_GROUP_SIZE 512u     // one invocation per cell

// One block to mesh.                                                                 size 16
struct MeshJob {
  uint block;        // offset  0: bx | by << 10 | bz << 20 (each <= 1024)
  uint slotWord;     // offset  4: first word of the block's slot in the pool (emit pass)
  uint vertexCount;  // offset  8: vertices the count pass found (emit pass checks it)
  uint indexWord;    // offset 12: first word of the block's indices, after its vertices
};

// Push constants of surface_count and surface_emit.                                 size 32
struct MeshParams {
  GridInfo grid;     // offset  0
  uint jobCount;     // offset 16: jobs in this dispatch
  uint tissue;       // offset 20: 0: every tissue counts as solid; else only this material
  uint reserved;     // offset 24: 0 (the emit pass takes the normal box side as specialization constant 1)
  uint firstJob;     // offset 28: job of workgroup 0
};

DS_FN uint meshBlockPack(uint bx, uint by, uint bz) { return bx | (by << 10u) | (bz << 20u); }
DS_FN uint meshBlockX(uint b) { return b & 1023u; }
DS_FN uint meshBlockY(uint b) { return (b >> 10u) & 1023u; }
DS_FN uint meshBlockZ(uint b) { return b >> 20u; }

// Tissue/across bits of MeshVertex.packed.
DS_FN uint meshVertexTissue(uint packed) { return (packed >> 24u) & 15u; }
DS_FN uint meshVertexAcross(uint packed) { return packed >> 28u; }

#ifdef __cplusplus
static_assert(sizeof(MeshVertex) == 16, "MeshVertex layout is pinned for GLSL and the renderer");
static_assert(sizeof(MeshJob) == 16, "MeshJob layout is pinned for GLSL");
static_assert(sizeof(MeshParams) == 32, "MeshParams layout is pinned for GLSL");
}  // namespace dentsim::layout
#endif

#endif  // DENTSIM_SURFACE_LAYOUT_H
