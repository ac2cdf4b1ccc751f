// surface_mesh.comp.glsl: marching cubes over one cell block per workgroup; counts (EMIT = 0) or writes (EMIT = 1) its slot.
//
// The block layout, vertex order and normal rule are in surface_layout.h and docs/MESHING.md; the
// CPU reference is meshBlockCpu in src/volume/surface_mesher.cpp, and this kernel follows it step for
// step so that both give the same vertices in the same order.
//
// Count pass: the 9^3 corner voxels decide which edges cross the surface and each cell's case; the
// workgroup writes (vertices, triangles) for its job. Emit pass: the 18^3 voxels the block reads go
// into shared memory as F (the fill that counts as solid) and are turned into 3-D prefix sums, from
// which every normal is a handful of exact integer box sums; vertices get their index by a scan in
// edge order, triangles by a scan in cell order, and both go into the job's slot.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "brick_layout.h"
#include "surface_layout.h"

layout(local_size_x = DS_MESH_GROUP_SIZE, local_size_y = 1, local_size_z = 1) in;
layout(constant_id = 0) const uint EMIT = 0u;

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
const uint GROUP = DS_MESH_GROUP_SIZE;

shared uint sat[LOCAL_VOXELS];                     // emit: F, then inclusive prefix sums
shared uint cornerFill[(CORNERS + 3u) / 4u];       // F of each corner, one byte each
shared uint vertexIndex[(DS_MESH_EDGES + 1u) / 2u];  // emit: vertex of each edge, 16 bits each
shared uint brickEntries[27];                      // bricks b-1 .. b+1
shared uint scanBuf[GROUP];
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

uint cornerF(uint c) { return (cornerFill[c >> 2u] >> ((c & 3u) * 8u)) & 0xffu; }
bool cornerInside(uint c) { return 2u * cornerF(c) > DS_FILL_FULL; }
uint cornerIndex(uvec3 c) { return (c.z * CD + c.y) * CD + c.x; }

// Whether the edge from corner c along `axis` exists in this block and crosses the surface.
bool edgeCrosses(uvec3 c, uint axis) {
  if (c[axis] >= DS_MESH_BLOCK_CELLS) return false;
  uvec3 q = c;
  q[axis] += 1u;
  return cornerInside(cornerIndex(c)) != cornerInside(cornerIndex(q));
}

uint cellConfig(uvec3 cell) {
  uint config = 0u;
  for (uint k = 0u; k < 8u; ++k) {
    uvec3 c = cell + uvec3(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
    if (cornerInside(cornerIndex(c))) config |= 1u << k;
  }
  return config;
}

// Exclusive scan of one value per invocation over the workgroup; returns this one's prefix and
// leaves the total in totals[slot]. Subgroups scan themselves; one invocation scans the subgroup
// totals (at most 64 of them), so the whole scan costs three barriers.
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

uint satAt(int x, int y, int z) { return sat[(uint(z) * LD + uint(y)) * LD + uint(x)]; }

// Sum of F over the inclusive local box [lo, hi].
int boxSum(ivec3 lo, ivec3 hi) {
  int sum = 0;
  for (int k = 0; k < 8; ++k) {
    ivec3 p = ivec3((k & 1) != 0 ? hi.x : lo.x - 1, (k & 2) != 0 ? hi.y : lo.y - 1, (k & 4) != 0 ? hi.z : lo.z - 1);
    if (any(lessThan(p, ivec3(0)))) continue;
    int lows = ((k & 1) != 0 ? 0 : 1) + ((k & 2) != 0 ? 0 : 1) + ((k & 4) != 0 ? 0 : 1);
    int v = int(satAt(p.x, p.y, p.z));
    sum += (lows & 1) != 0 ? -v : v;
  }
  return sum;
}

// The integer normal sums of meshBlockCpu (normalSums): minus this is the normal's direction.
ivec3 normalSums(ivec3 p, uint axis, int side) {
  int h = side / 2;
  ivec3 lo0, hi0, lo1, hi1;  // full and inner ranges per axis
  ivec3 count;
  for (uint d = 0u; d < 3u; ++d) {
    if (d == axis) {
      lo0[d] = p[d] - h + 1; hi0[d] = p[d] + h;
      lo1[d] = lo0[d]; hi1[d] = hi0[d];
      count[d] = 1;
    } else {
      lo0[d] = p[d] - h; hi0[d] = p[d] + h;
      lo1[d] = p[d] - h + 1; hi1[d] = p[d] + h - 1;
      count[d] = 2;
    }
  }
  ivec3 n = ivec3(0);
  for (uint c = 0u; c < 3u; ++c) {
    uint u = (c + 1u) % 3u, w = (c + 2u) % 3u;
    int sum = 0;
    for (int rc = 0; rc < count[c]; ++rc)
      for (int ru = 0; ru < count[u]; ++ru)
        for (int rw = 0; rw < count[w]; ++rw) {
          ivec3 lo, hi;
          lo[u] = ru == 0 ? lo0[u] : lo1[u];
          hi[u] = ru == 0 ? hi0[u] : hi1[u];
          lo[w] = rw == 0 ? lo0[w] : lo1[w];
          hi[w] = rw == 0 ? hi0[w] : hi1[w];
          lo[c] = (rc == 0 ? lo0[c] : lo1[c]) + 1;
          hi[c] = (rc == 0 ? hi0[c] : hi1[c]) + 1;
          int plus = boxSum(lo, hi);
          lo[c] -= 2;
          hi[c] -= 2;
          sum += plus - boxSum(lo, hi);
        }
    n[c] = sum;
  }
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
  uint fa = cornerF(c);
  uvec3 cq = cc;
  cq[axis] += 1u;
  uint fb = cornerF(cornerIndex(cq));
  bool aInside = 2u * fa > DS_FILL_FULL;
  precise float t = float(int(DS_FILL_FULL) - 2 * int(fa)) / float(2 * (int(fb) - int(fa)));
  ivec3 g = ivec3(blockCoord) * int(DS_MESH_BLOCK_CELLS) - 1 + ivec3(cc);
  precise vec3 pos = vec3(g) + 0.5;
  pos[axis] = pos[axis] + t;

  ivec3 n = normalSums(p, axis, int(params.side));
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
  for (uint i = lane; i < (CORNERS + 3u) / 4u; i += GROUP) cornerFill[i] = 0u;
  if (lane < 2u) totals[lane] = 0u;
  barrier();

  // Local x 0..4 lie in brick b-1, 5..12 in brick b, 13..17 in brick b+1.
  const uint segStart[3] = uint[3](0u, DS_MESH_APRON, DS_MESH_APRON + DS_MESH_BLOCK_CELLS);
  const uint segCount[3] = uint[3](DS_MESH_APRON, DS_MESH_BLOCK_CELLS, LD - DS_MESH_APRON - DS_MESH_BLOCK_CELLS);
  if (EMIT != 0u) {
    for (uint i = lane; i < (DS_MESH_EDGES + 1u) / 2u; i += GROUP) vertexIndex[i] = 0u;
    // One invocation per row of 18 voxels: F, the corners' bytes, and the prefix sum along x.
    if (lane < LD * LD) {
      uint y = lane % LD, z = lane / LD;
      uint base = (z * LD + y) * LD;
      bool cornerRow = y >= C0 && y < C0 + CD && z >= C0 && z < C0 + CD;
      uint run = 0u;
      for (uint seg = 0u; seg < 3u; ++seg) {
        RowWords r = rowWords(segStart[seg], y, z);
        for (uint i = 0u; i < segCount[seg]; ++i) {
          uint x = segStart[seg] + i;
          uint f = rowFill(r, i);
          if (cornerRow && x >= C0 && x < C0 + CD) {
            uint c = cornerIndex(uvec3(x, y, z) - C0);
            atomicOr(cornerFill[c >> 2u], f << ((c & 3u) * 8u));
          }
          run += f;
          sat[base + x] = run;
        }
      }
    }
    barrier();
    // Prefix sums along y, then z; one invocation per line of 18.
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
      barrier();
    }
  } else {
    // Corners only: local x 4 (brick b-1) and 5..12 (brick b) of each corner row.
    if (lane < CD * CD) {
      uint y = C0 + lane % CD, z = C0 + lane / CD;
      for (uint seg = 0u; seg < 2u; ++seg) {
        uint x0 = seg == 0u ? C0 : DS_MESH_APRON;
        uint n = seg == 0u ? 1u : DS_MESH_BLOCK_CELLS;
        RowWords r = rowWords(x0, y, z);
        for (uint i = 0u; i < n; ++i) {
          uint c = cornerIndex(uvec3(x0 + i, y, z) - C0);
          atomicOr(cornerFill[c >> 2u], rowFill(r, i) << ((c & 3u) * 8u));
        }
      }
    }
    barrier();
  }

  // Each invocation owns a contiguous run of corners, so a scan over invocations is edge order.
  uint cornerBegin = lane * CORNERS / GROUP, cornerEnd = (lane + 1u) * CORNERS / GROUP;
  uint myEdges = 0u;
  for (uint c = cornerBegin; c < cornerEnd; ++c) {
    uvec3 cc = uvec3(c % CD, (c / CD) % CD, c / (CD * CD));
    for (uint axis = 0u; axis < 3u; ++axis)
      if (edgeCrosses(cc, axis)) ++myEdges;
  }
  uvec3 cell = uvec3(lane % DS_MESH_BLOCK_CELLS, (lane / DS_MESH_BLOCK_CELLS) % DS_MESH_BLOCK_CELLS,
                     lane / (DS_MESH_BLOCK_CELLS * DS_MESH_BLOCK_CELLS));
  uint config = cellConfig(cell);
  uint myTriangles = cases[config * DS_MESH_CASE_WORDS];

  if (EMIT == 0u) {
    atomicAdd(totals[0], myEdges);
    atomicAdd(totals[1], myTriangles);
    barrier();
    if (lane == 0u) counts[jobIndex] = uvec2(totals[0], totals[1]);
    return;
  }

  // ---- vertices --------------------------------------------------------------------------------
  uint vertex = exclusiveScan(myEdges, 0u);
  uint vertexTotal = totals[0];
  for (uint c = cornerBegin, v = vertex; c < cornerEnd; ++c) {
    uvec3 cc = uvec3(c % CD, (c / CD) % CD, c / (CD * CD));
    for (uint axis = 0u; axis < 3u; ++axis)
      if (edgeCrosses(cc, axis)) {
        uint edge = c * 3u + axis;
        atomicOr(vertexIndex[edge >> 1u], v << ((edge & 1u) * 16u));
        ++v;
      }
  }
  // Vertices are few and scattered over the corners; computing each where its corner lies would
  // run the normal's box sums in nearly every SIMD batch. Instead the edges are listed in vertex
  // order (16 bits each in scanBuf, a round of up to 2 x GROUP at a time) and invocation k
  // computes vertex k: the work fills the first batches only.
  const uint ROUND = 2u * GROUP;
  for (uint first = 0u; first < vertexTotal; first += ROUND) {
    barrier();
    scanBuf[lane] = 0u;
    barrier();
    for (uint c = cornerBegin, v = vertex; c < cornerEnd; ++c) {
      uvec3 cc = uvec3(c % CD, (c / CD) % CD, c / (CD * CD));
      for (uint axis = 0u; axis < 3u; ++axis)
        if (edgeCrosses(cc, axis)) {
          if (v >= first && v < first + ROUND)
            atomicOr(scanBuf[(v - first) >> 1u], (c * 3u + axis) << (((v - first) & 1u) * 16u));
          ++v;
        }
    }
    barrier();
    for (uint k = lane; k < min(vertexTotal - first, ROUND); k += GROUP) {
      uint edge = (scanBuf[k >> 1u] >> ((k & 1u) * 16u)) & 0xffffu;
      emitVertex(first + k, edge / 3u, edge % 3u, job);
    }
  }
  barrier();

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
      uint edge = cornerIndex(corner) * 3u + axis;
      uint index = (vertexIndex[edge >> 1u] >> ((edge & 1u) * 16u)) & 0xffffu;
      surface[job.indexWord + (triangle + t) * 3u + k] = index;
    }
  }
}
