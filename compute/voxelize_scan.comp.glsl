// voxelize_scan.comp.glsl: exclusive prefix sum of the per-ray hit counts, in three phases.
//
// PHASE 0: each workgroup sums DS_VOX_SCAN_BLOCK counts into scanSums[group].
// PHASE 1: one workgroup turns scanSums into exclusive block offsets and stores the total hits.
// PHASE 2: each workgroup scans its block from its offset, writing offsets[] and, as the scatter
//          pass's write cursors, counts[]; offsets[scanCount] receives the total.
// Groups index blocks from firstItem, so a long scan can be split over several dispatches.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "brick_layout.h"
#include "voxelize_layout.h"

#define SCAN_LANES 256u
#define PER_LANE (DS_VOX_SCAN_BLOCK / SCAN_LANES)

layout(local_size_x = SCAN_LANES) in;
layout(constant_id = 0) const uint PHASE = 0u;

#include "voxelize_common.glsl"

shared uint laneSums[SCAN_LANES];

// Exclusive scan of laneSums in place (Hillis-Steele on an inclusive copy); returns the total.
uint scanLanes(uint lane, uint value) {
  laneSums[lane] = value;
  barrier();
  for (uint step = 1u; step < SCAN_LANES; step <<= 1u) {
    uint add = lane >= step ? laneSums[lane - step] : 0u;
    barrier();
    laneSums[lane] += add;
    barrier();
  }
  uint total = laneSums[SCAN_LANES - 1u];
  uint exclusive = laneSums[lane] - value;
  barrier();
  laneSums[lane] = exclusive;
  barrier();
  return total;
}

void main() {
  uint lane = gl_LocalInvocationID.x;
  uint n = params.scanCount;
  if (PHASE == 1u) {
    // Block sums of one band fit one workgroup's loop: at most 2^24 rays / 1024 per block.
    uint blocks = (n + DS_VOX_SCAN_BLOCK - 1u) / DS_VOX_SCAN_BLOCK;
    uint carry = 0u;
    for (uint base = 0u; base < blocks; base += SCAN_LANES) {
      uint i = base + lane;
      uint v = i < blocks ? scanSums[i] : 0u;
      uint total = scanLanes(lane, v);
      if (i < blocks) scanSums[i] = carry + laneSums[lane];
      carry += total;
      barrier();
    }
    if (lane == 0u) {
      offsets[n] = carry;
      counters[DS_VOX_COUNTER_HITS] = carry;
    }
    return;
  }
  uint block = params.firstItem + gl_WorkGroupID.x;
  uint first = block * DS_VOX_SCAN_BLOCK + lane * PER_LANE;
  uint local[PER_LANE];
  uint sum = 0u;
  for (uint k = 0u; k < PER_LANE; ++k) {
    local[k] = first + k < n ? counts[first + k] : 0u;
    sum += local[k];
  }
  uint total = scanLanes(lane, sum);
  if (PHASE == 0u) {
    if (lane == 0u) scanSums[block] = total;
    return;
  }
  uint running = scanSums[block] + laneSums[lane];
  for (uint k = 0u; k < PER_LANE; ++k) {
    if (first + k < n) {
      offsets[first + k] = running;
      counts[first + k] = running;
    }
    running += local[k];
  }
}
