// voxelize_sort.comp.glsl: orders each ray's hits by depth and marks the layers whose crossings do not balance.
//
// One invocation per ray of the band. Lists are short (a tooth crosses a ray a dozen times), so an
// insertion sort in place is the fastest choice. A layer whose winding is not back to zero at the
// end of the ray has a hole the ray passed through: its bit is set in leakyMask.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "brick_layout.h"
#include "voxelize_layout.h"

layout(local_size_x = DS_VOX_GROUP_SIZE) in;

#include "voxelize_common.glsl"

void main() {
  uint r = params.firstItem + gl_GlobalInvocationID.x;
  if (r >= params.itemLimit) return;
  uint begin = offsets[r];
  uint end = offsets[r + 1u];
  uint winding = 0u;
  for (uint i = begin; i < end; ++i) {
    uint key = hits[i];
    winding = voxWindingStep(winding, key);
    uint j = i;
    while (j > begin && hits[j - 1u] > key) {
      hits[j] = hits[j - 1u];
      --j;
    }
    hits[j] = key;
  }
  uint mask = 0u;
  for (uint l = 0u; l < DS_VOX_MAX_LAYERS; ++l)
    if (((winding >> (8u * l)) & 0xffu) != 0u) mask |= 1u << l;
  leakyMask[r] = mask;
}
