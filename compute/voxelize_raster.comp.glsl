// voxelize_raster.comp.glsl: depth peeling by compute: each triangle finds the rays it crosses, then counts or stores the hits.
//
// One invocation per raster item (firstItem + global id): a triangle and one tile of its rays, so
// that no invocation runs past lavapipe's loop budget. MODE 0 counts hits per ray; MODE 1, run after
// the scan turned counts into write cursors, stores each hit's key at its ray's next slot. The order
// within a ray is arbitrary here; the sort pass orders it.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "brick_layout.h"
#include "voxelize_layout.h"

layout(local_size_x = DS_VOX_GROUP_SIZE) in;
layout(constant_id = 0) const uint MODE = 0u;

#include "voxelize_common.glsl"

void main() {
  uint item = params.firstItem + gl_GlobalInvocationID.x;
  if (item >= params.itemLimit) return;
  uint t = rasterItems[2u * item];
  uint tile = rasterItems[2u * item + 1u];
  uint c = 9u * t;
  float ax = corners[c + 0u], ay = corners[c + 1u], az = corners[c + 2u];
  float bx = corners[c + 3u], by = corners[c + 4u], bz = corners[c + 5u];
  float cx = corners[c + 6u], cy = corners[c + 7u], cz = corners[c + 8u];
  uint x0, x1, y0, y1;
  voxRaySpan(min(ax, min(bx, cx)), max(ax, max(bx, cx)), params.rayX1, x0, x1);
  voxRaySpan(min(ay, min(by, cy)), max(ay, max(by, cy)), params.rayY1, y0, y1);
  // Only this item's tile of the triangle's rays (see DS_VOX_RASTER_TILE).
  uint tileX0 = (tile & 0xffffu) * DS_VOX_RASTER_TILE;
  uint tileY0 = (tile >> 16u) * DS_VOX_RASTER_TILE;
  x0 = max(x0, max(params.rayX0, tileX0));
  y0 = max(y0, max(params.rayY0, tileY0));
  x1 = min(x1, tileX0 + DS_VOX_RASTER_TILE);
  y1 = min(y1, tileY0 + DS_VOX_RASTER_TILE);
  uint layer = triangleLayer[t];
  for (uint y = y0; y < y1; ++y) {
    for (uint x = x0; x < x1; ++x) {
      float depth;
      uint entering;
      if (!voxRayHitsTriangle(ax, ay, az, bx, by, bz, cx, cy, cz, float(x) + 0.5, float(y) + 0.5, depth, entering))
        continue;
      uint r = bandRayIndex(x, y);
      if (MODE == 0u) {
        atomicAdd(counts[r], 1u);
      } else {
        uint slot = atomicAdd(counts[r], 1u);
        hits[slot] = voxHitKey(voxQuantiseDepth(depth, params.level), layer, entering);
      }
    }
  }
}
