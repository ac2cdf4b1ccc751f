// material_counts.comp.glsl: voxel count and fill sum per material over a brick volume, one record per workgroup.
//
// One invocation per brick: linear brick index firstBrick + gl_GlobalInvocationID.x (x fastest), up
// to brickLimit. Each workgroup reduces its bricks in shared memory and writes DS_COUNT_OUT_WORDS
// words (fillSum[8], then voxels[8]) at record firstBrick / groupSize + gl_WorkGroupID.x; the CPU sums
// the records in 64 bits, so no atomics are needed. firstBrick is a multiple of the group size.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "brick_layout.h"

layout(local_size_x = DS_COUNT_GROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(push_constant) uniform PushConstants { MaterialCountParams params; };

#include "brick_access.glsl"

layout(std430, set = 0, binding = DS_BINDING_COUNT_OUT) writeonly buffer CountOut { uint countRecords[]; };

// Per material and invocation: fill sum and voxel count of that invocation's brick.
shared uint sharedFill[DS_MATERIAL_COUNT][DS_COUNT_GROUP_SIZE];
shared uint sharedVoxels[DS_MATERIAL_COUNT][DS_COUNT_GROUP_SIZE];

void main() {
  uint lane = gl_LocalInvocationID.x;
  for (uint m = 0u; m < DS_MATERIAL_COUNT; ++m) {
    sharedFill[m][lane] = 0u;
    sharedVoxels[m][lane] = 0u;
  }

  // Invocations past the end still take part in the barrier below, so none returns early.
  uint brick = params.firstBrick + gl_GlobalInvocationID.x;
  if (brick < params.brickLimit && brick < params.grid.brickCount) {
    uint entry = brickEntryAt(brickCoordFromLinear(brick, params.grid.brickDim), params.grid);
    if (entryIsTile(entry)) {
      uint v = tileVoxel(entry);
      uint m = voxelMaterial(v);
      sharedFill[m][lane] = DS_BRICK_VOXELS * voxelFill(v);
      sharedVoxels[m][lane] = DS_BRICK_VOXELS;
    } else {
      uint base = (entry & DS_ENTRY_INDEX_MASK) * DS_BRICK_WORDS;
      for (uint w = 0u; w < DS_BRICK_WORDS; ++w) {
        uint word = brickWords[base + w];
        for (uint k = 0u; k < 4u; ++k) {
          uint v = (word >> (8u * k)) & 0xffu;
          uint m = voxelMaterial(v);
          sharedFill[m][lane] += voxelFill(v);
          sharedVoxels[m][lane] += 1u;
        }
      }
    }
  }
  barrier();

  // Lanes 0..7 sum the fill of material `lane`, lanes 8..15 the voxel count of material lane - 8.
  if (lane < DS_COUNT_OUT_WORDS) {
    uint m = lane % DS_MATERIAL_COUNT;
    bool voxels = lane >= DS_MATERIAL_COUNT;
    uint sum = 0u;
    for (uint i = 0u; i < gl_WorkGroupSize.x; ++i) sum += voxels ? sharedVoxels[m][i] : sharedFill[m][i];
    uint record = params.firstBrick / gl_WorkGroupSize.x + gl_WorkGroupID.x;
    countRecords[record * DS_COUNT_OUT_WORDS + lane] = sum;
  }
}
