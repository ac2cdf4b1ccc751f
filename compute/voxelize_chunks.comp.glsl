// voxelize_chunks.comp.glsl: turns each chunk of the band into a tile or a packed index block.
//
// One workgroup per chunk of the band, 8 entries per invocation. A chunk whose 512 brick entries
// are one and the same tile becomes a chunk tile; any other gets the next packed block slot and
// its entries are copied there. Entries for bricks outside a grid smaller than a chunk are empty.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "brick_layout.h"
#include "voxelize_layout.h"

layout(local_size_x = DS_VOX_GROUP_SIZE) in;

#include "voxelize_common.glsl"

#define ENTRIES_PER_LANE (DS_CHUNK_BRICKS / DS_VOX_GROUP_SIZE)

shared uint chunkFirst;
shared uint chunkSame;
shared uint chunkSlot;

void main() {
  uint chunk = params.firstItem + gl_WorkGroupID.x;
  if (chunk >= params.itemLimit) return;
  uint lane = gl_LocalInvocationID.x;
  uint brickDim = 1u << (params.level - DS_BRICK_LOG2);
  uint entries[ENTRIES_PER_LANE];
  for (uint k = 0u; k < ENTRIES_PER_LANE; ++k) {
    uint i = lane * ENTRIES_PER_LANE + k;
    uvec3 local = uvec3(i & 7u, (i >> 3u) & 7u, i >> 6u);
    bool inside = all(lessThan(local, uvec3(brickDim)));
    entries[k] = inside ? blockEntries[chunk * DS_CHUNK_BRICKS + i] : DS_ENTRY_UNIFORM;
  }
  if (lane == 0u) {
    chunkFirst = entries[0];
    chunkSame = 1u;
  }
  barrier();
  uint first = chunkFirst;
  bool same = (first & DS_ENTRY_UNIFORM) != 0u;
  for (uint k = 0u; k < ENTRIES_PER_LANE; ++k) same = same && entries[k] == first;
  if (!same) atomicAnd(chunkSame, 0u);
  barrier();
  if (chunkSame != 0u) {
    if (lane == 0u) chunkEntries[chunk] = first;
    return;
  }
  if (lane == 0u) chunkSlot = atomicAdd(counters[DS_VOX_COUNTER_BLOCKS], 1u);
  barrier();
  uint slot = chunkSlot;
  for (uint k = 0u; k < ENTRIES_PER_LANE; ++k) packedEntries[slot * DS_CHUNK_BRICKS + lane * ENTRIES_PER_LANE + k] = entries[k];
  if (lane == 0u) chunkEntries[chunk] = slot;
}
