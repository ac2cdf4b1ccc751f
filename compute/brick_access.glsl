// brick_access.glsl: the brick-volume buffers (set 0) and lookups from brick and voxel coordinates to voxels.
//
// Include after brick_layout.h. Every kernel that reads a brick volume binds the three word arrays
// at DS_BINDING_CHUNKS/BLOCKS/BRICKS and receives the grid as a GridInfo in its push constants.
#ifndef DENTSIM_BRICK_ACCESS_GLSL
#define DENTSIM_BRICK_ACCESS_GLSL

layout(std430, set = 0, binding = DS_BINDING_CHUNKS) readonly buffer ChunkTable { uint chunkEntries[]; };
layout(std430, set = 0, binding = DS_BINDING_BLOCKS) readonly buffer BlockTable { uint blockEntries[]; };
layout(std430, set = 0, binding = DS_BINDING_BRICKS) readonly buffer BrickPool { uint brickWords[]; };

// Brick coordinate of linear brick index i (x fastest); brickDim is a power of two.
uvec3 brickCoordFromLinear(uint i, uint brickDim) {
  return uvec3(i % brickDim, (i / brickDim) % brickDim, i / (brickDim * brickDim));
}

// Entry of brick b: a tile (DS_ENTRY_UNIFORM | voxel) when its chunk or the brick itself is uniform,
// else the pool index of its dense brick. Chunk tiles answer after one read, which is how empty and
// solid 64^3 regions cost nothing.
uint brickEntryAt(uvec3 b, GridInfo grid) {
  uvec3 c = b >> DS_CHUNK_LOG2;
  uint chunk = chunkEntries[chunkCoordToIndex(c.x, c.y, c.z, grid.chunkDim)];
  if ((chunk & DS_ENTRY_UNIFORM) != 0u) return chunk;
  uvec3 l = b & uvec3(DS_CHUNK_DIM - 1u);
  return blockEntries[(chunk & DS_ENTRY_INDEX_MASK) * DS_CHUNK_BRICKS + brickCoordToOffset(l.x, l.y, l.z)];
}

bool entryIsTile(uint entry) { return (entry & DS_ENTRY_UNIFORM) != 0u; }
uint tileVoxel(uint entry) { return entry & 0xffu; }

// Voxel at offset o (brickCoordToOffset) of dense brick `brick`: byte (o & 3) of its word o >> 2.
uint denseVoxel(uint brick, uint o) {
  uint word = brickWords[brick * DS_BRICK_WORDS + (o >> 2u)];
  return (word >> ((o & 3u) * 8u)) & 0xffu;
}

// Voxel at p (each coordinate below 2^grid.level).
uint voxelAt(uvec3 p, GridInfo grid) {
  uint entry = brickEntryAt(p >> DS_BRICK_LOG2, grid);
  if (entryIsTile(entry)) return tileVoxel(entry);
  uvec3 l = p & uvec3(DS_BRICK_DIM - 1u);
  return denseVoxel(entry & DS_ENTRY_INDEX_MASK, brickCoordToOffset(l.x, l.y, l.z));
}

#endif  // DENTSIM_BRICK_ACCESS_GLSL
