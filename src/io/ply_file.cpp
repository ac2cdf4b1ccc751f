// PLY reading and writing: a strict header parser, bounded allocation, binary and ASCII bodies, fan triangulation, one-line errors.
//
// Contents
//   1. Helpers: scalar types, little-endian loads and stores, quoting, numbers
//   2. Header: lines, elements, properties, checks against the limits and the file size
//   3. Binary body
//   4. ASCII body
//   5. parsePly / readPly
//   6. Writers
#include "io/ply_file.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <new>

#include "io/atomic_file.h"
#include "io/file_kind.h"
#include "io/input_budget.h"
#include "io/parse_guard.h"

namespace dentsim {
namespace {

static_assert(std::endian::native == std::endian::little, "binary PLY is read and written as little-endian memory");

// ---- 1. helpers -----------------------------------------------------------------------------

constexpr size_t kMaxHeaderBytes = 64 * 1024;  // a real header is a few hundred bytes [B]
// Corner indices are uint32 in TriangleMesh.
constexpr uint64_t kMaxIndexable = std::numeric_limits<uint32_t>::max();

enum class Scalar : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct ScalarName {
  std::string_view name;
  Scalar type;
};
// Both the PLY 1.0 names and the sized aliases that many writers use.
constexpr ScalarName kScalarNames[] = {
    {"char", Scalar::Int8},     {"int8", Scalar::Int8},       {"uchar", Scalar::UInt8},  {"uint8", Scalar::UInt8},
    {"short", Scalar::Int16},   {"int16", Scalar::Int16},     {"ushort", Scalar::UInt16}, {"uint16", Scalar::UInt16},
    {"int", Scalar::Int32},     {"int32", Scalar::Int32},     {"uint", Scalar::UInt32},  {"uint32", Scalar::UInt32},
    {"float", Scalar::Float32}, {"float32", Scalar::Float32}, {"double", Scalar::Float64}, {"float64", Scalar::Float64},
};

bool parseScalar(std::string_view name, Scalar* type) {
  for (const ScalarName& s : kScalarNames)
    if (s.name == name) {
      *type = s.type;
      return true;
    }
  return false;
}

std::string_view scalarName(Scalar type) {
  for (const ScalarName& s : kScalarNames)
    if (s.type == type) return s.name;  // the first, PLY 1.0 name
  return "?";
}

size_t scalarBytes(Scalar type) {
  switch (type) {
    case Scalar::Int8: case Scalar::UInt8: return 1;
    case Scalar::Int16: case Scalar::UInt16: return 2;
    case Scalar::Int32: case Scalar::UInt32: case Scalar::Float32: return 4;
    case Scalar::Float64: return 8;
  }
  return 0;
}

bool isFloat(Scalar type) { return type == Scalar::Float32 || type == Scalar::Float64; }

template <class T>
T load(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// An integer field of any integer type, widened.
int64_t loadInteger(const uint8_t* p, Scalar type) {
  switch (type) {
    case Scalar::Int8: return load<int8_t>(p);
    case Scalar::UInt8: return load<uint8_t>(p);
    case Scalar::Int16: return load<int16_t>(p);
    case Scalar::UInt16: return load<uint16_t>(p);
    case Scalar::Int32: return load<int32_t>(p);
    case Scalar::UInt32: return load<uint32_t>(p);
    default: assert(false && "not an integer type"); return 0;
  }
}

double loadReal(const uint8_t* p, Scalar type) {
  return type == Scalar::Float32 ? double(load<float>(p)) : load<double>(p);
}

template <class T>
void store(std::vector<uint8_t>& out, T v) {
  const size_t at = out.size();
  out.resize(at + sizeof v);
  std::memcpy(out.data() + at, &v, sizeof v);
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

std::string quote(std::string_view token) { return quoteToken(token); }

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

// A decimal integer; a leading '+' is allowed, which from_chars does not take.
bool parseInteger(std::string_view token, int64_t* value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, *value);
  return !token.empty() && ec == std::errc() && ptr == end;
}

// A real number in double; nan and inf parse, and the caller decides. Values too small for a double
// round to zero, as strtod would.
bool parseReal(std::string_view token, double* value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, *value);
  if (token.empty() || ptr != end) return false;
  if (ec == std::errc::result_out_of_range) {
    // from_chars leaves the value unset; tell underflow (a tiny mantissa scale) from overflow.
    const size_t e = token.find_first_of("eE");
    const bool tiny = e != std::string_view::npos && e + 1 < token.size() && token[e + 1] == '-';
    if (!tiny) return false;
    *value = 0.0;
    return true;
  }
  return ec == std::errc();
}

// ---- 2. header ------------------------------------------------------------------------------

// The vertex properties dentsim knows, in the order they are written.
enum Field : uint8_t { kX, kY, kZ, kNx, kNy, kNz, kRed, kGreen, kBlue, kFieldCount };
constexpr std::string_view kFieldNames[kFieldCount] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"};

struct VertexProperty {
  Field field;
  Scalar type;
  size_t offset;  // within a binary vertex record [B]
};

struct Header {
  PlyFormat format = PlyFormat::BinaryLittleEndian;
  uint64_t vertices = 0;
  uint64_t faces = 0;
  std::vector<VertexProperty> vertex_properties;  // in file order
  size_t vertex_stride = 0;                       // binary vertex record [B]
  bool has_normals = false;
  bool has_colours = false;
  Scalar count_type = Scalar::UInt8;  // face list length
  Scalar index_type = Scalar::Int32;  // face list entries
  size_t body_offset = 0;             // first byte after "end_header\n"
  uint64_t body_line = 0;             // line number of that byte, for ASCII errors
};

class HeaderParser {
 public:
  HeaderParser(std::span<const uint8_t> bytes, const std::string& where) : bytes_(bytes), where_(where) {}

  Result<Header> parse() {
    if (bytes_.empty()) return makeError(where_, "empty file, not a PLY");
    if (auto other = refuseOtherKind(bytes_, FileKind::Ply, where_, "a PLY mesh")) return *other;
    if (!nextLine()) return makeError(where_, "not a PLY file (no \"ply\" line)");
    if (line_ != "ply") return makeError(where_, "not a PLY file (the first line is " + quote(line_) + ", not \"ply\")");
    bool format_seen = false;
    for (;;) {
      if (!nextLine()) {
        if (bytes_.size() > kMaxHeaderBytes) return fail("no end_header in the first " + std::to_string(kMaxHeaderBytes) + " bytes");
        return fail("the file ends inside the header (no end_header)");
      }
      for (char c : line_)
        if ((uint8_t(c) < 0x20 && c != '\t' && c != '\r') || uint8_t(c) == 0x7f) return fail("binary data in the header");
      const std::vector<std::string_view> w = splitWords(line_);
      if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
      if (w[0] == "end_header") {
        if (w.size() != 1) return fail("unexpected text after end_header");
        break;
      }
      if (w[0] == "format") {
        if (format_seen) return fail("a second format line");
        if (Status s = parseFormat(w); !s) return s.error();
        format_seen = true;
      } else if (w[0] == "element") {
        if (!format_seen) return fail("element before the format line");
        if (Status s = parseElement(w); !s) return s.error();
      } else if (w[0] == "property") {
        if (Status s = parseProperty(w); !s) return s.error();
      } else {
        return fail("unexpected header line " + quote(line_));
      }
    }
    if (Status s = finish(); !s) return s.error();
    h_.body_offset = pos_;
    h_.body_line = line_number_ + 1;
    return h_;
  }

 private:
  // The next '\n'-terminated line without its "\r\n" or "\n"; false at the end of the bytes or of the
  // header budget.
  bool nextLine() {
    const size_t limit = std::min(bytes_.size(), kMaxHeaderBytes);
    if (pos_ >= limit) return false;
    const auto* text = reinterpret_cast<const char*>(bytes_.data());
    const void* nl = std::memchr(text + pos_, '\n', limit - pos_);
    if (!nl) return false;
    const size_t end = size_t(static_cast<const char*>(nl) - text);
    line_ = std::string_view(text + pos_, end - pos_);
    if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
    pos_ = end + 1;
    ++line_number_;
    return true;
  }

  Status parseFormat(const std::vector<std::string_view>& w) {
    if (w.size() != 3) return fail("malformed format line " + quote(line_));
    if (w[2] != "1.0") return fail("unsupported PLY version " + quote(w[2]) + " (expected 1.0)");
    if (w[1] == "ascii") h_.format = PlyFormat::Ascii;
    else if (w[1] == "binary_little_endian") h_.format = PlyFormat::BinaryLittleEndian;
    else if (w[1] == "binary_big_endian") return fail("big-endian binary PLY is not supported (convert it to little-endian or ASCII)");
    else return fail("unknown format " + quote(w[1]));
    return Ok{};
  }

  Status parseElement(const std::vector<std::string_view>& w) {
    if (w.size() != 3) return fail("malformed element line " + quote(line_));
    int64_t count = 0;
    if (!parseInteger(w[2], &count) || count < 0) return fail("element " + quote(w[1]) + " has a bad count " + quote(w[2]));
    const std::string_view expected = elements_ == 0 ? "vertex" : elements_ == 1 ? "face" : "";
    if (w[1] != expected) {
      if (w[1] == "vertex" || w[1] == "face") return fail("element " + quote(w[1]) + " out of order (expected vertex, then face)");
      return fail("unsupported element " + quote(w[1]) + " (only vertex and face)");
    }
    (elements_ == 0 ? h_.vertices : h_.faces) = uint64_t(count);
    ++elements_;
    return Ok{};
  }

  Status parseProperty(const std::vector<std::string_view>& w) {
    if (elements_ == 0) return fail("property before any element");
    return elements_ == 1 ? parseVertexProperty(w) : parseFaceProperty(w);
  }

  Status parseVertexProperty(const std::vector<std::string_view>& w) {
    if (w.size() >= 2 && w[1] == "list") return fail("list property " + quote(w.back()) + " in the vertex element");
    if (w.size() != 3) return fail("malformed property line " + quote(line_));
    Scalar type{};
    if (!parseScalar(w[1], &type)) return fail("unknown property type " + quote(w[1]));
    size_t field = 0;
    while (field < kFieldCount && kFieldNames[field] != w[2]) ++field;
    if (field == kFieldCount)
      return fail("unsupported vertex property " + quote(w[2]) + " (expected x y z, nx ny nz, red green blue)");
    if (seen_[field]) return fail("vertex property " + quote(w[2]) + " appears twice");
    const bool colour = field >= kRed;
    if (colour ? type != Scalar::UInt8 : !isFloat(type))
      return fail("vertex property " + quote(w[2]) + " has type " + std::string(scalarName(type)) +
                  (colour ? ", expected uchar" : ", expected float or double"));
    seen_[field] = true;
    h_.vertex_properties.push_back({Field(field), type, h_.vertex_stride});
    h_.vertex_stride += scalarBytes(type);
    return Ok{};
  }

  Status parseFaceProperty(const std::vector<std::string_view>& w) {
    if (face_property_) return fail("a second face property " + quote(w.back()) + " (only vertex_indices)");
    if (w.size() != 5 || w[1] != "list") return fail("face property " + quote(w.back()) + " is not a list");
    if (w[4] != "vertex_indices" && w[4] != "vertex_index")
      return fail("unsupported face property " + quote(w[4]) + " (expected vertex_indices)");
    if (!parseScalar(w[2], &h_.count_type) || isFloat(h_.count_type))
      return fail("face list count type " + quote(w[2]) + " is not an integer type");
    if (!parseScalar(w[3], &h_.index_type) || isFloat(h_.index_type))
      return fail("face index type " + quote(w[3]) + " is not an integer type");
    face_property_ = true;
    return Ok{};
  }

  // The whole header is known: check that it describes a mesh.
  Status finish() {
    if (elements_ < 2) return fail(elements_ == 0 ? "no vertex element" : "no face element");
    if (!face_property_) return fail("the face element has no vertex_indices list");
    for (Field f : {kX, kY, kZ})
      if (!seen_[f]) return fail("no vertex property " + quote(kFieldNames[f]));
    h_.has_normals = seen_[kNx] || seen_[kNy] || seen_[kNz];
    h_.has_colours = seen_[kRed] || seen_[kGreen] || seen_[kBlue];
    if (h_.has_normals && !(seen_[kNx] && seen_[kNy] && seen_[kNz])) return fail("normals need all of nx, ny and nz");
    if (h_.has_colours && !(seen_[kRed] && seen_[kGreen] && seen_[kBlue])) return fail("colours need all of red, green and blue");
    return Ok{};
  }

  Error fail(const std::string& what) const {
    return makeError(where_, "header line " + std::to_string(line_number_) + ": " + what);
  }

  std::span<const uint8_t> bytes_;
  const std::string& where_;
  Header h_;
  size_t pos_ = 0;
  uint64_t line_number_ = 0;
  std::string_view line_;
  int elements_ = 0;  // elements declared so far: 0, 1 (vertex) or 2 (vertex, face)
  bool seen_[kFieldCount] = {};
  bool face_property_ = false;
};

// Counts against the budget and against what the body can hold, before anything is allocated.
Status checkCounts(const Header& h, uint64_t body_bytes, const std::string& where, const PlyReadLimits& limits) {
  const uint64_t max_vertices = std::min(limits.max_vertices, kMaxIndexable);
  const uint64_t max_triangles = std::min(limits.max_triangles, kMaxIndexable);
  if (h.vertices > max_vertices)
    return makeError(where, std::to_string(h.vertices) + " vertices exceed the limit of " + std::to_string(max_vertices) +
                                ": mesh too large for the memory budget");
  // Every face gives at least one triangle.
  if (h.faces > max_triangles)
    return makeError(where, std::to_string(h.faces) + " faces exceed the limit of " + std::to_string(max_triangles) +
                                " triangles: mesh too large for the memory budget");
  const std::string counts = std::to_string(h.vertices) + " vertices and " + std::to_string(h.faces) + " faces";
  if (h.format == PlyFormat::BinaryLittleEndian) {
    // A face holds at least its count and three indices.
    const uint64_t need = h.vertices * h.vertex_stride + h.faces * (scalarBytes(h.count_type) + 3 * scalarBytes(h.index_type));
    if (need > body_bytes)
      return makeError(where, "truncated: the header says " + counts + " (at least " + std::to_string(need) +
                                  " bytes of data) but " + std::to_string(body_bytes) + " bytes follow it");
  } else {
    // Each number takes at least one character and one separator (but the last).
    const uint64_t tokens = h.vertices * h.vertex_properties.size() + h.faces * 4;
    if (tokens > 0 && 2 * tokens - 1 > body_bytes)
      return makeError(where, "truncated: the header says " + counts + " (at least " + std::to_string(tokens) +
                                  " numbers) but only " + std::to_string(body_bytes) + " bytes follow it");
  }
  return Ok{};
}

std::string nonFinite(double v) { return std::isnan(v) ? "NaN" : "Inf"; }

// Stores one vertex property value; positions and normals must be finite as floats.
Status setVertexField(PlyMesh& out, uint64_t v, Field f, double value, const std::string& where_vertex) {
  if (f >= kRed) {
    (*out.colours)[v][f - kRed] = uint8_t(value);
    return Ok{};
  }
  const auto narrow = float(value);
  if (!std::isfinite(narrow))
    return Error{where_vertex + " has a non-finite " + std::string(kFieldNames[f]) + " (" +
                 (std::isfinite(value) ? std::string("out of the float range") : nonFinite(value)) + ")"};
  if (f <= kZ) out.mesh.positions[v][f] = narrow;
  else (*out.normals)[v][f - kNx] = narrow;
  return Ok{};
}

// Splits one face of `n` corners into a fan and appends it; corners have been range-checked.
Status addFace(PlyMesh& out, std::span<const uint32_t> corners, uint64_t max_triangles, const std::string& where) {
  if (corners.size() > 3) ++out.info.polygon_faces;
  for (size_t i = 1; i + 1 < corners.size(); ++i) {
    if (out.mesh.triangles.size() >= max_triangles)
      return makeError(where, "more than " + std::to_string(max_triangles) +
                                  " triangles after splitting polygons: mesh too large for the memory budget");
    out.mesh.triangles.push_back({corners[0], corners[i], corners[i + 1]});
  }
  return Ok{};
}

std::string faceCornersError(uint64_t face, int64_t n) {
  return "face " + std::to_string(face) + " has " + std::to_string(n) + (n == 1 ? " corner" : " corners") +
         ", at least 3 needed";
}

std::string indexError(uint64_t face, int64_t index, uint64_t vertices) {
  return "face " + std::to_string(face) + " has vertex index " + std::to_string(index) + " out of range (" +
         std::to_string(vertices) + " vertices)";
}

void allocate(PlyMesh& out, const Header& h) {
  out.mesh.positions.resize(h.vertices);
  if (h.has_normals) out.normals.emplace(h.vertices);
  if (h.has_colours) out.colours.emplace(h.vertices);
  out.mesh.triangles.reserve(h.faces);
}

// ---- 3. binary body ---------------------------------------------------------------------------

Status parseBinaryBody(std::span<const uint8_t> bytes, const Header& h, const std::string& where,
                       const PlyReadLimits& limits, PlyMesh& out) {
  const uint8_t* p = bytes.data() + h.body_offset;
  const uint8_t* const end = bytes.data() + bytes.size();
  for (uint64_t v = 0; v < h.vertices; ++v, p += h.vertex_stride)
    for (const VertexProperty& prop : h.vertex_properties) {
      const uint8_t* field = p + prop.offset;
      const double value = prop.field >= kRed ? double(*field) : loadReal(field, prop.type);
      if (Status s = setVertexField(out, v, prop.field, value, "vertex " + std::to_string(v)); !s)
        return makeError(where, s.message());
    }

  const size_t count_bytes = scalarBytes(h.count_type);
  const size_t index_bytes = scalarBytes(h.index_type);
  const uint64_t max_triangles = std::min(limits.max_triangles, kMaxIndexable);
  std::vector<uint32_t> corners;
  for (uint64_t f = 0; f < h.faces; ++f) {
    if (size_t(end - p) < count_bytes) return makeError(where, "truncated in face " + std::to_string(f));
    const int64_t n = loadInteger(p, h.count_type);
    p += count_bytes;
    if (n < 3) return makeError(where, faceCornersError(f, n));
    if (uint64_t(end - p) / index_bytes < uint64_t(n))
      return makeError(where, "truncated in face " + std::to_string(f) + " (" + std::to_string(n) + " corners)");
    corners.resize(size_t(n));
    for (int64_t k = 0; k < n; ++k, p += index_bytes) {
      const int64_t index = loadInteger(p, h.index_type);
      if (index < 0 || uint64_t(index) >= h.vertices) return makeError(where, indexError(f, index, h.vertices));
      corners[size_t(k)] = uint32_t(index);
    }
    if (Status s = addFace(out, corners, max_triangles, where); !s) return s;
  }
  if (p != end)
    return makeError(where, std::to_string(end - p) + (end - p == 1 ? " byte" : " bytes") + " of trailing data after the last face");
  return Ok{};
}

// ---- 4. ASCII body ----------------------------------------------------------------------------

// Whitespace-separated tokens with line numbers; the element structure does not depend on line breaks.
class Scanner {
 public:
  Scanner(std::string_view text, uint64_t first_line) : text_(text), line_(first_line) {}

  std::string_view next() {
    while (pos_ < text_.size() && isSpace(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const size_t start = pos_;
    while (pos_ < text_.size() && !isSpace(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  uint64_t line() const { return line_; }

 private:
  std::string_view text_;
  size_t pos_ = 0;
  uint64_t line_;
};

class AsciiBody {
 public:
  AsciiBody(std::span<const uint8_t> bytes, const Header& h, const std::string& where, const PlyReadLimits& limits,
            PlyMesh& out)
      : scan_(std::string_view(reinterpret_cast<const char*>(bytes.data()) + h.body_offset, bytes.size() - h.body_offset),
              h.body_line),
        h_(h), where_(where), max_triangles_(std::min(limits.max_triangles, kMaxIndexable)), out_(out) {}

  Status parse() {
    for (uint64_t v = 0; v < h_.vertices; ++v)
      for (const VertexProperty& prop : h_.vertex_properties) {
        const std::string what = "vertex " + std::to_string(v);
        const std::string_view tok = scan_.next();
        if (tok.empty()) return fail("the file ends inside " + what);
        double value = 0.0;
        if (prop.field >= kRed) {
          int64_t i = 0;
          if (!parseInteger(tok, &i) || i < 0 || i > 255)
            return fail(what + ": expected a colour 0-255 for " + std::string(kFieldNames[prop.field]) + ", found " + quote(tok));
          value = double(i);
        } else if (!parseReal(tok, &value)) {
          return fail(what + ": expected a number for " + std::string(kFieldNames[prop.field]) + ", found " + quote(tok));
        }
        if (Status s = setVertexField(out_, v, prop.field, value, what); !s) return fail(s.message());
      }

    std::vector<uint32_t> corners;
    for (uint64_t f = 0; f < h_.faces; ++f) {
      const std::string what = "face " + std::to_string(f);
      int64_t n = 0;
      if (Status s = integer(what, &n); !s) return s;
      if (n < 3) return fail(faceCornersError(f, n));
      // Every corner needs a token of its own, so the file bounds the polygon size.
      corners.clear();
      for (int64_t k = 0; k < n; ++k) {
        int64_t index = 0;
        if (Status s = integer(what, &index); !s) return s;
        if (index < 0 || uint64_t(index) >= h_.vertices) return fail(indexError(f, index, h_.vertices));
        corners.push_back(uint32_t(index));
      }
      if (Status s = addFace(out_, corners, max_triangles_, where_); !s) return s;
    }
    if (const std::string_view tok = scan_.next(); !tok.empty()) return fail("unexpected " + quote(tok) + " after the last face");
    return Ok{};
  }

 private:
  Status integer(const std::string& what, int64_t* value) {
    const std::string_view tok = scan_.next();
    if (tok.empty()) return fail("the file ends inside " + what);
    if (!parseInteger(tok, value)) return fail(what + ": expected an integer, found " + quote(tok));
    return Ok{};
  }

  Error fail(const std::string& what) const { return makeError(where_, "line " + std::to_string(scan_.line()) + ": " + what); }

  Scanner scan_;
  const Header& h_;
  const std::string& where_;
  uint64_t max_triangles_;
  PlyMesh& out_;
};

// ---- 5. parsing -------------------------------------------------------------------------------

Result<PlyMesh> parseUnchecked(std::span<const uint8_t> bytes, const std::string& where, const PlyReadLimits& limits) {
  Result<Header> header = HeaderParser(bytes, where).parse();
  if (!header) return header.error();
  const Header& h = *header;
  if (Status s = checkCounts(h, bytes.size() - h.body_offset, where, limits); !s) return s.error();
  PlyMesh out;
  out.info.format = h.format;
  out.info.file_faces = h.faces;
  allocate(out, h);
  Status body = h.format == PlyFormat::BinaryLittleEndian ? parseBinaryBody(bytes, h, where, limits, out)
                                                          : AsciiBody(bytes, h, where, limits, out).parse();
  if (!body) return body.error();
  return out;
}

}  // namespace

Result<PlyMesh> parsePly(std::span<const uint8_t> bytes, const std::string& where, const PlyReadLimits& limits) {
  return guardParse<PlyMesh>(where, bytes.size(), [&] { return parseUnchecked(bytes, where, limits); });
}

Result<PlyMesh> readPly(const std::string& path, const PlyReadLimits& limits) {
  // Verbose ASCII spends about 120 bytes on a vertex with normals and colours and 40 on a triangle;
  // the counts themselves are checked against the limits after the header.
  constexpr uint64_t kMaxBytesPerVertex = 256;
  constexpr uint64_t kMaxBytesPerTriangle = 128;
  const uint64_t max_bytes = kMaxHeaderBytes + std::min(limits.max_vertices, kMaxIndexable) * kMaxBytesPerVertex +
                             std::min(limits.max_triangles, kMaxIndexable) * kMaxBytesPerTriangle;
  Result<std::vector<uint8_t>> bytes = readFileBytes(path, std::min(max_bytes, inputBudget().max_bytes));
  if (!bytes) return bytes.error();
  return parsePly(*bytes, path, limits);
}

// ---- 6. writers -------------------------------------------------------------------------------

namespace {

std::string headerText(const PlyView& view, std::string_view format, std::string_view comment) {
  std::string h = "ply\nformat " + std::string(format) + " 1.0\n";
  if (!comment.empty()) {
    // A newline in the comment would end the header line early.
    std::string clean(comment);
    for (char& c : clean)
      if (uint8_t(c) < 0x20 || uint8_t(c) == 0x7f) c = ' ';
    h += "comment " + clean + "\n";
  }
  h += "element vertex " + std::to_string(view.positions.size()) + "\n";
  h += "property float x\nproperty float y\nproperty float z\n";
  if (!view.normals.empty()) h += "property float nx\nproperty float ny\nproperty float nz\n";
  if (!view.colours.empty()) h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  h += "element face " + std::to_string(view.triangles.size()) + "\n";
  h += "property list uchar int vertex_indices\nend_header\n";
  return h;
}

void assertValid(const PlyView& view) {
  assert(view.normals.empty() || view.normals.size() == view.positions.size());
  assert(view.colours.empty() || view.colours.size() == view.positions.size());
  assert(view.positions.size() <= size_t(std::numeric_limits<int32_t>::max()));
  (void)view;
}

void appendFloats(std::string& out, const Vec3f& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, " %.9g %.9g %.9g", double(v[0]), double(v[1]), double(v[2]));
  out += buf;
}

}  // namespace

std::vector<uint8_t> encodePlyBinary(const PlyView& view, std::string_view comment) {
  assertValid(view);
  const std::string header = headerText(view, "binary_little_endian", comment);
  const size_t stride = 12 + (view.normals.empty() ? 0 : 12) + (view.colours.empty() ? 0 : 3);
  std::vector<uint8_t> out(header.begin(), header.end());
  out.reserve(header.size() + stride * view.positions.size() + 13 * view.triangles.size());
  for (size_t v = 0; v < view.positions.size(); ++v) {
    for (float x : view.positions[v]) store(out, x);
    if (!view.normals.empty())
      for (float x : view.normals[v]) store(out, x);
    if (!view.colours.empty())
      for (uint8_t c : view.colours[v]) store(out, c);
  }
  for (const auto& t : view.triangles) {
    store(out, uint8_t{3});
    for (uint32_t c : t) {
      assert(c < view.positions.size());
      store(out, int32_t(c));
    }
  }
  return out;
}

std::string encodePlyAscii(const PlyView& view, std::string_view comment) {
  assertValid(view);
  std::string out = headerText(view, "ascii", comment);
  out.reserve(out.size() + 80 * view.positions.size() + 24 * view.triangles.size());
  for (size_t v = 0; v < view.positions.size(); ++v) {
    std::string line;
    appendFloats(line, view.positions[v]);
    if (!view.normals.empty()) appendFloats(line, view.normals[v]);
    if (!view.colours.empty())
      for (uint8_t c : view.colours[v]) line += " " + std::to_string(unsigned(c));
    out.append(line, 1);  // without the leading space
    out += '\n';
  }
  for (const auto& t : view.triangles)
    out += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  return out;
}

Status writePly(const std::string& path, const PlyView& view, std::string_view comment) {
  // The view comes from the caller's own data, but a mismatch would write a file that reads wrong,
  // so it is refused here even in builds without asserts.
  const size_t n = view.positions.size();
  if (!view.normals.empty() && view.normals.size() != n)
    return makeError(path, std::to_string(view.normals.size()) + " normals for " + std::to_string(n) + " vertices");
  if (!view.colours.empty() && view.colours.size() != n)
    return makeError(path, std::to_string(view.colours.size()) + " colours for " + std::to_string(n) + " vertices");
  if (n > size_t(std::numeric_limits<int32_t>::max()))
    return makeError(path, std::to_string(n) + " vertices are too many for PLY int indices");
  for (size_t t = 0; t < view.triangles.size(); ++t)
    for (uint32_t c : view.triangles[t])
      if (c >= n) return makeError(path, "triangle " + std::to_string(t) + " has vertex index " + std::to_string(c) +
                                             " out of range (" + std::to_string(n) + " vertices)");
  try {
    return writeFileAtomic(path, encodePlyBinary(view, comment));
  } catch (const std::bad_alloc&) {
    return makeError(path, "out of memory encoding " + std::to_string(view.triangles.size()) + " triangles");
  }
}

}  // namespace dentsim
