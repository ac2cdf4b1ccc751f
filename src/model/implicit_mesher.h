// Marching tetrahedra: the closed, welded, outward triangle surface of a sampled scalar field's zero set.
//
// Entry points:
//   SampleGrid            a regular lattice of nodes in mm
//   sampleField()         a field's values at every node (x fastest, then y, then z)
//   meshZeroSet()         the surface {value = 0} of the piecewise-linear field on the Kuhn tetrahedra
//
// Conventions: a node is inside when its value is < 0 (zero and positive are outside). Each cube
// of the lattice is cut into the same six tetrahedra around its (0,0,0)-(1,1,1) diagonal, so that
// neighbouring cubes cut their shared face along the same diagonal and the surface is watertight.
// Nodes on the lattice's outer layer always count as outside, so the surface is always closed.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "core/triangle_mesh.h"

namespace dentsim {

// A regular lattice of sample nodes.
struct SampleGrid {
  Vec3d origin{0, 0, 0};          // position of node (0,0,0) [mm]
  double spacing = 0.1;           // distance between neighbouring nodes [mm], > 0
  std::array<int, 3> nodes{2, 2, 2};  // node count along x, y, z, each >= 2

  size_t nodeCount() const { return size_t(nodes[0]) * size_t(nodes[1]) * size_t(nodes[2]); }
  size_t index(int i, int j, int k) const {
    return (size_t(k) * size_t(nodes[1]) + size_t(j)) * size_t(nodes[0]) + size_t(i);
  }
  Vec3d position(int i, int j, int k) const {
    return {origin[0] + spacing * i, origin[1] + spacing * j, origin[2] + spacing * k};
  }
};

// The lattice with spacing `spacing` [mm] whose nodes cover `box` plus `pad_cells` cells on every side.
SampleGrid gridAround(const Bounds3& box, double spacing, int pad_cells);

// Values of `field` at every node, in SampleGrid::index order. A value that is exactly zero is
// replaced by a tiny positive one, so that a field and its negation never both call a node outside.
std::vector<double> sampleField(const SampleGrid& grid, const std::function<double(const Vec3d&)>& field);

// The zero set of `values` (one per node, SampleGrid::index order) as a welded, closed, 2-manifold
// mesh whose triangles face the positive side. One vertex per crossed lattice edge, placed by
// linear interpolation from the edge's lower-index node; so two value arrays that agree up to sign
// on an edge give bit-identical vertices there. Output is deterministic: cells are visited in
// index order and vertices numbered as first met.
TriangleMesh meshZeroSet(const SampleGrid& grid, std::span<const double> values);

}  // namespace dentsim
