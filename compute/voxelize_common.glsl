// voxelize_common.glsl: push constants and the buffers (set 0) every voxelizer kernel binds.
//
// Include after brick_layout.h and voxelize_layout.h. All voxelizer kernels declare the same
// bindings 0..13 so that the host binds one list for each of them.
#ifndef DENTSIM_VOXELIZE_COMMON_GLSL
#define DENTSIM_VOXELIZE_COMMON_GLSL

layout(push_constant) uniform PushConstants { VoxelizeParams params; };

layout(std430, set = 0, binding = DS_VOX_BINDING_CORNERS) readonly buffer Corners { float corners[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_TRILAYER) readonly buffer TriangleLayers { uint triangleLayer[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_COUNTS) buffer Counts { uint counts[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_OFFSETS) buffer Offsets { uint offsets[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_HITS) buffer Hits { uint hits[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_RAYINFO) buffer RayInfo { uint leakyMask[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_BLOCKS) buffer Blocks { uint blockEntries[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_BRICKS) buffer Bricks { uint brickWords[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_COUNTERS) buffer Counters { uint counters[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_CHUNKS) buffer Chunks { uint chunkEntries[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_PACKED) buffer Packed { uint packedEntries[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_SCANSUMS) buffer ScanSums { uint scanSums[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_DONORS) buffer Donors { uint donors[]; };
layout(std430, set = 0, binding = DS_VOX_BINDING_RASTER) readonly buffer RasterItems { uint rasterItems[]; };

// Counter words.
#define DS_VOX_COUNTER_BRICKS 0
#define DS_VOX_COUNTER_BLOCKS 1
#define DS_VOX_COUNTER_HITS 2

uint bandRayWidth() { return params.rayX1 - params.rayX0; }
uint bandRayCount() { return (params.rayX1 - params.rayX0) * (params.rayY1 - params.rayY0); }
bool rayInBand(uint rx, uint ry) {
  return rx >= params.rayX0 && rx < params.rayX1 && ry >= params.rayY0 && ry < params.rayY1;
}
uint bandRayIndex(uint rx, uint ry) { return (ry - params.rayY0) * bandRayWidth() + (rx - params.rayX0); }

#endif
