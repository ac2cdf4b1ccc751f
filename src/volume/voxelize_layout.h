// Mesh voxelizer rules shared by the CPU reference and the GLSL kernels: ray coverage, hit keys, push constants.
//
// Both implementations include this header, so the decisions that must agree bit for bit (which
// triangle covers a ray, at what quantised depth, and how a voxel's coverage becomes a fill) are
// one piece of code. Only 32-bit scalars, plain structs and functions of scalars appear here.
#ifndef DENTSIM_VOXELIZE_LAYOUT_H
#define DENTSIM_VOXELIZE_LAYOUT_H

#ifdef __cplusplus
#include <cmath>
#include <cstdint>

#include "volume/brick_layout.h"
namespace dentsim::layout {
using uint = std::uint32_t;
using std::ceil;
using std::floor;
#define DS_VFN inline
#define DS_OUT(T) T&
#define DS_PRECISE
#else
#define DS_VFN
#define DS_OUT(T) out T
#define DS_PRECISE precise
#endif

#define DS_VOX_MAX_LAYERS 4u        // tissue layers per voxelization (2 bits in a hit key)
#define DS_VOX_MAX_SUBSAMPLES 4u    // rays per voxel side
#define DS_VOX_DEPTH_BITS 24u       // quantised depth over the grid height
#define DS_VOX_DEPTH_SHIFT 8u
#define DS_VOX_DEPTH_MAX 0xffffffu
#define DS_VOX_NO_HIT 0xffffffffu   // a key past every real hit
#define DS_VOX_GROUP_SIZE 64u       // triangles or rays per workgroup in 1-D passes
#define DS_VOX_SCAN_BLOCK 1024u     // counts reduced per workgroup by the scan

// Bindings of the voxelizer kernels (set 0). Not every kernel binds all of them.
#define DS_VOX_BINDING_CORNERS 0    // float[9 per triangle]
#define DS_VOX_BINDING_TRILAYER 1   // uint per triangle
#define DS_VOX_BINDING_COUNTS 2     // uint per ray: hits (count pass), then the scatter cursor
#define DS_VOX_BINDING_OFFSETS 3    // uint per ray + 1: exclusive prefix sum of counts
#define DS_VOX_BINDING_HITS 4       // uint keys
#define DS_VOX_BINDING_RAYINFO 5    // uint per ray: mask of layers whose hits do not balance
#define DS_VOX_BINDING_BLOCKS 6     // uint[512 per chunk of the band]: brick entries
#define DS_VOX_BINDING_BRICKS 7     // uint[128 per dense brick]
#define DS_VOX_BINDING_COUNTERS 8   // uint[4]: dense bricks, live blocks, spare, spare
#define DS_VOX_BINDING_CHUNKS 9     // uint per chunk of the band: chunk entries
#define DS_VOX_BINDING_PACKED 10    // uint[512 per live block]: blocks packed by the chunk pass
#define DS_VOX_BINDING_SCANSUMS 11  // uint per scan block
#define DS_VOX_BINDING_DONORS 12    // uint per ray: the ray a leaky ray borrows from (see below)
#define DS_VOX_BINDING_RASTER 13    // uint[2 per raster item]: triangle, tile (x | y << 16)
#define DS_VOX_BINDING_COUNT 14

// Work a kernel invocation may do. lavapipe (Mesa's llvmpipe, as in Debian 12) ends every loop of
// an invocation once all its loops together have run 65535 iterations, silently: a large
// triangle's rays past that point got no hit, and a long column's last bricks were painted
// wrongly (at level 12, voxels with a fill but no tissue). So the raster pass takes a triangle a
// tile of rays at a time, and the paint pass a column a segment of bricks at a time, each well
// under that budget on any device.
#define DS_VOX_RASTER_TILE 32u    // rays per side of one raster item's tile
#define DS_VOX_PAINT_SEGMENT 32u  // bricks of a column one paint workgroup visits

// Donor word of a ray: 0 when the ray is balanced; else the valid flag in bit 29, the borrowed
// layer in bits 27..28 and the donor ray's band index in bits 0..26 (all ones: borrow nothing).
#define DS_VOX_DONOR_NONE 0x7ffffffu
#define DS_VOX_DONOR_VALID 0x20000000u

// Push constants of every voxelizer kernel.                                  size 80, align 4
struct VoxelizeParams {
  uint level;          // offset  0: grid 2^level voxels per side
  uint subsamples;     // offset  4: S, rays per voxel side
  uint pad0;           // offset  8
  uint firstItem;      // offset 12: first triangle, ray or workgroup of this dispatch
  uint itemLimit;      // offset 16: one past the last item of the whole pass
  uint rayX0;          // offset 20: ray rectangle of this band, half-open, in grid rays
  uint rayY0;          // offset 24
  uint rayX1;          // offset 28
  uint rayY1;          // offset 32
  uint brickRow0;      // offset 36: first brick row (y) the paint pass visits
  uint brickRows;      // offset 40: brick rows the paint pass visits
  uint brickCapacity;  // offset 44: dense bricks the pool holds
  uint holeRadius;     // offset 48: how far a leaky ray looks for a donor [rays]
  uint layerMaterials; // offset 52: material of layer l in bits 4l..4l+3
  uint pad1;           // offset 56
  uint scanCount;      // offset 60: counts to scan
  uint chunkRow0;      // offset 64: first chunk row of the band
  uint chunkRows;      // offset 68: chunk rows of the band
  uint paintColumn0;   // offset 72: first brick column (x) the paint pass visits
  uint paintColumns;   // offset 76: brick columns (x) the paint pass visits per brick row
};

// ---- hit keys -----------------------------------------------------------------------------------
DS_VFN uint voxHitKey(uint depthQ, uint layer, uint entering) {
  return (depthQ << DS_VOX_DEPTH_SHIFT) | (layer << 1u) | entering;
}
DS_VFN uint voxKeyDepth(uint key) { return key >> DS_VOX_DEPTH_SHIFT; }
DS_VFN uint voxKeyLayer(uint key) { return (key >> 1u) & 3u; }
DS_VFN uint voxKeyEntering(uint key) { return key & 1u; }
// Depth steps per voxel: the grid height spans 2^24 steps.
DS_VFN uint voxDepthPerVoxel(uint level) { return 1u << (DS_VOX_DEPTH_BITS - level); }

// Winding numbers of up to four layers, one signed byte each, packed in one word. A key adds +1
// to its layer when the ray enters and -1 when it leaves; bytes wrap, like int8_t.
DS_VFN uint voxWindingStep(uint winding, uint key) {
  uint shift = 8u * voxKeyLayer(key);
  uint delta = voxKeyEntering(key) != 0u ? 1u : 0xffu;
  uint byteValue = ((winding >> shift) + delta) & 0xffu;
  return (winding & ~(0xffu << shift)) | (byteValue << shift);
}
// Material inside: that of the highest layer whose winding is not zero; 0 (empty) if none.
DS_VFN uint voxMaterialOf(uint winding, uint layerMaterials) {
  for (uint l = DS_VOX_MAX_LAYERS; l > 0u; --l) {
    if (((winding >> (8u * (l - 1u))) & 0xffu) != 0u) return (layerMaterials >> (4u * (l - 1u))) & 15u;
  }
  return 0u;
}

// ---- ray coverage -------------------------------------------------------------------------------
// Edge function of the edge (p,q) at r with the edge's endpoints put in a canonical order
// (lexicographic in x, then y), so both triangles sharing an edge compute the same value; `flip`
// is 1 when the order was swapped. Positive values lie to the left of the canonical direction.
DS_VFN float voxEdge(float px, float py, float qx, float qy, float rx, float ry, DS_OUT(uint) flip) {
  bool swap = (qx < px) || (qx == px && qy < py);
  flip = swap ? 1u : 0u;
  float ax = swap ? qx : px;
  float ay = swap ? qy : py;
  float bx = swap ? px : qx;
  float by = swap ? py : qy;
  DS_PRECISE float e = (bx - ax) * (ry - ay) - (by - ay) * (rx - ax);
  return e;
}

// Whether the ray through (rx, ry) (x and y in rays, z in voxels) crosses the triangle a, b, c, and
// if so at what depth and in which direction. A point exactly on an edge belongs to the triangle
// whose interior lies on the positive side of the canonical edge, which gives every point of a
// closed mesh's projection to exactly one triangle per sheet: the mesh is watertight for rays.
DS_VFN bool voxRayHitsTriangle(float ax, float ay, float az, float bx, float by, float bz, float cx, float cy,
                               float cz, float rx, float ry, DS_OUT(float) depth, DS_OUT(uint) entering) {
  DS_PRECISE float area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  depth = 0.0f;
  entering = 0u;
  if (area == 0.0f) return false;  // seen edge-on: the ray runs along it
  // Counter-clockwise from above means the outward normal points up: the ray leaves there.
  bool ccw = area > 0.0f;
  uint fab;
  uint fbc;
  uint fca;
  float eab = voxEdge(ax, ay, bx, by, rx, ry, fab);
  float ebc = voxEdge(bx, by, cx, cy, rx, ry, fbc);
  float eca = voxEdge(cx, cy, ax, ay, rx, ry, fca);
  // Interior side of each canonical edge: left of the triangle's own direction when ccw.
  bool posAB = (fab == 0u) == ccw;
  bool posBC = (fbc == 0u) == ccw;
  bool posCA = (fca == 0u) == ccw;
  float wab = posAB ? eab : -eab;
  float wbc = posBC ? ebc : -ebc;
  float wca = posCA ? eca : -eca;
  bool inAB = wab > 0.0f || (wab == 0.0f && posAB);
  bool inBC = wbc > 0.0f || (wbc == 0.0f && posBC);
  bool inCA = wca > 0.0f || (wca == 0.0f && posCA);
  if (!(inAB && inBC && inCA)) return false;
  // Barycentric depth: each edge's weight belongs to the opposite corner.
  DS_PRECISE float sum = wab + wbc + wca;
  if (!(sum > 0.0f)) return false;
  DS_PRECISE float z = (wbc * az + wca * bz + wab * cz) / sum;
  depth = z;
  entering = ccw ? 0u : 1u;
  return true;
}

// Quantised depth of z (in voxels) on a grid of 2^level voxels.
DS_VFN uint voxQuantiseDepth(float z, uint level) {
  float steps = z * float(voxDepthPerVoxel(level));
  if (!(steps > 0.0f)) return 0u;
  if (steps >= float(DS_VOX_DEPTH_MAX)) return DS_VOX_DEPTH_MAX;
  return uint(steps);
}

// Rays along one side whose centres (index + 0.5) lie in [lo, hi], clamped to [0, limit):
// first and one-past-last index.
DS_VFN void voxRaySpan(float lo, float hi, uint limit, DS_OUT(uint) first, DS_OUT(uint) last) {
  float f = ceil(lo - 0.5f);
  float l = floor(hi - 0.5f) + 1.0f;
  f = f < 0.0f ? 0.0f : f;
  l = l > float(limit) ? float(limit) : l;
  first = uint(f);
  last = l > f ? uint(l) : first;
}

// Tissue materials from lowest to highest priority, 4 bits each: enamel, dentin, caries, pulp.
#define DS_VOX_PRIORITY_ORDER 0x3421u

// Threshold of an ordered (Bayer-like) 4x4x4 dither at voxel (x,y,z), 0..63. Neighbouring voxels
// get far-apart thresholds, so a boundary's choices interleave finely.
DS_VFN uint voxDither(uint x, uint y, uint z) {
  uint a = x & 1u, c = y & 1u, d = z & 1u;
  uint e = (x >> 1u) & 1u, f = (y >> 1u) & 1u, g = (z >> 1u) & 1u;
  return 8u * (4u * (a ^ c ^ d) + 2u * (c ^ d) + d) + (4u * (e ^ f ^ g) + 2u * (f ^ g) + g);
}

// A voxel from the covered depth of each tissue summed over its S^2 rays. The fill is the covered
// share rounded to 1/31. Where tissues meet inside a voxel, it holds one of them, chosen by its
// share against the dither threshold: a tissue covering 30% of such voxels gets 30% of them, so
// tissue volumes stay unbiased even for thin, curved parts like root canals, where taking the
// largest share would grow the convex side by a few tenths of a percent.
DS_VFN uint voxVoxelFromCoverage(uint cov1, uint cov2, uint cov3, uint cov4, uint full, uint dither) {
  uint total = cov1 + cov2 + cov3 + cov4;
  uint fill = (total * DS_FILL_FULL + full / 2u) / full;
  if (fill == 0u) return 0u;
  uint threshold = dither * total + total / 2u;  // below 64 * total < 2^32
  // The first tissue in DS_VOX_PRIORITY_ORDER (enamel, dentin, caries, pulp) whose cumulative share
  // passes the threshold; pulp, the last, always does (64 * total > 63.5 * total). Straight-line
  // rather than a loop, which on lavapipe would spend the invocation's loop budget (see above).
  uint upToEnamel = cov1;
  uint upToDentin = upToEnamel + cov2;
  uint upToCaries = upToDentin + cov4;
  uint chosen = 64u * upToEnamel > threshold   ? DS_MAT_ENAMEL
                : 64u * upToDentin > threshold ? DS_MAT_DENTIN
                : 64u * upToCaries > threshold ? DS_MAT_CARIES
                                               : DS_MAT_PULP;
  return makeVoxel(chosen, fill > DS_FILL_FULL ? DS_FILL_FULL : fill);
}

#ifdef __cplusplus
static_assert(sizeof(VoxelizeParams) == 80, "VoxelizeParams layout is pinned for GLSL");
}  // namespace dentsim::layout
#undef DS_VFN
#undef DS_OUT
#undef DS_PRECISE
#endif

#endif  // DENTSIM_VOXELIZE_LAYOUT_H
