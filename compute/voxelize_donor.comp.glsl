// voxelize_donor.comp.glsl: a leaky ray finds the nearest balanced ray to borrow its highest-priority leaky layer from.
//
// One invocation per ray of the band. Rings of growing Chebyshev radius, each scanned row by row,
// exactly as the CPU reference does; a ray outside the band's footprint has no hits and counts as
// balanced, so it donates nothing. The band carries holeRadius rows of halo, so the rays it paints
// see the same neighbours as on the CPU.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "brick_layout.h"
#include "voxelize_layout.h"

layout(local_size_x = DS_VOX_GROUP_SIZE) in;

#include "voxelize_common.glsl"

void main() {
  uint r = params.firstItem + gl_GlobalInvocationID.x;
  if (r >= params.itemLimit) return;
  uint mask = leakyMask[r];
  if (mask == 0u) {
    donors[r] = 0u;
    return;
  }
  uint borrow = uint(findMSB(mask));
  uint w = bandRayWidth();
  int x = int(params.rayX0 + r % w);
  int y = int(params.rayY0 + r / w);
  uint donor = DS_VOX_DONOR_NONE;
  int radius = int(params.holeRadius);
  bool found = false;
  for (int ring = 1; ring <= radius && !found; ++ring) {
    for (int dy = -ring; dy <= ring && !found; ++dy) {
      for (int dx = -ring; dx <= ring && !found; ++dx) {
        if (max(abs(dx), abs(dy)) != ring) continue;
        int cx = x + dx;
        int cy = y + dy;
        if (cx < 0 || cy < 0 || !rayInBand(uint(cx), uint(cy))) {
          found = true;  // no hits out there: balanced, and nothing to borrow
        } else {
          uint c = bandRayIndex(uint(cx), uint(cy));
          if (((leakyMask[c] >> borrow) & 1u) == 0u) {
            donor = c;
            found = true;
          }
        }
      }
    }
  }
  donors[r] = DS_VOX_DONOR_VALID | (borrow << 27u) | donor;
}
