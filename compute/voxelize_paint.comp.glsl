// voxelize_paint.comp.glsl: walks the sorted hits of a column of bricks and writes its brick entries and dense bricks.
//
// One workgroup per brick column (8 x 8 voxel columns) and segment of DS_VOX_PAINT_SEGMENT bricks
// up it; each invocation owns one voxel column and its S x S rays. A segment first steps its rays
// past the hits below it, adding up their windings, so it starts as the bricks below left it. Only brick columns under the footprint are visited: the host
// has filled every entry with the empty tile beforehand. The group moves up the column brick by brick. Where no ray
// has a hit before the next brick boundary and every ray is in the same material, the bricks up to
// the next hit are uniform and written as tiles in one step, which is how empty space and the solid
// interior cost almost nothing. Any other brick is painted: each ray adds the length of each
// material span to the voxels it overlaps, and voxVoxelFromCoverage turns the sums into voxels.
// A painted brick whose voxels all came out equal is still stored as a tile.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "brick_layout.h"
#include "voxelize_layout.h"

layout(local_size_x = DS_BRICK_DIM * DS_BRICK_DIM) in;
// S as a constant, so that loops over an invocation's rays unroll and its ray state stays in
// registers; on lavapipe that alone is several times faster than indexing arrays in memory.
layout(constant_id = 1) const uint SUBSAMPLES = 2u;

#include "voxelize_common.glsl"

#define MAX_RAYS (SUBSAMPLES * SUBSAMPLES)

// Per ray of this invocation: own hit range, borrowed hit range, winding, and which layers to skip
// (bits 0..3) and borrow (bits 4..6: layer + 1, or 0).
uint rayNext[MAX_RAYS];
uint rayEnd[MAX_RAYS];
uint borrowNext[MAX_RAYS];
uint borrowEnd[MAX_RAYS];
uint rayWinding[MAX_RAYS];
uint rayFilter[MAX_RAYS];

shared uint groupMinKey;
shared uint groupMaterials;
shared uint groupSame;
shared uint groupSlot;
shared uint brickVoxels[DS_BRICK_VOXELS];  // one voxel a word, so no invocation shares a word

// The ray's next key after skipping filtered ones, or DS_VOX_NO_HIT.
uint peekKey(uint s) {
  uint skip = rayFilter[s];
  uint own = DS_VOX_NO_HIT;
  while (rayNext[s] < rayEnd[s]) {
    uint k = hits[rayNext[s]];
    if (((skip >> voxKeyLayer(k)) & 1u) == 0u) {
      own = k;
      break;
    }
    rayNext[s] += 1u;
  }
  uint borrowed = DS_VOX_NO_HIT;
  uint layerPlusOne = (skip >> 4u) & 7u;
  if (layerPlusOne != 0u) {
    while (borrowNext[s] < borrowEnd[s]) {
      uint k = hits[borrowNext[s]];
      if (voxKeyLayer(k) == layerPlusOne - 1u) {
        borrowed = k;
        break;
      }
      borrowNext[s] += 1u;
    }
  }
  return min(own, borrowed);
}

// Steps past `key`, the value peekKey just returned.
void consumeKey(uint s, uint key) {
  rayWinding[s] = voxWindingStep(rayWinding[s], key);
  if (rayNext[s] < rayEnd[s] && hits[rayNext[s]] == key) rayNext[s] += 1u;
  else borrowNext[s] += 1u;
}

uint bandChunkIndex(uint bx, uint by, uint bz, uint chunkDim) {
  return (bx >> DS_CHUNK_LOG2) + chunkDim * (((by >> DS_CHUNK_LOG2) - params.chunkRow0) + params.chunkRows * (bz >> DS_CHUNK_LOG2));
}

void writeEntry(uint bx, uint by, uint bz, uint chunkDim, uint entry) {
  uint local = brickCoordToOffset(bx & (DS_CHUNK_DIM - 1u), by & (DS_CHUNK_DIM - 1u), bz & (DS_CHUNK_DIM - 1u));
  blockEntries[bandChunkIndex(bx, by, bz, chunkDim) * DS_CHUNK_BRICKS + local] = entry;
}

void paintColumn(uint bx, uint by, uint bzBegin, uint bzEnd) {
  uint brickDim = 1u << (params.level - DS_BRICK_LOG2);
  uint chunkDim = max(1u, brickDim >> DS_CHUNK_LOG2);
  uint lane = gl_LocalInvocationID.x;
  uint lx = lane & (DS_BRICK_DIM - 1u);
  uint ly = lane >> DS_BRICK_LOG2;
  const uint S = SUBSAMPLES;
  const uint rays = MAX_RAYS;
  uint unit = voxDepthPerVoxel(params.level);
  uint full = rays * unit;
  uint materials = params.layerMaterials;

  for (uint s = 0u; s < MAX_RAYS; ++s) {
    rayNext[s] = 0u;
    rayEnd[s] = 0u;
    borrowNext[s] = 0u;
    borrowEnd[s] = 0u;
    rayWinding[s] = 0u;
    rayFilter[s] = 0u;
    uint rx = (bx * DS_BRICK_DIM + lx) * S + s % S;
    uint ry = (by * DS_BRICK_DIM + ly) * S + s / S;
    if (!rayInBand(rx, ry)) continue;
    uint r = bandRayIndex(rx, ry);
    rayNext[s] = offsets[r];
    rayEnd[s] = offsets[r + 1u];
    uint d = donors[r];
    if ((d & DS_VOX_DONOR_VALID) != 0u) {
      uint borrow = (d >> 27u) & 3u;
      rayFilter[s] = leakyMask[r] | ((borrow + 1u) << 4u);
      uint donor = d & DS_VOX_DONOR_NONE;
      if (donor != DS_VOX_DONOR_NONE) {
        borrowNext[s] = offsets[donor];
        borrowEnd[s] = offsets[donor + 1u];
      }
    }
  }

  // The hits below the segment only turn the windings; the bricks below are another group's.
  uint zStart = bzBegin * DS_BRICK_DIM * unit;
  for (uint s = 0u; s < MAX_RAYS; ++s) {
    uint skip = rayFilter[s];
    while (rayNext[s] < rayEnd[s] && voxKeyDepth(hits[rayNext[s]]) < zStart) {
      uint k = hits[rayNext[s]];
      if (((skip >> voxKeyLayer(k)) & 1u) == 0u) rayWinding[s] = voxWindingStep(rayWinding[s], k);
      rayNext[s] += 1u;
    }
    uint layerPlusOne = (skip >> 4u) & 7u;
    while (layerPlusOne != 0u && borrowNext[s] < borrowEnd[s] && voxKeyDepth(hits[borrowNext[s]]) < zStart) {
      uint k = hits[borrowNext[s]];
      if (voxKeyLayer(k) == layerPlusOne - 1u) rayWinding[s] = voxWindingStep(rayWinding[s], k);
      borrowNext[s] += 1u;
    }
  }

  uint bz = bzBegin;
  while (bz < bzEnd) {
    uint minKey = DS_VOX_NO_HIT;
    uint present = 0u;
    for (uint s = 0u; s < rays; ++s) {
      minKey = min(minKey, peekKey(s));
      present |= 1u << voxMaterialOf(rayWinding[s], materials);
    }
    barrier();  // the previous brick's shared values are no longer read
    if (lane == 0u) {
      groupMinKey = DS_VOX_NO_HIT;
      groupMaterials = 0u;
    }
    barrier();
    atomicMin(groupMinKey, minKey);
    atomicOr(groupMaterials, present);
    barrier();
    uint nextKey = groupMinKey;
    uint groupPresent = groupMaterials;
    uint eventBrick = nextKey == DS_VOX_NO_HIT ? bzEnd : min(bzEnd, voxKeyDepth(nextKey) / (unit * DS_BRICK_DIM));
    if (bitCount(groupPresent) == 1 && eventBrick > bz) {
      uint m = uint(findLSB(groupPresent));
      uint tile = DS_ENTRY_UNIFORM | (m == 0u ? 0u : makeVoxel(m, DS_FILL_FULL));
      for (uint b = bz + lane; b < eventBrick; b += DS_BRICK_DIM * DS_BRICK_DIM) writeEntry(bx, by, b, chunkDim, tile);
      bz = eventBrick;
      continue;
    }

    // Paint brick bz: covered depth per voxel and material, summed over this column's rays.
    uint cov[DS_BRICK_DIM * 4u];
    for (uint i = 0u; i < DS_BRICK_DIM * 4u; ++i) cov[i] = 0u;
    uint z0 = bz * DS_BRICK_DIM * unit;
    uint zEnd = z0 + DS_BRICK_DIM * unit;
    for (uint s = 0u; s < rays; ++s) {
      uint pos = z0;
      bool more = true;
      while (more) {
        uint key = peekKey(s);
        uint stop = zEnd;
        more = key != DS_VOX_NO_HIT && voxKeyDepth(key) < zEnd;
        if (more) stop = voxKeyDepth(key);
        uint m = voxMaterialOf(rayWinding[s], materials);
        if (m != 0u && stop > pos) {
          for (uint v = (pos - z0) / unit; v < DS_BRICK_DIM && z0 + v * unit < stop; ++v) {
            uint a = max(pos, z0 + v * unit);
            uint b = min(stop, z0 + (v + 1u) * unit);
            if (b > a) cov[v * 4u + m - 1u] += b - a;
          }
        }
        if (more) {
          pos = stop;
          consumeKey(s, key);
        }
      }
    }
    uint voxels[DS_BRICK_DIM];
    for (uint v = 0u; v < DS_BRICK_DIM; ++v)
      voxels[v] = voxVoxelFromCoverage(cov[v * 4u], cov[v * 4u + 1u], cov[v * 4u + 2u], cov[v * 4u + 3u], full,
                                     voxDither(bx * DS_BRICK_DIM + lx, by * DS_BRICK_DIM + ly, bz * DS_BRICK_DIM + v));

    for (uint v = 0u; v < DS_BRICK_DIM; ++v) brickVoxels[brickCoordToOffset(lx, ly, v)] = voxels[v];
    if (lane == 0u) groupSame = 1u;
    barrier();
    // Each invocation packs two words (8 voxels) and checks them against the first voxel.
    uint first = brickVoxels[0];
    uint words[2];
    bool same = true;
    for (uint w = 0u; w < 2u; ++w) {
      uint base = 4u * (2u * lane + w);
      words[w] = brickVoxels[base] | (brickVoxels[base + 1u] << 8u) | (brickVoxels[base + 2u] << 16u) |
                 (brickVoxels[base + 3u] << 24u);
      same = same && words[w] == first * 0x01010101u;
    }
    if (!same) atomicAnd(groupSame, 0u);
    barrier();
    if (groupSame != 0u) {
      if (lane == 0u) writeEntry(bx, by, bz, chunkDim, DS_ENTRY_UNIFORM | first);
    } else {
      if (lane == 0u) groupSlot = atomicAdd(counters[DS_VOX_COUNTER_BRICKS], 1u);
      barrier();
      uint slot = groupSlot;
      if (slot < params.brickCapacity) {
        brickWords[slot * DS_BRICK_WORDS + 2u * lane] = words[0];
        brickWords[slot * DS_BRICK_WORDS + 2u * lane + 1u] = words[1];
        if (lane == 0u) writeEntry(bx, by, bz, chunkDim, slot);
      } else if (lane == 0u) {
        writeEntry(bx, by, bz, chunkDim, DS_ENTRY_UNIFORM);  // the host sees the overflow and paints again
      }
    }
    bz += 1u;
  }
}

void main() {
  uint item = params.firstItem + gl_WorkGroupID.x;
  if (item >= params.itemLimit) return;  // the whole group leaves together
  uint brickDim = 1u << (params.level - DS_BRICK_LOG2);
  uint segments = (brickDim + DS_VOX_PAINT_SEGMENT - 1u) / DS_VOX_PAINT_SEGMENT;
  uint column = item / segments;
  uint bzBegin = (item % segments) * DS_VOX_PAINT_SEGMENT;
  paintColumn(params.paintColumn0 + column % params.paintColumns, params.brickRow0 + column / params.paintColumns,
              bzBegin, min(brickDim, bzBegin + DS_VOX_PAINT_SEGMENT));
}
