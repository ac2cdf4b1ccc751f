// BlockMesher: row loads from the bricks, 9-bit inside masks per corner row, prefix sums on demand, normals as unrolled box sums.
//
// Contents
//   1. Scratch: the block's voxels, F, corner-row masks, prefix sums
//   2. Loading: rows of words from the 27 bricks a block reads, F of 8 voxels at once
//   3. Masks: crossing edges and mixed cells from the corner rows
//   4. Normals: the reference's box sums over padded prefix sums, unrolled per box side and edge axis
//   5. count, emit, mesh
#include "volume/block_mesher.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstring>

#include "volume/surface_mesher_internal.h"

namespace dentsim {

namespace {

// ==== 1. scratch ==================================================================================
constexpr int kCells = int(DS_MESH_BLOCK_CELLS);      // 8
constexpr int kCorners = int(DS_MESH_CORNER_DIM);     // 9
constexpr int kLocal = int(DS_MESH_LOCAL_DIM);        // 18: local voxels 0..17 are 8b-5 .. 8b+12
constexpr int kCorner0 = int(DS_MESH_APRON) - 1;      // 4: local index of corner 0 (voxel 8b-1)
constexpr int kRowBytes = 24;                         // a voxel row with room for the word written at x 13

// Prefix sums with one zero plane below each axis: padded index = local + 1, 0 .. 18.
constexpr int kSatDim = kLocal + 1;
constexpr int kSatRow = kSatDim + 1;  // padded x row, one spare so rows start 8-byte aligned
constexpr int kSatPlane = kSatRow * kSatDim;
constexpr int kSatStride[3] = {1, kSatRow, kSatPlane};

// Local edge id of cell edge e relative to its cell's lower corner (surface_layout.h's edge order).
constexpr std::array<int, 12> cellEdgeOffsets() {
  std::array<int, 12> off{};
  for (int e = 0; e < 12; ++e) {
    const int c = internal::kEdgeCorner[size_t(e)];
    off[size_t(e)] = (((c >> 2 & 1) * kCorners + (c >> 1 & 1)) * kCorners + (c & 1)) * 3 + internal::kEdgeAxis[size_t(e)];
  }
  return off;
}
constexpr std::array<int, 12> kCellEdgeOffset = cellEdgeOffsets();

}  // namespace

using NormalSumsFn = std::array<int64_t, 3> (*)(const int32_t* sat, const int p[3]);

struct BlockMesher::Scratch {
  Material tissue = Material::Empty;
  std::array<NormalSumsFn, 3> normal_sums{};  // per edge axis, for the chosen box side
  void (*prefix_sums)(Scratch&) = nullptr;     // over as many voxels as that box side reads

  alignas(64) uint8_t voxels[kLocal][kLocal][kRowBytes]{};  // voxel bytes [z][y][x]; x >= 18 don't care
  alignas(64) uint8_t fill[kLocal][kLocal][kRowBytes]{};    // F of each voxel
  uint16_t mask[kCorners][kCorners]{};                      // [cz][cy]: bit cx set when corner (cx,cy,cz) is inside
  alignas(64) int32_t sat[kSatDim * kSatPlane]{};           // inclusive prefix sums of F, padded
  uint16_t vertex_of[DS_MESH_EDGES]{};                      // local edge id -> vertex, for crossed edges
  BrickView views[3][3][3];                                 // bricks b-1 .. b+1, [z][y][x]
};

namespace {

// ==== 2. loading ==================================================================================
// Local coordinate l (0..17) lies in brick slot (l + 3) >> 3 (0: brick b-1, 1: b, 2: b+1) at
// in-brick coordinate (l + 3) & 7.
constexpr int slotOf(int l) { return (l + 3) >> 3; }
constexpr int inBrick(int l) { return (l + 3) & 7; }

void fetchViews(const BrickVolume& vol, MeshBlock b, int slot_lo, int slot_hi, BrickView (&views)[3][3][3]) {
  const int64_t bd = vol.brickDim();
  for (int z = slot_lo; z <= slot_hi; ++z)
    for (int y = slot_lo; y <= slot_hi; ++y)
      for (int x = slot_lo; x <= slot_hi; ++x) {
        const int64_t c[3] = {int64_t(b.x) - 1 + x, int64_t(b.y) - 1 + y, int64_t(b.z) - 1 + z};
        // Outside the grid is empty space: a tile of 0.
        if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= bd || c[1] >= bd || c[2] >= bd)
          views[z][y][x] = BrickView{};
        else
          views[z][y][x] = vol.brick(BrickCoord{uint32_t(c[0]), uint32_t(c[1]), uint32_t(c[2])});
      }
}

// Rows go in 64-bit words, one byte a voxel, x in byte order (a little-endian host).
static_assert(std::endian::native == std::endian::little, "voxel rows are read as little-endian words");
constexpr uint64_t kOnes = 0x0101010101010101ull;

uint64_t loadWord(const uint8_t* p) {
  uint64_t w;
  std::memcpy(&w, p, sizeof w);
  return w;
}
void storeWord(uint8_t* p, uint64_t w) { std::memcpy(p, &w, sizeof w); }

// The 8 voxels of row (y, z) of a brick, in-brick coordinates.
uint64_t brickRow(const BrickView& v, int y, int z) {
  if (v.uniform) return kOnes * v.value;
  return loadWord(v.voxels + layout::brickCoordToOffset(0, uint32_t(y), uint32_t(z)));
}

// F of 8 voxels at once: the fill where the voxel counts as solid (every voxel, or only the meshed
// tissue's), as FieldTable has it.
uint64_t fillWord(uint64_t w, bool all_tissue, uint32_t tissue) {
  const uint64_t fill = w & (kOnes * DS_FILL_MASK);
  if (all_tissue) return fill;
  const uint64_t diff = ((w >> DS_MATERIAL_SHIFT) & (kOnes * 7u)) ^ (kOnes * tissue);  // 0 where the tissue
  const uint64_t other = (diff + kOnes * 0x7fu) & (kOnes * 0x80u);  // bit 7 where diff != 0 (diff <= 7: no carry)
  return fill & (((other >> 7) ^ kOnes) * 0xffu);
}

// Copies the rows of local voxels [lo, hi)^2 in y and z from the bricks, with their F. A row takes
// one word from each brick it crosses: local x 0..4 are in-brick 3..7 of brick b-1, 5..12 brick b,
// 13..17 in-brick 0..4 of b+1 (`right`: read that brick too; the count pass needs x <= 12 only).
// Words overlap and are written left to right; bytes from 18 on are don't-care.
void loadRows(BlockMesher::Scratch& s, int lo, int hi, bool right) {
  const bool all_tissue = s.tissue == Material::Empty;
  const uint32_t tissue = uint32_t(s.tissue);
  for (int z = lo; z < hi; ++z)
    for (int y = lo; y < hi; ++y) {
      const int sy = slotOf(y), sz = slotOf(z), iy = inBrick(y), iz = inBrick(z);
      const uint64_t left = brickRow(s.views[sz][sy][0], iy, iz) >> 24;  // in-brick 3..7 to bytes 0..4
      const uint64_t mid = brickRow(s.views[sz][sy][1], iy, iz);
      uint8_t* row = s.voxels[z][y];
      uint8_t* f = s.fill[z][y];
      storeWord(row, left);
      storeWord(f, fillWord(left, all_tissue, tissue));
      storeWord(row + 5, mid);
      storeWord(f + 5, fillWord(mid, all_tissue, tissue));
      if (right) {
        const uint64_t r = brickRow(s.views[sz][sy][2], iy, iz) & 0xffffffffffull;  // in-brick 0..4
        storeWord(row + 13, r);
        storeWord(f + 13, fillWord(r, all_tissue, tissue));
      }
    }
}

// ==== 3. masks ====================================================================================
// Inside is 2F > 31, i.e. F >= 16: bit 4 of F. Corner x 0..8 are local 4..12.
void buildMasks(BlockMesher::Scratch& s) {
  for (int cz = 0; cz < kCorners; ++cz)
    for (int cy = 0; cy < kCorners; ++cy) {
      const uint8_t* f = s.fill[kCorner0 + cz][kCorner0 + cy] + kCorner0;
      // Bit 4 of each byte to bit 0, then byte i to bit i by one multiplication.
      const uint64_t low = (loadWord(f) >> 4) & kOnes;
      const uint32_t m = uint32_t((low * 0x0102040810204080ull) >> 56) | uint32_t(f[8] >> 4 & 1u) << 8;
      s.mask[cz][cy] = uint16_t(m);
    }
}

// Set bits of a corner-row mask (9 bits), without a library call on hosts lacking POPCNT.
constexpr std::array<uint8_t, 512> kBitCount = [] {
  std::array<uint8_t, 512> t{};
  for (int i = 0; i < 512; ++i) t[size_t(i)] = uint8_t(std::popcount(unsigned(i)));
  return t;
}();

// The crossed edges of corner row (cy, cz), per axis, as bit cx: along x between corners cx and cx+1
// (cx <= 7), along y and z to the next row (none from the last row).
struct RowEdges {
  uint32_t e[3];
  uint32_t any() const { return e[0] | e[1] | e[2]; }
  int count() const { return kBitCount[e[0]] + kBitCount[e[1]] + kBitCount[e[2]]; }
};

RowEdges rowEdges(const BlockMesher::Scratch& s, int cy, int cz) {
  const uint32_t m = s.mask[cz][cy];
  return {{(m ^ (m >> 1)) & 0xffu, cy + 1 < kCorners ? (m ^ s.mask[cz][cy + 1]) & 0x1ffu : 0u,
           cz + 1 < kCorners ? (m ^ s.mask[cz + 1][cy]) & 0x1ffu : 0u}};
}

// Cells of row (cy, cz) whose corners are neither all inside nor all outside, as bit cx.
uint32_t mixedCells(const BlockMesher::Scratch& s, int cy, int cz) {
  const uint32_t m00 = s.mask[cz][cy], m10 = s.mask[cz][cy + 1], m01 = s.mask[cz + 1][cy], m11 = s.mask[cz + 1][cy + 1];
  const uint32_t all = m00 & m10 & m01 & m11, any = m00 | m10 | m01 | m11;
  return ((any | any >> 1) & ~(all & all >> 1)) & 0xffu;
}

// The corner configuration of cell cx in row (cy, cz): bit c for corner (c & 1, c >> 1 & 1, c >> 2 & 1).
uint32_t cellConfig(const BlockMesher::Scratch& s, int cx, int cy, int cz) {
  return (uint32_t(s.mask[cz][cy]) >> cx & 3u) | (uint32_t(s.mask[cz][cy + 1]) >> cx & 3u) << 2 |
         (uint32_t(s.mask[cz + 1][cy]) >> cx & 3u) << 4 | (uint32_t(s.mask[cz + 1][cy + 1]) >> cx & 3u) << 6;
}

// ==== 4. normals ==================================================================================
// The reference (surface_mesher.cpp, normalSums) sums, for component c, over ranges of each axis:
//   Box(range_c + 1, range_u, range_w) - Box(range_c - 1, range_u, range_w)
// with ranges [p-h+1, p+h] along the edge and [p-h, p+h] plus [p-h+1, p+h-1] across it. A box is
// eight prefix-sum reads, so each component is a product of three short lists of (index, sign) and
// the sums are exact integers in any order. Indices below are padded (local + 1).
template <int N>
struct Terms {
  int off[N];   // padded index x stride
  int sign[N];  // +1 or -1
};

template <int H>
Terms<2> boxAlong(int p, int stride) {  // range [p-H+1, p+H]
  return {{(p + H + 1) * stride, (p - H + 1) * stride}, {1, -1}};
}
template <int H>
Terms<4> boxAcross(int p, int stride) {  // ranges [p-H, p+H] and [p-H+1, p+H-1]
  return {{(p + H + 1) * stride, (p - H) * stride, (p + H) * stride, (p - H + 1) * stride}, {1, -1, 1, -1}};
}
template <int H>
Terms<4> diffAlong(int p, int stride) {  // [lo+1, hi+1] minus [lo-1, hi-1] of [p-H+1, p+H]
  return {{(p + H + 2) * stride, (p - H + 2) * stride, (p + H) * stride, (p - H) * stride}, {1, -1, -1, 1}};
}
template <int H>
Terms<8> diffAcross(int p, int stride) {  // the same for both ranges across the edge
  return {{(p + H + 2) * stride, (p - H + 1) * stride, (p + H) * stride, (p - H - 1) * stride, (p + H + 1) * stride,
           (p - H + 2) * stride, (p + H - 1) * stride, (p - H) * stride},
          {1, -1, -1, 1, 1, -1, -1, 1}};
}

template <int H, int Axis, int D>
auto boxTerms(const int p[3]) {
  if constexpr (D == Axis)
    return boxAlong<H>(p[D], kSatStride[D]);
  else
    return boxAcross<H>(p[D], kSatStride[D]);
}
template <int H, int Axis, int D>
auto diffTerms(const int p[3]) {
  if constexpr (D == Axis)
    return diffAlong<H>(p[D], kSatStride[D]);
  else
    return diffAcross<H>(p[D], kSatStride[D]);
}

template <int A, int B, int C>
int32_t tripleSum(const int32_t* sat, const Terms<A>& a, const Terms<B>& b, const Terms<C>& c) {
  // At most 64 reads of sums up to 18^3 x 31: well inside int32.
  int32_t sum = 0;
  for (int i = 0; i < A; ++i)
    for (int j = 0; j < B; ++j) {
      int32_t inner = 0;
      for (int k = 0; k < C; ++k) inner += c.sign[k] * sat[a.off[i] + b.off[j] + c.off[k]];
      sum += a.sign[i] * b.sign[j] * inner;
    }
  return sum;
}

template <int H, int Axis, int C>
int64_t component(const int32_t* sat, const int p[3]) {
  constexpr int U = (C + 1) % 3, W = (C + 2) % 3;
  return tripleSum(sat, diffTerms<H, Axis, C>(p), boxTerms<H, Axis, U>(p), boxTerms<H, Axis, W>(p));
}

// p: the edge's lower voxel, local coordinates (the terms pad them).
template <int H, int Axis>
std::array<int64_t, 3> normalSumsAt(const int32_t* sat, const int p[3]) {
  return {component<H, Axis, 0>(sat, p), component<H, Axis, 1>(sat, p), component<H, Axis, 2>(sat, p)};
}

template <int H>
std::array<NormalSumsFn, 3> normalSumsFor() {
  return {&normalSumsAt<H, 0>, &normalSumsAt<H, 1>, &normalSumsAt<H, 2>};
}

// Inclusive prefix sums of F, along x, then y, then z; the padded planes stay 0. Only local voxels
// 0 .. N-1 are summed: with a box of side 2h the highest sum a normal reads is at local 13 + h
// (vertex corners reach local 12, a box h past it, a difference one more), so N = 14 + h of the 18.
template <int N>
void buildPrefixSums(BlockMesher::Scratch& s) {
  static_assert(N <= kLocal);
  int32_t* sat = s.sat;
  for (int z = 0; z < N; ++z)
    for (int y = 0; y < N; ++y) {
      int32_t* row = sat + (z + 1) * kSatPlane + (y + 1) * kSatRow + 1;
      const uint8_t* f = s.fill[z][y];
      int32_t run = 0;
#pragma GCC unroll 18
      for (int x = 0; x < N; ++x) {
        run += f[x];
        row[x] = run;
      }
    }
  for (int z = 1; z <= N; ++z)
    for (int y = 2; y <= N; ++y) {
      int32_t* row = sat + z * kSatPlane + y * kSatRow;
      const int32_t* below = row - kSatRow;
      for (int x = 1; x <= N; ++x) row[x] += below[x];
    }
  for (int z = 2; z <= N; ++z)
    for (int y = 1; y <= N; ++y) {
      int32_t* row = sat + z * kSatPlane + y * kSatRow;
      const int32_t* below = row - kSatPlane;
      for (int x = 1; x <= N; ++x) row[x] += below[x];
    }
}

}  // namespace

// ==== 5. count, emit, mesh ========================================================================
BlockMesher::BlockMesher(Material tissue, uint32_t side) : s_(std::make_unique<Scratch>()) {
  s_->tissue = tissue;
  switch (side) {
    case DS_MESH_SIDE_8:
      s_->normal_sums = normalSumsFor<1>();
      s_->prefix_sums = &buildPrefixSums<15>;
      break;
    case DS_MESH_SIDE_64:
      s_->normal_sums = normalSumsFor<2>();
      s_->prefix_sums = &buildPrefixSums<16>;
      break;
    case DS_MESH_SIDE_216:
      s_->normal_sums = normalSumsFor<3>();
      s_->prefix_sums = &buildPrefixSums<17>;
      break;
    default: assert(false && "the normal box side is 2, 4 or 6");
  }
}

BlockMesher::~BlockMesher() = default;
BlockMesher::BlockMesher(BlockMesher&&) noexcept = default;
BlockMesher& BlockMesher::operator=(BlockMesher&&) noexcept = default;

BlockCounts BlockMesher::count(const BrickVolume& volume, MeshBlock b) {
  Scratch& s = *s_;
  // The corners are local 4..12: bricks b-1 (its last voxel) and b on each axis.
  fetchViews(volume, b, 0, 1, s.views);
  loadRows(s, kCorner0, kCorner0 + kCorners, /*right=*/false);
  buildMasks(s);
  const auto& table = internal::caseTable();
  BlockCounts n;
  for (int cz = 0; cz < kCorners; ++cz)
    for (int cy = 0; cy < kCorners; ++cy) {
      n.vertices += uint32_t(rowEdges(s, cy, cz).count());
      // A cell row may hold mixed cells while this corner row has no crossed edge of its own.
      if (cy + 1 == kCorners || cz + 1 == kCorners) continue;
      for (uint32_t cells = mixedCells(s, cy, cz); cells; cells &= cells - 1)
        n.triangles += table[cellConfig(s, std::countr_zero(cells), cy, cz)].triangle_count;
    }
  return n;
}

BlockCounts BlockMesher::emit(const BrickVolume& volume, MeshBlock b, layout::MeshVertex* vertices, uint32_t* indices) {
  Scratch& s = *s_;
  fetchViews(volume, b, 0, 2, s.views);
  loadRows(s, 0, kLocal, /*right=*/true);
  buildMasks(s);
  bool crossed = false;
  for (int cz = 0; cz < kCorners && !crossed; ++cz)
    for (int cy = 0; cy < kCorners && !crossed; ++cy) crossed = rowEdges(s, cy, cz).any() != 0;
  if (!crossed) return {};
  s.prefix_sums(s);

  // Vertices in local edge order: corners z, then y, then x, then the axis.
  const int64_t lo[3] = {int64_t(b.x) * kCells - 1, int64_t(b.y) * kCells - 1, int64_t(b.z) * kCells - 1};
  uint32_t nv = 0;
  for (int cz = 0; cz < kCorners; ++cz)
    for (int cy = 0; cy < kCorners; ++cy) {
      const RowEdges edges = rowEdges(s, cy, cz);
      for (uint32_t any = edges.any(); any; any &= any - 1) {
        const int cx = std::countr_zero(any);
        for (int axis = 0; axis < 3; ++axis) {
          if (!(edges.e[axis] >> cx & 1u)) continue;
          const int p[3] = {kCorner0 + cx, kCorner0 + cy, kCorner0 + cz};
          int q[3] = {p[0], p[1], p[2]};
          ++q[axis];
          const int fa = s.fill[p[2]][p[1]][p[0]], fb = s.fill[q[2]][q[1]][q[0]];
          const Voxel va = s.voxels[p[2]][p[1]][p[0]], vb = s.voxels[q[2]][q[1]][q[0]];
          const bool a_in = 2 * fa > int(DS_FILL_FULL);
          const std::array<int64_t, 3> n = s.normal_sums[size_t(axis)](s.sat, p);
          const int64_t g[3] = {lo[0] + cx, lo[1] + cy, lo[2] + cz};
          s.vertex_of[((cz * kCorners + cy) * kCorners + cx) * 3 + axis] = uint16_t(nv);
          vertices[nv++] = internal::meshVertex(g, axis, fa, fb, n, a_in ? va : vb, a_in ? vb : va, s.tissue);
        }
      }
    }

  // Triangles in cell order (x fastest), each cell's in the case table's order.
  const auto& table = internal::caseTable();
  uint32_t ni = 0;
  for (int cz = 0; cz < kCells; ++cz)
    for (int cy = 0; cy < kCells; ++cy)
      for (uint32_t cells = mixedCells(s, cy, cz); cells; cells &= cells - 1) {
        const int cx = std::countr_zero(cells);
        const internal::CaseEntry& entry = table[cellConfig(s, cx, cy, cz)];
        const int base = ((cz * kCorners + cy) * kCorners + cx) * 3;
        for (int t = 0; t < entry.triangle_count; ++t)
          for (int k = 0; k < 3; ++k) indices[ni++] = s.vertex_of[base + kCellEdgeOffset[entry.triangles[size_t(t)][size_t(k)]]];
      }
  return {nv, ni / 3};
}

BlockMesh BlockMesher::mesh(const BrickVolume& volume, MeshBlock b) {
  BlockMesh out;
  out.block = b;
  out.vertices.resize(kMaxBlockVertices);
  out.indices.resize(size_t(kMaxBlockTriangles) * 3u);
  const BlockCounts n = emit(volume, b, out.vertices.data(), out.indices.data());
  out.vertices.resize(n.vertices);
  out.indices.resize(size_t(n.triangles) * 3u);
  return out;
}

}  // namespace dentsim
