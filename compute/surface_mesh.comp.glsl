// surface_mesh.comp.glsl: marching cubes over one cell block per workgroup; counts (EMIT = 0) or writes (EMIT = 1) its slot.
//
// The block layout, vertex order and normal rule are in surface_layout.h and docs/MESHING.md; the
// CPU reference is meshBlockCpu in src/volume/surface_mesher.cpp, and this kernel follows it step for
// step so that both give the same vertices in the same order.
//
// Count pass: the 9^3 corner voxels decide which edges cross the surface and each cell's case; the
// workgroup writes (vertices, triangles) for its job. Emit pass: the 18^3 voxels the block reads go
// into shared memory as F (the fill that counts as solid) and are turned into 3-D prefix sums, from
// which every normal is exact integer box sums; vertices get their index by a scan in edge order,
// triangles by a scan in cell order, and both go into the job's slot.
//
// Both passes work on bit masks of corner rows (9 corners along x): a row's inside mask gives its
// crossing edges as a 27-bit mask in edge order, so counting is a popcount, a vertex's index is the
// row's first vertex plus a popcount, and vertex k finds its edge by a search over 81 rows. Shared
// memory is gathered and scattered lane by lane on software devices, so the kernel keeps its
// per-cell and per-vertex reads of it few.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "brick_layout.h"
#include "surface_layout.h"

layout(local_size_x = DS_MESH_GROUP_SIZE, local_size_y = 1, local_size_z = 1) in;
layout(constant_id = 0) const uint EMIT = 0u;
layout(constant_id = 1) const int SIDE = 2;        // emit: normal box side, DS_MESH_SIDE_*

layout(push_constant) uniform PushConstants { MeshParams params; };

#include "brick_access.glsl"

layout(std430, set = 0, binding = DS_MESH_BINDING_JOBS) readonly buffer Jobs { MeshJob jobs[]; };
layout(std430, set = 0, binding = DS_MESH_BINDING_COUNTS) writeonly buffer Counts { uvec2 counts[]; };
layout(std430, set = 0, binding = DS_MESH_BINDING_SURFACE) writeonly buffer Surface { uint surface[]; };
layout(std430, set = 0, binding = DS_MESH_BINDING_CASES) readonly buffer Cases { uint cases[]; };

const uint LD = DS_MESH_LOCAL_DIM;                 // 18 voxels per side
const uint LOCAL_VOXELS = LD * LD * LD;            // 5832
const uint CD = DS_MESH_CORNER_DIM;                // 9 corners per side
const uint CORNERS = CD * CD * CD;                 // 729
const uint C0 = DS_MESH_APRON - 1u;                // local index of corner 0
const uint ROWS = CD * CD;                        // 81 corner rows, row (y, z) = z * 9 + y
const uint GROUP = DS_MESH_GROUP_SIZE;

shared uint sat[LOCAL_VOXELS];                     // emit: F, then inclusive prefix sums
shared uint cornerFill[CORNERS];                   // emit: F of each corner
shared uint rowInside[ROWS];                       // bit x: corner (x, row) is inside
shared uint rowEdges[ROWS];                        // bit 3x + a: the edge from corner (x, row) along a crosses
shared uint rowFirst[ROWS];                        // emit: the row's first vertex
shared uint brickEntries[27];                      // bricks b-1 .. b+1
shared uint scanBuf[GROUP];                        // subgroup totals of a scan
shared uint totals[2];

uvec3 blockCoord;
ivec3 localBase;  // grid voxel of local (0,0,0): 8b - 5

uint countedFill(uint voxel) {
  uint m = voxelMaterial(voxel);
  return (params.tissue == 0u || m == params.tissue) ? voxelFill(voxel) : 0u;
}

// Raw voxel byte at local coordinate l (outside the grid: empty).
uint rawVoxel(ivec3 l) {
  ivec3 g = localBase + l;
  int dim = int(1u << params.grid.level);
  if (any(lessThan(g, ivec3(0))) || any(greaterThanEqual(g, ivec3(dim)))) return 0u;
  ivec3 s = (g >> int(DS_BRICK_LOG2)) - (ivec3(blockCoord) - 1);
  uint entry = brickEntries[(s.z * 3 + s.y) * 3 + s.x];
  if (entryIsTile(entry)) return tileVoxel(entry);
  uvec3 o = uvec3(g) & uvec3(DS_BRICK_DIM - 1u);
  return denseVoxel(entry & DS_ENTRY_INDEX_MASK, brickCoordToOffset(o.x, o.y, o.z));
}

// Where the voxels of local row (y, z) from x0 on lie: a tile's value, or the two words of the dense
// brick row holding them. The row stays inside one brick; bricks outside the grid are empty tiles,
// so the apron needs no bounds checks.
struct RowWords {
  bool tile;
  uint value;   // the tile's F
  uint w0, w1;  // the brick row's voxels 0..3 and 4..7
  uint x;       // brick-local x of x0
};

RowWords rowWords(uint x0, uint y, uint z) {
  ivec3 g = localBase + ivec3(x0, y, z);
  ivec3 s = (g >> int(DS_BRICK_LOG2)) - (ivec3(blockCoord) - 1);
  uint entry = brickEntries[(s.z * 3 + s.y) * 3 + s.x];
  RowWords r;
  uvec3 o = uvec3(g) & uvec3(DS_BRICK_DIM - 1u);
  r.x = o.x;
  r.tile = entryIsTile(entry);
  r.value = countedFill(tileVoxel(entry));
  r.w0 = 0u;
  r.w1 = 0u;
  if (!r.tile) {
    uint word0 = (entry & DS_ENTRY_INDEX_MASK) * DS_BRICK_WORDS + (brickCoordToOffset(0u, o.y, o.z) >> 2u);
    r.w0 = brickWords[word0];
    r.w1 = brickWords[word0 + 1u];
  }
  return r;
}

// F of the i-th voxel from x0 in the row.
uint rowFill(RowWords r, uint i) {
  if (r.tile) return r.value;
  uint x = r.x + i;
  return countedFill(((x < 4u ? r.w0 : r.w1) >> ((x & 3u) * 8u)) & 0xffu);
}

uint insideMask(uint f, uint x) { return 2u * f > DS_FILL_FULL ? 1u << x : 0u; }

// The crossing edges of corner row `row` as bit 3x + a, from the inside masks: an edge exists in
// the block only while its far corner does, so x-edges stop at x = 7 and rows y = 8 or z = 8 have
// no y- or z-edges.
uint crossingEdges(uint row) {
  uint r = rowInside[row];
  uint y = row % CD, z = row / CD;
  uint ex = (r ^ (r >> 1u)) & 0xffu;
  uint ey = y + 1u < CD ? (r ^ rowInside[row + 1u]) : 0u;
  uint ez = z + 1u < CD ? (r ^ rowInside[row + CD]) : 0u;
  uint m = 0u;
  for (uint x = 0u; x < CD; ++x)
    m |= (((ex >> x) & 1u) | (((ey >> x) & 1u) << 1u) | (((ez >> x) & 1u) << 2u)) << (3u * x);
  return m;
}

// Marching-cubes configuration of cell (x, y, z): bit k for corner (k & 1, k >> 1 & 1, k >> 2 & 1).
uint cellConfig(uvec3 cell) {
  uint row = cell.z * CD + cell.y;
  return ((rowInside[row] >> cell.x) & 3u) | (((rowInside[row + 1u] >> cell.x) & 3u) << 2u) |
         (((rowInside[row + CD] >> cell.x) & 3u) << 4u) | (((rowInside[row + CD + 1u] >> cell.x) & 3u) << 6u);
}

// Exclusive scan of one value per invocation over the workgroup; returns this one's prefix and
// leaves the total in totals[slot]. Subgroups scan themselves; one invocation scans the subgroup
// totals, so the whole scan costs three barriers.
uint exclusiveScan(uint value, uint slot) {
  uint inSubgroup = subgroupExclusiveAdd(value);
  uint subgroupTotal = subgroupAdd(value);
  if (subgroupElect()) scanBuf[gl_SubgroupID] = subgroupTotal;
  barrier();
  if (gl_LocalInvocationID.x == 0u) {
    uint run = 0u;
    for (uint i = 0u; i < gl_NumSubgroups; ++i) {
      uint t = scanBuf[i];
      scanBuf[i] = run;
      run += t;
    }
    totals[slot] = run;
  }
  barrier();
  uint prefix = scanBuf[gl_SubgroupID] + inSubgroup;
  barrier();
  return prefix;
}

// ---- emit-pass helpers -------------------------------------------------------------------------

// Prefix sum at flat local index i; a negative index lies below the block's reads, where the sum is
// 0. The load always reads a valid word and the select drops it, which keeps the code branch-free.
int satAt(int i) {
  int v = int(sat[max(i, 0)]);
  return i < 0 ? 0 : v;
}
// Offset of coordinate `coord` along an axis of stride `stride`; below 0 it poisons the index.
int satOffset(int coord, int stride) { return coord < 0 ? -(1 << 24) : coord * stride; }

// Sums over lists of prefix-sum offsets, with the signs the lists carry (see normalSums): "plain"
// lists are + - + -, "diff" lists + - - +. Scalar and vector arguments only, so that the whole
// normal compiles to straight-line code without local arrays.
int plain4(int o, ivec4 q) { return satAt(o + q.x) - satAt(o + q.y) + satAt(o + q.z) - satAt(o + q.w); }
int diff4(int o, ivec4 q) { return satAt(o + q.x) - satAt(o + q.y) - satAt(o + q.z) + satAt(o + q.w); }
int plainPlain(int o, ivec4 u, ivec4 w) {
  return plain4(o + u.x, w) - plain4(o + u.y, w) + plain4(o + u.z, w) - plain4(o + u.w, w);
}
int diffPlain(int o, ivec4 u, ivec4 w) {
  return plain4(o + u.x, w) - plain4(o + u.y, w) - plain4(o + u.z, w) + plain4(o + u.w, w);
}
int plainDiff(int o, ivec4 u, ivec4 w) {
  return diff4(o + u.x, w) - diff4(o + u.y, w) + diff4(o + u.z, w) - diff4(o + u.w, w);
}

// Offsets of the lists along one axis of stride s about coordinate x.
ivec2 plainEdgeList(int x, int s) { return ivec2(satOffset(x + SIDE / 2, s), satOffset(x - SIDE / 2, s)); }
ivec4 diffEdgeList(int x, int s) {
  const int H = SIDE / 2;
  return ivec4(satOffset(x + H + 1, s), satOffset(x - H + 1, s), satOffset(x + H - 1, s), satOffset(x - H - 1, s));
}
ivec4 plainList(int x, int s) {
  const int H = SIDE / 2;
  return ivec4(satOffset(x + H, s), satOffset(x - H - 1, s), satOffset(x + H - 1, s), satOffset(x - H, s));
}
ivec4 diffListFull(int x, int s) {
  const int H = SIDE / 2;
  return ivec4(satOffset(x + H + 1, s), satOffset(x - H, s), satOffset(x + H - 1, s), satOffset(x - H - 2, s));
}
ivec4 diffListInner(int x, int s) {
  const int H = SIDE / 2;
  return ivec4(satOffset(x + H, s), satOffset(x - H + 1, s), satOffset(x + H - 2, s), satOffset(x - H - 1, s));
}

// The integer normal sums of meshBlockCpu (normalSums): minus this is the normal's direction.
//
// Each box sum of the CPU's formula is 8 signed prefix sums, one corner per axis; gathered per axis,
// a component is a product of per-axis lists of (coordinate, sign), summed over all combinations.
// In a frame whose first axis is the edge's, with H = SIDE / 2 and the edge from p:
//   along the edge, plain:       +(a+H) -(a-H)
//   along the edge, differenced: +(a+H+1) -(a-H+1) -(a+H-1) +(a-H-1)
//   across, plain (full + inner range):       +(u+H) -(u-H-1) +(u+H-1) -(u-H)
//   across, differenced (full + inner range): +(u+H+1) -(u-H) -(u+H-1) +(u-H-2) +(u+H) -(u-H+1) -(u+H-2) +(u-H-1)
// The sums are integers, so their order does not matter and the CPU's box-by-box sums agree exactly.
ivec3 normalSums(ivec3 p, uint axis) {
  uint u = axis == 2u ? 0u : axis + 1u, w = axis == 0u ? 2u : axis - 1u;
  ivec3 stride = ivec3(1, int(LD), int(LD * LD));
  int sa = stride[axis], su = stride[u], sw = stride[w];
  int pa = p[axis], pu = p[u], pw = p[w];
  ivec2 plainA = plainEdgeList(pa, sa);
  ivec4 diffA = diffEdgeList(pa, sa);
  ivec4 plainU = plainList(pu, su), plainW = plainList(pw, sw);

  int nA = plainPlain(diffA.x, plainU, plainW) - plainPlain(diffA.y, plainU, plainW) -
           plainPlain(diffA.z, plainU, plainW) + plainPlain(diffA.w, plainU, plainW);
  ivec4 diffUFull = diffListFull(pu, su), diffUInner = diffListInner(pu, su);
  int nU = diffPlain(plainA.x, diffUFull, plainW) + diffPlain(plainA.x, diffUInner, plainW) -
           diffPlain(plainA.y, diffUFull, plainW) - diffPlain(plainA.y, diffUInner, plainW);
  ivec4 diffWFull = diffListFull(pw, sw), diffWInner = diffListInner(pw, sw);
  int nW = plainDiff(plainA.x, plainU, diffWFull) + plainDiff(plainA.x, plainU, diffWInner) -
           plainDiff(plainA.y, plainU, diffWFull) - plainDiff(plainA.y, plainU, diffWInner);
  ivec3 n;
  n[axis] = nA;
  n[u] = nU;
  n[w] = nW;
  return n;
}

uint packOctahedral(vec3 n) {
  float l1 = abs(n.x) + abs(n.y) + abs(n.z);
  float u = n.x / l1, v = n.y / l1;
  if (n.z < 0.0) {
    float uu = (1.0 - abs(v)) * (u >= 0.0 ? 1.0 : -1.0);
    float vv = (1.0 - abs(u)) * (v >= 0.0 ? 1.0 : -1.0);
    u = uu;
    v = vv;
  }
  uint qu = uint(round(clamp(u * 0.5 + 0.5, 0.0, 1.0) * 4095.0));
  uint qv = uint(round(clamp(v * 0.5 + 0.5, 0.0, 1.0) * 4095.0));
  return qu | (qv << 12u);
}

// Writes vertex `vertex` of the job's slot: the crossing of the edge from corner c along `axis`.
void emitVertex(uint vertex, uint c, uint axis, MeshJob job) {
  if (vertex >= job.vertexCount) return;  // the count pass disagreed: never write past the slot
  uvec3 cc = uvec3(c % CD, (c / CD) % CD, c / (CD * CD));
  ivec3 p = ivec3(cc + C0);
  ivec3 q = p;
  q[axis] += 1;
  uint fa = cornerFill[c];
  uint fb = cornerFill[c + (axis == 0u ? 1u : axis == 1u ? CD : CD * CD)];
  bool aInside = 2u * fa > DS_FILL_FULL;
  precise float t = float(int(DS_FILL_FULL) - 2 * int(fa)) / float(2 * (int(fb) - int(fa)));
  ivec3 g = ivec3(blockCoord) * int(DS_MESH_BLOCK_CELLS) - 1 + ivec3(cc);
  precise vec3 pos = vec3(g) + 0.5;
  pos[axis] = pos[axis] + t;

  ivec3 n = normalSums(p, axis);
  vec3 normal;
  if (n == ivec3(0)) {
    normal = vec3(0.0);
    normal[axis] = aInside ? 1.0 : -1.0;
  } else {
    normal = -normalize(vec3(n));
  }
  uint inVoxel = rawVoxel(aInside ? p : q), outVoxel = rawVoxel(aInside ? q : p);
  uint w = job.slotWord + vertex * DS_MESH_VERTEX_WORDS;
  surface[w + 0u] = floatBitsToUint(pos.x);
  surface[w + 1u] = floatBitsToUint(pos.y);
  surface[w + 2u] = floatBitsToUint(pos.z);
  uint outMaterial = voxelMaterial(outVoxel);
  uint across = (params.tissue != 0u && outMaterial != params.tissue) ? outMaterial : 0u;
  surface[w + 3u] = packOctahedral(normal) | (voxelMaterial(inVoxel) << 24u) | (across << 28u);
}

// Vertex k's edge: the last row whose first vertex is at most k (rows without edges share their
// successor's first vertex and come before it), then the (k - first)-th set bit of its edge mask.
void edgeOfVertex(uint k, out uint corner, out uint axis) {
  uint row = 0u;
  for (uint step = 64u; step > 0u; step >>= 1u)
    if (row + step < ROWS && rowFirst[row + step] <= k) row += step;
  uint j = k - rowFirst[row], m = rowEdges[row], bit = 0u;
  for (uint step = 16u; step > 0u; step >>= 1u)
    if (bit + step < 3u * CD && bitCount(m & ((1u << (bit + step)) - 1u)) <= j) bit += step;
  corner = row * CD + bit / 3u;
  axis = bit % 3u;
}

void main() {
  uint jobIndex = params.firstJob + gl_WorkGroupID.x;
  if (jobIndex >= params.jobCount) return;  // the whole workgroup leaves together
  MeshJob job = jobs[jobIndex];
  uint lane = gl_LocalInvocationID.x;
  blockCoord = uvec3(meshBlockX(job.block), meshBlockY(job.block), meshBlockZ(job.block));
  localBase = ivec3(blockCoord) * int(DS_MESH_BLOCK_CELLS) - int(DS_MESH_APRON);

  if (lane < 27u) {
    ivec3 b = ivec3(blockCoord) - 1 + ivec3(lane % 3u, (lane / 3u) % 3u, lane / 9u);
    bool inGrid = all(greaterThanEqual(b, ivec3(0))) && all(lessThan(b, ivec3(params.grid.brickDim)));
    brickEntries[lane] = inGrid ? brickEntryAt(uvec3(b), params.grid) : (DS_ENTRY_UNIFORM | 0u);
  }
  if (lane < 2u) totals[lane] = 0u;
  barrier();

  // Local x 0..4 lie in brick b-1, 5..12 in brick b, 13..17 in brick b+1.
  const uint segStart[3] = uint[3](0u, DS_MESH_APRON, DS_MESH_APRON + DS_MESH_BLOCK_CELLS);
  const uint segCount[3] = uint[3](DS_MESH_APRON, DS_MESH_BLOCK_CELLS, LD - DS_MESH_APRON - DS_MESH_BLOCK_CELLS);
  if (EMIT != 0u) {
    // One invocation per row of 18 voxels: F, the corners' F and inside mask, and the prefix sum along x.
    if (lane < LD * LD) {
      uint y = lane % LD, z = lane / LD;
      uint base = (z * LD + y) * LD;
      bool cornerRow = y >= C0 && y < C0 + CD && z >= C0 && z < C0 + CD;
      uint row = (z - C0) * CD + (y - C0);
      uint inside = 0u;
      uint run = 0u;
      for (uint seg = 0u; seg < 3u; ++seg) {
        RowWords r = rowWords(segStart[seg], y, z);
        for (uint i = 0u; i < segCount[seg]; ++i) {
          uint x = segStart[seg] + i;
          uint f = rowFill(r, i);
          if (cornerRow && x >= C0 && x < C0 + CD) {
            cornerFill[row * CD + x - C0] = f;
            inside |= insideMask(f, x - C0);
          }
          run += f;
          sat[base + x] = run;
        }
      }
      if (cornerRow) rowInside[row] = inside;
    }
  } else {
    // Corners only: local x 4 (brick b-1) and 5..12 (brick b) of each corner row.
    if (lane < ROWS) {
      uint y = C0 + lane % CD, z = C0 + lane / CD;
      RowWords r0 = rowWords(C0, y, z), r1 = rowWords(DS_MESH_APRON, y, z);
      uint inside = insideMask(rowFill(r0, 0u), 0u);
      for (uint i = 0u; i < DS_MESH_BLOCK_CELLS; ++i) inside |= insideMask(rowFill(r1, i), i + 1u);
      rowInside[lane] = inside;
    }
  }
  barrier();

  uint myEdges = 0u;
  if (lane < ROWS) {
    uint m = crossingEdges(lane);
    if (EMIT != 0u) rowEdges[lane] = m;  // only the emit pass looks edges up again
    myEdges = bitCount(m);
  }
  uvec3 cell = uvec3(lane % DS_MESH_BLOCK_CELLS, (lane / DS_MESH_BLOCK_CELLS) % DS_MESH_BLOCK_CELLS,
                     lane / (DS_MESH_BLOCK_CELLS * DS_MESH_BLOCK_CELLS));
  uint config = cellConfig(cell);
  uint myTriangles = cases[config * DS_MESH_CASE_WORDS];

  if (EMIT == 0u) {
    uint edges = subgroupAdd(myEdges), triangles = subgroupAdd(myTriangles);
    if (subgroupElect()) {
      atomicAdd(totals[0], edges);
      atomicAdd(totals[1], triangles);
    }
    barrier();
    if (lane == 0u) counts[jobIndex] = uvec2(totals[0], totals[1]);
    return;
  }

  // Prefix sums along y, then z; one invocation per line of 18. The scan's first barrier ends the z pass.
  for (uint axis = 1u; axis < 3u; ++axis) {
    if (lane < LD * LD) {
      uint a = lane % LD, b = lane / LD;
      uint stride = axis == 1u ? LD : LD * LD;
      uint start = axis == 1u ? b * LD * LD + a : b * LD + a;
      uint run = sat[start];
      for (uint k = 1u; k < LD; ++k) {
        run += sat[start + k * stride];
        sat[start + k * stride] = run;
      }
    }
    if (axis == 1u) barrier();
  }

  // ---- vertices --------------------------------------------------------------------------------
  uint first = exclusiveScan(myEdges, 0u);
  if (lane < ROWS) rowFirst[lane] = first;
  barrier();
  uint vertexTotal = totals[0];
  // Invocation k computes vertex k, so the normals' box sums fill the first SIMD batches only.
  for (uint k = lane; k < vertexTotal; k += GROUP) {
    uint corner, axis;
    edgeOfVertex(k, corner, axis);
    emitVertex(k, corner, axis, job);
  }

  // ---- triangles -------------------------------------------------------------------------------
  uint triangle = exclusiveScan(myTriangles, 1u);
  for (uint t = 0u; t < myTriangles; ++t) {
    uint tri = (cases[config * DS_MESH_CASE_WORDS + 1u + t / 2u] >> ((t & 1u) * 12u)) & 0xfffu;
    for (uint k = 0u; k < 3u; ++k) {
      uint e = (tri >> (4u * k)) & 15u;
      // Cell edge e: its lower corner and axis (surface_layout.h).
      uint axis = e / 4u;
      uint which = e & 3u;
      uvec3 corner = cell;
      if (axis == 0u) corner += uvec3(0u, which & 1u, which >> 1u);
      else if (axis == 1u) corner += uvec3(which & 1u, 0u, which >> 1u);
      else corner += uvec3(which & 1u, which >> 1u, 0u);
      uint row = corner.z * CD + corner.y, bit = corner.x * 3u + axis;
      uint index = rowFirst[row] + bitCount(rowEdges[row] & ((1u << bit) - 1u));
      surface[job.indexWord + (triangle + t) * 3u + k] = index;
    }
  }
}
