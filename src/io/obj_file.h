// Wavefront OBJ reading: the vertices and faces of a triangle mesh, as tooth libraries export them, every line checked.
//
// The reader takes `v x y z [w]` (w ignored) and `f` with one to three slash-separated indices per
// corner (`7`, `7/3`, `7/3/5`, `7//5`), only the first (the vertex) used; indices count from 1, or
// back from the last vertex read when negative. Faces of more than three corners are split into
// fans (0, i, i+1), right for the convex polygons exporters write. Texture coordinates, normals,
// groups, objects, smoothing, materials, lines and points are skipped, as is any other statement
// (OBJ has many, none of which changes the surface). The file is ASCII; it is read whole within
// the input budget.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "core/result.h"
#include "core/triangle_mesh.h"

namespace dentsim {

// Budget checked while parsing, before each element is stored: a forged file cannot exhaust memory.
struct ObjReadLimits {
  uint64_t max_vertices = 20'000'000;
  uint64_t max_triangles = 40'000'000;  // after fan triangulation
};

struct ObjMesh {
  TriangleMesh mesh;           // in the file's own units, indexed as the file indexes it
  uint64_t file_faces = 0;     // `f` lines
  uint64_t polygon_faces = 0;  // faces of more than three corners, split into fans
};

// Parses OBJ text; `where` names the source in errors. Errors are one line naming the source and
// the line: a malformed or non-finite number, a face with fewer than three corners, an index of 0
// or outside the vertices read so far, counts over `limits`, no triangles, a NUL byte (a binary
// file). Never throws.
Result<ObjMesh> parseObj(std::span<const uint8_t> bytes, const std::string& where, const ObjReadLimits& limits = {});
// Reads and parses a file within the input budget (io/input_budget.h).
Result<ObjMesh> readObj(const std::string& path, const ObjReadLimits& limits = {});

}  // namespace dentsim
