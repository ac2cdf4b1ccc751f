// STL reading and writing: format detection by size, bounded allocation, strict but tolerant ASCII, one-line errors.
//
// Contents
//   1. Small helpers: little-endian fields, quoting, numbers
//   2. Binary reader
//   3. ASCII reader (scanner, then the solid/facet/loop grammar)
//   4. Format detection and parseStl / readStl
//   5. Writers
#include "io/stl_file.h"

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

static_assert(std::endian::native == std::endian::little, "binary STL stores little-endian floats as in memory");

// ---- 1. helpers -----------------------------------------------------------------------------

constexpr size_t kHeaderBytes = 80;   // binary header [B]
constexpr size_t kPreambleBytes = 84; // header and the uint32 triangle count [B]
constexpr size_t kRecordBytes = 50;   // normal, three corners, attribute word [B]

// Corner indices are uint32, three per triangle before welding.
constexpr uint64_t kMaxIndexableTriangles = std::numeric_limits<uint32_t>::max() / 3;

uint32_t loadU32(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

float loadF32(const uint8_t* p) {
  float v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

void storeU32(uint8_t* p, uint32_t v) { std::memcpy(p, &v, sizeof v); }
void storeF32(uint8_t* p, float v) { std::memcpy(p, &v, sizeof v); }

bool isSpace(uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
// Bytes no text file holds; finding one means binary data, often a binary STL whose header says "solid".
bool isControl(uint8_t c) { return (c < 0x20 && !isSpace(c)) || c == 0x7f; }

std::string hexByte(uint8_t c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02x", unsigned(c));
  return buf;
}

// A token from the file, shortened and with unprintable bytes escaped so the message stays one line.
std::string quote(std::string_view token) {
  constexpr size_t kMaxShown = 24;
  std::string out = "\"";
  for (size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    const auto c = uint8_t(token[i]);
    if (c < 0x20 || c >= 0x7f) out += "\\x" + hexByte(c).substr(2);
    else out += char(c);
  }
  if (token.size() > kMaxShown) out += "...";
  return out + "\"";
}

bool keywordIs(std::string_view token, std::string_view keyword) {
  if (token.size() != keyword.size()) return false;
  for (size_t i = 0; i < token.size(); ++i) {
    char c = token[i];
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    if (c != keyword[i]) return false;
  }
  return true;
}

// Text with NULs, control bytes and surrounding spaces removed (a name from a header or a solid line).
std::string trimmedText(std::string_view raw) {
  const size_t nul = raw.find('\0');
  if (nul != std::string_view::npos) raw = raw.substr(0, nul);
  std::string out;
  out.reserve(raw.size());
  for (char c : raw) out += isControl(uint8_t(c)) || isSpace(uint8_t(c)) ? ' ' : c;
  const size_t first = out.find_first_not_of(' ');
  if (first == std::string::npos) return "";
  return out.substr(first, out.find_last_not_of(' ') - first + 1);
}

enum class NumberParse { Ok, NotANumber, OutOfRange };

// One float token. Accepts a leading '+', which from_chars does not, and rounds values too small for
// a float to a subnormal or zero, as strtof would; nan and inf parse, and the caller decides.
NumberParse parseFloat(std::string_view token, float* value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  float f = 0.0f;
  auto [ptr, ec] = std::from_chars(token.data(), end, f);
  if (ptr != end || token.empty()) return NumberParse::NotANumber;
  if (ec == std::errc::result_out_of_range) {
    double d = 0.0;
    auto [dptr, dec] = std::from_chars(token.data(), end, d);
    if (dec != std::errc() || dptr != end || !(std::fabs(d) < 1.0)) return NumberParse::OutOfRange;
    f = float(d);
  } else if (ec != std::errc()) {
    return NumberParse::NotANumber;
  }
  *value = f;
  return NumberParse::Ok;
}

// `count` says how many triangles the file has, or at least has ("more than 10").
std::string limitMessage(const std::string& count, uint64_t limit) {
  return count + " triangles exceed the limit of " + std::to_string(limit) +
         " triangles: mesh too large for the memory budget";
}

uint64_t effectiveLimit(const StlReadLimits& limits) {
  return std::min(limits.max_triangles, kMaxIndexableTriangles);
}

// Corners as unwelded triangle soup: three positions per triangle, in file order.
void addTriangle(TriangleMesh& mesh, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const auto base = uint32_t(mesh.positions.size());
  mesh.positions.push_back(a);
  mesh.positions.push_back(b);
  mesh.positions.push_back(c);
  mesh.triangles.push_back({base, base + 1, base + 2});
}

// ---- 2. binary reader -----------------------------------------------------------------------

// The caller has checked that the size matches the count; the count is checked against the limit
// here, before anything is allocated.
Result<StlMesh> parseBinary(std::span<const uint8_t> bytes, const std::string& where, const StlReadLimits& limits) {
  const uint32_t count = loadU32(bytes.data() + kHeaderBytes);
  StlMesh out;
  out.info.format = StlFormat::Binary;
  out.info.solid_name = trimmedText(std::string_view(reinterpret_cast<const char*>(bytes.data()), kHeaderBytes));
  out.info.file_triangles = count;
  if (count == 0) return makeError(where, "binary STL with no triangles");
  if (count > effectiveLimit(limits)) return makeError(where, limitMessage(std::to_string(count), effectiveLimit(limits)));

  TriangleMesh& mesh = out.mesh;
  mesh.positions.resize(size_t(count) * 3);
  mesh.triangles.resize(count);
  for (uint32_t t = 0; t < count; ++t) {
    // The stored normal (first 12 bytes) is ignored: exporters often get it wrong, and the winding
    // order of the corners already gives the orientation.
    const uint8_t* corners = bytes.data() + kPreambleBytes + size_t(t) * kRecordBytes + 12;
    for (uint32_t k = 0; k < 3; ++k) {
      Vec3f& p = mesh.positions[size_t(t) * 3 + k];
      for (size_t a = 0; a < 3; ++a) {
        p[a] = loadF32(corners + 12 * k + 4 * a);
        if (!std::isfinite(p[a]))
          return makeError(where, "triangle " + std::to_string(t) + ", corner " + std::to_string(k) +
                                      " has a non-finite coordinate (" + (std::isnan(p[a]) ? "NaN" : "Inf") + ")");
      }
    }
    mesh.triangles[t] = {3 * t, 3 * t + 1, 3 * t + 2};
  }
  return out;
}

// ---- 3. ASCII reader ------------------------------------------------------------------------

// Splits text into whitespace-separated tokens and counts lines ('\n'; "\r\n" is whitespace too).
class AsciiScanner {
 public:
  explicit AsciiScanner(std::string_view text) : text_(text) {}

  // The next token, or an empty view at the end; line() is then the token's line.
  std::string_view next() {
    while (pos_ < text_.size() && isSpace(uint8_t(text_[pos_]))) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const size_t start = pos_;
    while (pos_ < text_.size() && !isSpace(uint8_t(text_[pos_]))) ++pos_;
    return text_.substr(start, pos_ - start);
  }

  // The rest of the current line (a solid's name), consumed without its newline.
  std::string_view restOfLine() {
    const size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    return text_.substr(start, pos_ - start);
  }

  uint64_t line() const { return line_; }

 private:
  std::string_view text_;
  size_t pos_ = 0;
  uint64_t line_ = 1;
};

// Recursive descent over: solid NAME { facet [normal x y z] outer loop vertex x y z (x3) endloop
// endfacet } endsolid [NAME], repeated when a file holds several solids.
class AsciiParser {
 public:
  AsciiParser(std::string_view text, const std::string& where, uint64_t max_triangles, TriangleMesh& mesh)
      : scan_(text), where_(where), max_triangles_(max_triangles), mesh_(mesh) {}

  // Returns the first solid's name.
  Result<std::string> parse() {
    std::string first_name;
    bool first = true;
    for (std::string_view tok = scan_.next(); !tok.empty() || first; tok = scan_.next()) {
      if (tok.empty()) return fail("empty ASCII STL");
      // Some exporters pad the end of the file with NULs or a DOS end-of-file mark (Ctrl-Z).
      if (!first && tok.find_first_not_of(std::string_view("\0\x1a", 2)) == std::string_view::npos) continue;
      if (hasControl(tok)) return failBinary(tok);
      if (!keywordIs(tok, "solid"))
        return fail(first ? "expected \"solid\", found " + quote(tok)
                          : "unexpected " + quote(tok) + " after endsolid");
      const std::string_view name = scan_.restOfLine();
      if (hasControl(name)) return failBinary(name);
      if (first) first_name = trimmedText(name);
      first = false;
      if (Status s = parseSolidBody(); !s) return s.error();
    }
    return first_name;
  }

  uint64_t facets() const { return facets_; }

 private:
  // Facets up to and including "endsolid [name]".
  Status parseSolidBody() {
    for (;;) {
      const std::string_view tok = scan_.next();
      if (tok.empty()) return fail("missing endsolid (the file ends inside the solid)");
      if (keywordIs(tok, "endsolid")) {
        // The name after endsolid often differs from the one after solid; it is not checked.
        if (hasControl(scan_.restOfLine())) return fail("binary data after endsolid");
        return Ok{};
      }
      if (!keywordIs(tok, "facet")) return unexpected(tok, "\"facet\" or \"endsolid\"");
      if (Status s = parseFacet(); !s) return s;
    }
  }

  Status parseFacet() {
    const uint64_t facet_line = scan_.line();
    if (facets_ >= max_triangles_) return fail(limitMessage("more than " + std::to_string(max_triangles_), max_triangles_));
    std::string_view tok = scan_.next();
    if (keywordIs(tok, "normal")) {
      // Read to check the syntax only: orientation comes from the corner order, and exporters write
      // wrong, zero or even NaN normals.
      Vec3f ignored;
      if (Status s = parseVector(&ignored, false); !s) return s;
      tok = scan_.next();
    }
    if (!keywordIs(tok, "outer")) return unexpected(tok, "\"outer loop\"");
    tok = scan_.next();
    if (!keywordIs(tok, "loop")) return unexpected(tok, "\"loop\" after \"outer\"");
    Vec3f corners[3];
    int n = 0;
    for (;;) {
      tok = scan_.next();
      if (keywordIs(tok, "vertex")) {
        if (n == 3) return fail("facet starting on line " + std::to_string(facet_line) + " has more than 3 vertices");
        if (Status s = parseVector(&corners[n], true); !s) return s;
        ++n;
      } else if (keywordIs(tok, "endloop")) {
        if (n != 3)
          return fail("facet starting on line " + std::to_string(facet_line) + " has " + std::to_string(n) +
                      (n == 1 ? " vertex" : " vertices") + ", expected 3");
        break;
      } else if (keywordIs(tok, "endfacet") || keywordIs(tok, "facet") || keywordIs(tok, "endsolid") || tok.empty()) {
        return fail("missing endloop (found " + (tok.empty() ? std::string("the end of the file") : quote(tok)) + ")");
      } else {
        return unexpected(tok, "\"vertex\" or \"endloop\"");
      }
    }
    tok = scan_.next();
    if (!keywordIs(tok, "endfacet")) {
      if (keywordIs(tok, "facet") || keywordIs(tok, "endsolid") || tok.empty())
        return fail("missing endfacet (found " + (tok.empty() ? std::string("the end of the file") : quote(tok)) + ")");
      return unexpected(tok, "\"endfacet\"");
    }
    addTriangle(mesh_, corners[0], corners[1], corners[2]);
    ++facets_;
    return Ok{};
  }

  // Three numbers; a vertex's must be finite.
  Status parseVector(Vec3f* v, bool corner) {
    for (size_t a = 0; a < 3; ++a) {
      const std::string_view tok = scan_.next();
      if (tok.empty()) return fail("the file ends inside a " + std::string(corner ? "vertex" : "normal"));
      if (hasControl(tok)) return failBinary(tok);
      switch (parseFloat(tok, &(*v)[a])) {
        case NumberParse::Ok: break;
        case NumberParse::NotANumber: return fail("expected a number, found " + quote(tok));
        case NumberParse::OutOfRange: return fail("number " + quote(tok) + " is out of the 32-bit float range");
      }
      if (corner && !std::isfinite((*v)[a]))
        return fail("vertex has a non-finite coordinate " + quote(tok));
    }
    return Ok{};
  }

  static bool hasControl(std::string_view s) {
    for (char c : s)
      if (isControl(uint8_t(c))) return true;
    return false;
  }

  Error fail(const std::string& what) const {
    return makeError(where_, "line " + std::to_string(scan_.line()) + ": " + what);
  }
  Error unexpected(std::string_view tok, const std::string& expected) const {
    if (tok.empty()) return fail("expected " + expected + ", found the end of the file");
    if (hasControl(tok)) return failBinary(tok);
    return fail("expected " + expected + ", found " + quote(tok));
  }
  Error failBinary(std::string_view tok) const {
    for (char c : tok)
      if (isControl(uint8_t(c)))
        return fail("binary data (byte " + hexByte(uint8_t(c)) + ") in an ASCII STL");
    return fail("binary data in an ASCII STL");
  }

  AsciiScanner scan_;
  const std::string& where_;
  uint64_t max_triangles_;
  TriangleMesh& mesh_;
  uint64_t facets_ = 0;
};

// ---- 4. detection and parsing ---------------------------------------------------------------

bool startsWithSolid(std::span<const uint8_t> bytes) {
  size_t i = 0;
  while (i < bytes.size() && isSpace(bytes[i])) ++i;
  const std::string_view rest(reinterpret_cast<const char*>(bytes.data()) + i, std::min<size_t>(bytes.size() - i, 5));
  return keywordIs(rest, "solid");
}

// What the size check says when a file is not binary: used on its own, or added to an ASCII error
// when a file that starts with "solid" holds binary data.
// `head` holds at least the 84-byte preamble; `size` is the whole file's [B].
std::string binarySizeMismatch(std::span<const uint8_t> head, uint64_t size) {
  const uint64_t count = loadU32(head.data() + kHeaderBytes);
  const uint64_t expected = kPreambleBytes + kRecordBytes * count;
  return "binary STL header says " + std::to_string(count) + " triangles (" + std::to_string(expected) +
         " bytes) but the file has " + std::to_string(size) + " bytes" +
         (expected > size ? " (truncated?)" : " (trailing data?)");
}
std::string binarySizeMismatch(std::span<const uint8_t> bytes) { return binarySizeMismatch(bytes, bytes.size()); }

// What a file's first bytes and its size make it, decided before the whole file is read: binary
// when its size is exactly 84 + 50 n for the count n (whatever its header says; the count is then
// checked against the limit), ASCII when it starts with "solid"; otherwise an error that names the
// real format of another kind of file (a PLY, a .nii.gz, a .dvol) or says what its size means.
// `head` holds the file's first min(size, kFileKindHeadBytes) bytes or more.
Result<StlFormat> classify(std::span<const uint8_t> head, uint64_t size, const std::string& where,
                           const StlReadLimits& limits) {
  if (size == 0) return makeError(where, "empty file, not an STL");
  // The size decides first: many binary files begin their header with "solid".
  if (size >= kPreambleBytes && kPreambleBytes + kRecordBytes * uint64_t(loadU32(head.data() + kHeaderBytes)) == size) {
    const uint64_t count = loadU32(head.data() + kHeaderBytes);
    if (count > effectiveLimit(limits)) return makeError(where, limitMessage(std::to_string(count), effectiveLimit(limits)));
    return StlFormat::Binary;
  }
  if (startsWithSolid(head)) return StlFormat::Ascii;
  if (auto other = refuseOtherKind(head, FileKind::Unknown, where, "an STL mesh")) return *other;
  if (size < kPreambleBytes)
    return makeError(where, "not an STL file: " + std::to_string(size) +
                                " bytes is shorter than a binary STL header (84 bytes) and the text does not "
                                "start with \"solid\"");
  return makeError(where, binarySizeMismatch(head, size));
}

Result<StlMesh> parseAscii(std::span<const uint8_t> bytes, const std::string& where, const StlReadLimits& limits) {
  StlMesh out;
  out.info.format = StlFormat::Ascii;
  AsciiParser parser(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), where,
                     effectiveLimit(limits), out.mesh);
  Result<std::string> name = parser.parse();
  if (!name) {
    // A binary file whose header starts with "solid" but whose size is off lands here; its header
    // or count field holds bytes no text has, so say what its size means for a binary reading too.
    const bool binary_preamble =
        bytes.size() >= kPreambleBytes && std::any_of(bytes.begin(), bytes.begin() + kPreambleBytes, isControl);
    if (binary_preamble) return makeError("", name.message() + "; read as binary, " + binarySizeMismatch(bytes));
    return name.error();
  }
  out.info.solid_name = std::move(*name);
  out.info.file_triangles = parser.facets();
  if (parser.facets() == 0) return makeError(where, "ASCII STL with no facets");
  return out;
}

// Welds the corner soup and reports its topology.
Status finish(StlMesh& stl, const std::string& where) {
  stl.info.dropped_triangles = weldVertices(stl.mesh);
  if (stl.mesh.triangles.empty())
    return makeError(where, "all " + std::to_string(stl.info.file_triangles) +
                                " triangles are degenerate (corners coincide)");
  stl.info.topology = analyzeTopology(stl.mesh);
  return Ok{};
}

Result<StlMesh> parseUnchecked(std::span<const uint8_t> bytes, const std::string& where, const StlReadLimits& limits) {
  Result<StlFormat> format = classify(bytes, bytes.size(), where, limits);
  if (!format) return format.error();
  Result<StlMesh> parsed =
      *format == StlFormat::Binary ? parseBinary(bytes, where, limits) : parseAscii(bytes, where, limits);
  if (!parsed) return parsed;
  if (Status s = finish(*parsed, where); !s) return s.error();
  return parsed;
}

}  // namespace

Result<StlMesh> parseStl(std::span<const uint8_t> bytes, const std::string& where, const StlReadLimits& limits) {
  return guardParse<StlMesh>(where, bytes.size(), [&] { return parseUnchecked(bytes, where, limits); });
}

Result<StlMesh> readStl(const std::string& path, const StlReadLimits& limits) {
  // ASCII spends about 250 bytes per facet, and verbose exporters more; the triangle limit itself is
  // checked while parsing. The input budget bounds the bytes read whatever the limit allows.
  constexpr uint64_t kMaxAsciiBytesPerTriangle = 512;
  const uint64_t max_bytes = std::min(kPreambleBytes + std::min(limits.max_triangles, kMaxIndexableTriangles) *
                                                           kMaxAsciiBytesPerTriangle,
                                      inputBudget().max_bytes);
  // The head and the size decide the format, and a binary file's count is checked, before the
  // whole file is read: a file that claims 20 million triangles, or is really a PLY, costs nothing.
  Result<uint64_t> size = regularFileSize(path);
  if (!size) return size.error();
  Result<std::vector<uint8_t>> head = readFileHead(path, kFileKindHeadBytes);
  if (!head) return head.error();
  if (Result<StlFormat> format = classify(*head, *size, path, limits); !format) return format.error();
  Result<std::vector<uint8_t>> bytes = readFileBytes(path, max_bytes);
  if (!bytes) return bytes.error();
  return parseStl(*bytes, path, limits);
}

// ---- 5. writers -----------------------------------------------------------------------------

namespace {

// The unit normal of a triangle from its corners (right-hand rule); zero when it has no area.
Vec3f facetNormal(const TriangleMesh& mesh, const std::array<uint32_t, 3>& t) {
  Vec3d e1{}, e2{};
  for (size_t a = 0; a < 3; ++a) {
    e1[a] = double(mesh.positions[t[1]][a]) - double(mesh.positions[t[0]][a]);
    e2[a] = double(mesh.positions[t[2]][a]) - double(mesh.positions[t[0]][a]);
  }
  const Vec3d n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0.0) || !std::isfinite(len)) return {0.0f, 0.0f, 0.0f};
  return {float(n[0] / len), float(n[1] / len), float(n[2] / len)};
}

void appendVector(std::string& out, const char* keyword, const Vec3f& v) {
  // %.9g gives back the same float when read again.
  char buf[128];
  std::snprintf(buf, sizeof buf, "%s %.9g %.9g %.9g\n", keyword, double(v[0]), double(v[1]), double(v[2]));
  out += buf;
}

}  // namespace

std::vector<uint8_t> encodeStlBinary(const TriangleMesh& mesh, std::string_view header) {
  assert(mesh.triangleCount() <= std::numeric_limits<uint32_t>::max());
  std::vector<uint8_t> out(kPreambleBytes + kRecordBytes * mesh.triangleCount(), 0);
  std::memcpy(out.data(), header.data(), std::min(header.size(), kHeaderBytes));
  storeU32(out.data() + kHeaderBytes, uint32_t(mesh.triangleCount()));
  uint8_t* record = out.data() + kPreambleBytes;
  for (const auto& t : mesh.triangles) {
    const Vec3f n = facetNormal(mesh, t);
    for (size_t a = 0; a < 3; ++a) storeF32(record + 4 * a, n[a]);
    for (size_t k = 0; k < 3; ++k)
      for (size_t a = 0; a < 3; ++a) storeF32(record + 12 + 12 * k + 4 * a, mesh.positions[t[k]][a]);
    record += kRecordBytes;  // the attribute word stays zero
  }
  return out;
}

std::string encodeStlAscii(const TriangleMesh& mesh, std::string_view name) {
  // A newline in the name would end the solid line early.
  std::string clean(name);
  for (char& c : clean)
    if (isControl(uint8_t(c)) || isSpace(uint8_t(c))) c = ' ';
  const std::string suffix = clean.empty() ? "" : " " + clean;
  std::string out = "solid" + suffix + "\n";
  out.reserve(out.size() + mesh.triangleCount() * 260);
  for (const auto& t : mesh.triangles) {
    appendVector(out, "  facet normal", facetNormal(mesh, t));
    out += "    outer loop\n";
    for (uint32_t c : t) appendVector(out, "      vertex", mesh.positions[c]);
    out += "    endloop\n  endfacet\n";
  }
  out += "endsolid" + suffix + "\n";
  return out;
}

Status writeStl(const std::string& path, const TriangleMesh& mesh, std::string_view header) {
  try {
    return writeFileAtomic(path, encodeStlBinary(mesh, header));
  } catch (const std::bad_alloc&) {
    return makeError(path, "out of memory encoding " + std::to_string(mesh.triangleCount()) + " triangles");
  }
}

}  // namespace dentsim
