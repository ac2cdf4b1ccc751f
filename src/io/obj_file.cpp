// Wavefront OBJ reading: a line at a time, each number and index checked, counts held to the limits before storing (io/obj_file.h).
#include "io/obj_file.h"

#include <charconv>
#include <cmath>
#include <string_view>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_budget.h"
#include "io/parse_guard.h"

namespace dentsim {
namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// The next token of `line` from `at`, skipping spaces; empty at the end.
std::string_view nextToken(std::string_view line, size_t& at) {
  while (at < line.size() && isSpace(line[at])) ++at;
  const size_t start = at;
  while (at < line.size() && !isSpace(line[at])) ++at;
  return line.substr(start, at - start);
}

std::string lineError(const std::string& where, uint64_t line, const std::string& what) {
  return where + ": line " + std::to_string(line) + ": " + what;
}

// The whole token as a finite number; false otherwise.
bool parseNumber(std::string_view token, double& out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);  // from_chars takes no '+'
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), out);
  return ec == std::errc() && end == token.data() + token.size() && std::isfinite(out);
}

// A corner's vertex index: the digits before the first '/', as written (1-based, or negative).
bool parseIndex(std::string_view token, int64_t& out) {
  token = token.substr(0, token.find('/'));
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), out);
  return !token.empty() && ec == std::errc() && end == token.data() + token.size();
}

struct Parsed {
  ObjMesh obj;
  uint64_t highest = 0;       // the highest positive index a face used
  uint64_t highest_line = 0;  // ... and its line, to name it once all vertices are known
};

Result<ObjMesh> parse(std::string_view text, const std::string& where, const ObjReadLimits& limits) {
  if (text.find('\0') != std::string_view::npos) return makeError(where, "not an OBJ text file (it holds NUL bytes)");
  Parsed p;
  TriangleMesh& mesh = p.obj.mesh;
  std::vector<uint32_t> corners;
  uint64_t line_no = 0;
  size_t at = 0;
  while (at < text.size()) {
    const size_t end = std::min(text.find('\n', at), text.size());
    std::string_view line = text.substr(at, end - at);
    at = end + 1;
    ++line_no;
    line = line.substr(0, line.find('#'));
    size_t pos = 0;
    const std::string_view keyword = nextToken(line, pos);
    if (keyword == "v") {
      if (mesh.positions.size() >= limits.max_vertices)
        return Error{lineError(where, line_no, "more than " + std::to_string(limits.max_vertices) + " vertices")};
      Vec3f v{};
      for (int a = 0; a < 3; ++a) {
        const std::string_view token = nextToken(line, pos);
        double x = 0.0;
        if (!parseNumber(token, x) || std::abs(x) > 3.0e38)
          return Error{lineError(where, line_no, "vertex coordinate " + quoteToken(token) + " is not a finite number")};
        v[a] = float(x);
      }
      mesh.positions.push_back(v);
    } else if (keyword == "f") {
      corners.clear();
      for (std::string_view token = nextToken(line, pos); !token.empty(); token = nextToken(line, pos)) {
        int64_t index = 0;
        if (!parseIndex(token, index) || index == 0)
          return Error{lineError(where, line_no, "face corner " + quoteToken(token) + " is not a vertex index (1, 2, ... or -1, -2, ...)")};
        const uint64_t count = mesh.positions.size();
        if (index < 0) {
          if (uint64_t(-(index + 1)) >= count)
            return Error{lineError(where, line_no, "face corner " + quoteToken(token) + " reaches before the first vertex")};
          corners.push_back(uint32_t(int64_t(count) + index));
        } else {
          if (uint64_t(index) > limits.max_vertices)
            return Error{lineError(where, line_no, "face corner " + quoteToken(token) + " is beyond any vertex")};
          if (uint64_t(index) > p.highest) {
            p.highest = uint64_t(index);
            p.highest_line = line_no;
          }
          corners.push_back(uint32_t(index - 1));
        }
      }
      if (corners.size() < 3)
        return Error{lineError(where, line_no, "a face needs three corners, this one has " + std::to_string(corners.size()))};
      if (mesh.triangles.size() + (corners.size() - 2) > limits.max_triangles)
        return Error{lineError(where, line_no, "more than " + std::to_string(limits.max_triangles) + " triangles")};
      ++p.obj.file_faces;
      if (corners.size() > 3) ++p.obj.polygon_faces;
      for (size_t i = 1; i + 1 < corners.size(); ++i) mesh.triangles.push_back({corners[0], corners[i], corners[i + 1]});
    }
    // Any other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, ...) leaves the surface as it is.
  }
  if (p.highest > mesh.positions.size())
    return Error{lineError(where, p.highest_line, "face corner " + std::to_string(p.highest) + " is beyond the " +
                                                     std::to_string(mesh.positions.size()) + " vertices of the file")};
  if (mesh.triangles.empty()) return makeError(where, "no faces: an OBJ surface needs `f` lines");
  return std::move(p.obj);
}

}  // namespace

Result<ObjMesh> parseObj(std::span<const uint8_t> bytes, const std::string& where, const ObjReadLimits& limits) {
  return guardParse<ObjMesh>(where, bytes.size(), [&] {
    return parse(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), where, limits);
  });
}

Result<ObjMesh> readObj(const std::string& path, const ObjReadLimits& limits) {
  Result<std::vector<uint8_t>> bytes = readFileBytes(path, inputBudget().max_bytes);
  if (!bytes) return bytes.error();
  return parseObj(*bytes, path, limits);
}

}  // namespace dentsim
