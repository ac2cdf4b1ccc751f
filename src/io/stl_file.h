// STL reading and writing (binary and ASCII): size checks, NaN rejection, vertex welding and a topology report.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "core/triangle_mesh.h"
#include "io/mesh_topology.h"

namespace dentsim {

enum class StlFormat { Binary, Ascii };

// Budget checked before anything is allocated, so a hostile header cannot exhaust memory.
struct StlReadLimits {
  uint64_t max_triangles = 20'000'000;  // about 1 GB of binary STL
};

// What the reader saw, for warnings and `dentsim voxelize`'s report.
struct StlInfo {
  StlFormat format = StlFormat::Binary;
  std::string solid_name;           // ASCII "solid NAME" or the binary header's text, trimmed
  uint64_t file_triangles = 0;      // facets in the file
  uint64_t dropped_triangles = 0;   // facets that collapsed when corners were welded
  MeshTopology topology;            // after welding
};

struct StlMesh {
  TriangleMesh mesh;  // welded, in the file's own units
  StlInfo info;
};

// Parses STL bytes; `where` names the source in errors ("enamel.stl"). The file is binary when its
// size is exactly 84 + 50 n for the count n at offset 80 (whatever its header says), else ASCII when
// it starts with "solid". Facet normals are ignored: the corner order gives the orientation. Errors
// are one line: size/count mismatch, over limits.max_triangles (checked before allocating), NaN or
// Inf corners (naming the triangle, or the line in ASCII), no triangles, malformed ASCII (naming the
// line). Never throws.
Result<StlMesh> parseStl(std::span<const uint8_t> bytes, const std::string& where,
                         const StlReadLimits& limits = {});
// Reads and parses a file; refuses files larger than an ASCII file of limits.max_triangles could be.
Result<StlMesh> readStl(const std::string& path, const StlReadLimits& limits = {});

// Binary STL bytes of a mesh (84 + 50 * triangleCount()); `header` fills the 80-byte header (cut or
// padded with zeros). Each facet normal is the unit normal of its corners, zero for no area.
std::vector<uint8_t> encodeStlBinary(const TriangleMesh& mesh, std::string_view header);
// ASCII STL text of a mesh ("solid NAME" ... "endsolid NAME"), corners with %.9g so that they read
// back bit-exact; control characters in `name` become spaces.
std::string encodeStlAscii(const TriangleMesh& mesh, std::string_view name);
// Writes binary STL atomically (temporary file, then rename).
Status writeStl(const std::string& path, const TriangleMesh& mesh, std::string_view header);

}  // namespace dentsim
