// What the two CPU meshers share (the reference in surface_mesher.cpp, the fast one in block_mesher.cpp): case table, field table, the one vertex formula.
//
// Both meshers must give the same vertices bit for bit, so the float arithmetic of a vertex (its
// position along the edge, its normal from the integer box sums, the octahedral packing) lives in
// one function, meshVertex, compiled once. The meshers differ only in how they find crossing edges
// and compute the integer sums, which are exact either way.
#pragma once

#include <array>
#include <cstdint>

#include "core/triangle_mesh.h"
#include "volume/brick_volume.h"
#include "volume/surface_layout.h"

namespace dentsim::internal {

// Cube corner c sits at (c & 1, (c >> 1) & 1, (c >> 2) & 1). Edge e joins corner kEdgeCorner[e] to
// that corner plus one step along kEdgeAxis[e]; edges 0..3 run along x, 4..7 along y, 8..11 along z.
inline constexpr std::array<int, 12> kEdgeCorner{0, 2, 4, 6, 0, 1, 4, 5, 0, 1, 2, 3};
inline constexpr std::array<int, 12> kEdgeAxis{0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};

constexpr int cornerBit(int c, int axis) { return (c >> axis) & 1; }

struct CaseEntry {
  uint8_t triangle_count = 0;
  std::array<std::array<uint8_t, 3>, 12> triangles{};  // cell-edge indices, counter-clockwise from outside
};

// The 256 corner configurations (bit c set: corner c inside), generated once from the per-face rule.
const std::array<CaseEntry, 256>& caseTable();

// F per voxel byte: the fill that counts as solid (only `tissue`'s when one is chosen); phi = F / 31.
struct FieldTable {
  std::array<uint32_t, 256> fill{};  // F: the fill that counts as solid
  std::array<bool, 256> inside{};    // 2F > 31: phi > 0.5 exactly, without float rounding
};
FieldTable makeFieldTable(Material tissue);

// The vertex on the lattice edge from voxel centre g (grid voxel coordinates) along `axis`.
//   fa, fb      F at g and at g + e_axis; exactly one of them is inside (2F > 31)
//   n           the integer normal sums (minus the mean gradient, up to a positive factor), see
//               docs/MESHING.md; all zero where the field is flat
//   in, out     the voxel bytes on the inside and outside end of the edge (tissue labels)
//   tissue      Empty for the outer surface, else the tissue meshed alone
//   float_normal, when given, receives the unit normal before packing
layout::MeshVertex meshVertex(const int64_t g[3], int axis, int fa, int fb, const std::array<int64_t, 3>& n, Voxel in,
                              Voxel out, Material tissue, Vec3f* float_normal = nullptr);

}  // namespace dentsim::internal
