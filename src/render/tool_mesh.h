// Tool meshes as the renderer draws them: per-corner normals that stay sharp across creases, and the mirror's glass disc.
#pragma once

#include <vector>

#include "core/triangle_mesh.h"

namespace dentsim::render {

// One corner of a drawn triangle (vertex buffer layout of tool.vert.glsl).          size 24
struct ToolVertex {
  float px, py, pz;  // position, tool frame [mm]
  float nx, ny, nz;  // unit normal, tool frame
};
static_assert(sizeof(ToolVertex) == 24, "tool.vert.glsl reads two vec3 at offsets 0 and 12");

// Three corners per triangle, in the mesh's order. A corner's normal averages (area-weighted) the
// faces around its vertex whose normals lie within crease_deg of its own face's normal, so smooth
// surfaces shade smoothly and the edge of a cap stays sharp. Degenerate faces get their neighbours'.
std::vector<ToolVertex> creasedVertices(const TriangleMesh& mesh, double crease_deg = 40.0);

// A flat disc of radius_mm in the plane z = z_mm, normal +Z, as `segments` (>= 3) triangles fanned
// from the centre, counter-clockwise seen from +Z.
std::vector<ToolVertex> discVertices(double radius_mm, double z_mm, int segments);

}  // namespace dentsim::render
