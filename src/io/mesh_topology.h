// Welding and topology checks of triangle meshes: open, non-manifold and inconsistently oriented edges.
#pragma once

#include <cstdint>
#include <string>

#include "core/triangle_mesh.h"

namespace dentsim {

// What analyzeTopology finds. A closed, consistently oriented (watertight) mesh has no open,
// non-manifold or flipped edges.
struct MeshTopology {
  uint64_t edges = 0;              // distinct undirected edges
  uint64_t open_edges = 0;         // edges used by one triangle (a hole's rim)
  uint64_t nonmanifold_edges = 0;  // edges used by three or more triangles
  uint64_t flipped_edges = 0;      // edges two triangles run the same way (inconsistent winding)
  uint64_t degenerate_triangles = 0;  // triangles with a repeated corner index
  double signed_volume_mm3 = 0.0;  // divergence-theorem volume; negative when turned inside out

  bool closed() const { return open_edges == 0 && nonmanifold_edges == 0; }
  bool consistent() const { return flipped_edges == 0; }
  // "outward", "inward" (inside out) or "inconsistent".
  std::string orientation() const;
};

// Merges vertices with bit-identical positions (+0 and -0 are one), as STL repeats every corner,
// and drops triangles that collapse to a repeated corner. Returns the number of triangles dropped.
uint64_t weldVertices(TriangleMesh& mesh);

// Counts edge uses over the mesh's index structure (weld first).
MeshTopology analyzeTopology(const TriangleMesh& mesh);

}  // namespace dentsim
