// PLY reading and writing: triangle meshes with optional per-vertex normals and colours, binary little-endian or ASCII.
//
// The writer emits binary little-endian PLY 1.0:
//   element vertex N: float x, y, z [mm]; float nx, ny, nz (if given); uchar red, green, blue (if given)
//   element face M:   list uchar int vertex_indices (always 3 corners)
// The reader accepts binary little-endian and ASCII PLY 1.0 with exactly the elements "vertex" and then
// "face". Vertex properties are x, y, z (required), nx, ny, nz (all or none) and red, green, blue (all
// or none), in any order; x..nz are float or double, colours uchar. The face element has one list
// property, vertex_indices (or vertex_index), with integer count and index types. Faces with more than
// three corners are triangulated as fans (0, i, i+1), which is right for the convex polygons exporters
// write; faces with fewer than three corners are errors. Big-endian files, other elements and other
// properties are refused with a one-line error naming the file ("tooth.ply: ...").
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "core/triangle_mesh.h"

namespace dentsim {

using Rgb8 = std::array<uint8_t, 3>;  // red, green, blue, 0-255

enum class PlyFormat { BinaryLittleEndian, Ascii };

// What to write. `normals` and `colours` are either empty (the property is left out) or hold one entry
// per position. Indices must be below positions.size(), which must fit an int32.
struct PlyView {
  std::span<const Vec3f> positions;                    // [mm]
  std::span<const Vec3f> normals;                      // unit, or empty
  std::span<const Rgb8> colours;                       // or empty
  std::span<const std::array<uint32_t, 3>> triangles;  // counter-clockwise seen from outside
};

// Budget checked against the header's counts before anything is allocated, so that a forged count
// cannot exhaust memory. A vertex costs up to 27 bytes and a triangle 12 in memory.
struct PlyReadLimits {
  uint64_t max_vertices = 20'000'000;
  uint64_t max_triangles = 40'000'000;  // after fan triangulation
};

// What the reader saw.
struct PlyInfo {
  PlyFormat format = PlyFormat::BinaryLittleEndian;
  uint64_t file_faces = 0;     // faces in the file
  uint64_t polygon_faces = 0;  // faces with more than three corners, split into fans
};

struct PlyMesh {
  TriangleMesh mesh;                          // in the file's own units
  std::optional<std::vector<Vec3f>> normals;  // per vertex, as stored (not renormalized), when present
  std::optional<std::vector<Rgb8>> colours;   // per vertex, when present
  PlyInfo info;
};

// Parses PLY bytes; `where` names the source in errors. Errors are one line: not a PLY, unsupported
// format, element or property, counts over `limits` or larger than the file can hold (checked before
// allocating), truncated or trailing data, NaN or Inf coordinates or normals, indices out of range,
// faces with fewer than three corners, malformed ASCII numbers (naming the line). Never throws.
Result<PlyMesh> parsePly(std::span<const uint8_t> bytes, const std::string& where, const PlyReadLimits& limits = {});
// Reads and parses a file, refusing one larger than an ASCII file within `limits` could be.
Result<PlyMesh> readPly(const std::string& path, const PlyReadLimits& limits = {});

// Binary little-endian PLY bytes of `view`; `comment` (control characters become spaces) goes on a
// "comment" header line when not empty. Size: header + positions * (12 + 12 if normals + 3 if colours)
// + triangles * 13 bytes.
std::vector<uint8_t> encodePlyBinary(const PlyView& view, std::string_view comment = {});
// ASCII PLY text of `view`, floats with %.9g so that they read back bit-exact.
std::string encodePlyAscii(const PlyView& view, std::string_view comment = {});
// Writes binary PLY atomically (temporary file, then rename). Errors: mismatched normal or colour
// counts, an index out of range, too many vertices for int32 indices, I/O.
Status writePly(const std::string& path, const PlyView& view, std::string_view comment = {});

}  // namespace dentsim
