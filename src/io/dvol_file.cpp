// .dvol reading and writing: fixed little-endian header, zstd payload, XXH64 checksums, atomic replace.
#include "io/dvol_file.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

#include <xxhash.h>
#include <zstd.h>

#include "io/atomic_file.h"
#include "io/file_kind.h"
#include "io/input_budget.h"

namespace dentsim {
namespace {

static_assert(std::endian::native == std::endian::little, ".dvol stores little-endian words as they are in memory");

constexpr char kMagic[8] = {'D', 'E', 'N', 'T', 'S', 'I', 'M', 'V'};
constexpr char kNoteMagic[8] = {'D', 'S', 'N', 'O', 'T', 'E', 0, 0};  // version 3's source note
constexpr size_t kNoteHeadBytes = 16;                                   // magic, then the text's length (u64)
constexpr int kZstdLevel = 3;  // fast; the brick pool is mostly repeated bytes

// Header field offsets [B]. The header is hashed up to kHeaderHashAt.
constexpr size_t kVersionAt = 8, kHeaderBytesAt = 12, kLevelAt = 16, kVoxelAt = 24, kOriginAt = 32,
                 kSourceOffsetAt = 56, kSourceDimsAt = 68, kScannerAt = 80, kChunkWordsAt = 176,
                 kBlockWordsAt = 184, kBrickWordsAt = 192, kCompressedAt = 200, kPayloadHashAt = 208,
                 kHeaderHashAt = 216, kHeaderBytesV1 = 224;
// Version 2 appends the tooth's frame, with its own checksum so that version 1's stays where it was.
constexpr size_t kCrownAt = 224, kMesialAt = 248, kBuccalAt = 272, kCentreAt = 296, kSourcesAt = 320, kTurnAt = 324,
                 kToothHashAt = 344, kHeaderBytes = 352;
// Version 4 uses two of the tooth block's spare bytes (zero in versions 2 and 3, and ignored there):
// 1 when the layers are synthesized, and the tooth type whose proportions made them.
constexpr size_t kLayersAt = 333, kLayerTypeAt = 334;

template <class T>
void put(std::vector<uint8_t>& out, size_t at, T v) {
  std::memcpy(out.data() + at, &v, sizeof(T));
}
template <class T>
T get(std::span<const uint8_t> in, size_t at) {
  T v;
  std::memcpy(&v, in.data() + at, sizeof(T));
  return v;
}

constexpr int minLevel = 3, maxLevel = 13;  // the brick layout's DS_MIN_LEVEL .. DS_MAX_LEVEL
uint64_t chunkEntriesFor(int level) {
  const uint64_t side = level > 6 ? uint64_t{1} << (level - 6) : 1;
  return side * side * side;
}

// A number for a message: at most 10 significant digits, so that 1e300 prints as 1e+300.
std::string num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

// The grid-to-scanner matrix is refused when its 3 x 3 part is singular: its determinant, relative
// to the product of its column lengths, measures how far the columns are from lying in one plane
// (1 for right angles, 0 for flat), and export would write a placement no reader can invert.
bool singularFrame(const std::array<double, 12>& m) {
  const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                     m[2] * (m[4] * m[9] - m[5] * m[8]);
  double lengths = 1.0;
  for (int c = 0; c < 3; ++c) lengths *= std::sqrt(m[c] * m[c] + m[4 + c] * m[4 + c] + m[8 + c] * m[8 + c]);
  return !(lengths > 0.0) || !(std::abs(det) > 1e-9 * lengths);
}

// Inflates one zstd frame straight into the three word arrays, in order, and stops at their end:
// nothing is allocated beyond what the header's counts allow, and a frame that would inflate past
// them is refused at that point, whatever size it declares.
Status inflateInto(std::span<const uint8_t> packed, std::initializer_list<std::vector<uint32_t>*> arrays,
                   const std::string& where) {
  std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> dctx(ZSTD_createDCtx(), &ZSTD_freeDCtx);
  if (!dctx) return makeError(where, "out of memory for the decompressor");
  ZSTD_inBuffer in{packed.data(), packed.size(), 0};
  size_t last = 1;  // ZSTD_decompressStream's hint: 0 once the frame is complete
  for (std::vector<uint32_t>* words : arrays) {
    ZSTD_outBuffer out{words->data(), words->size() * sizeof(uint32_t), 0};
    while (out.pos < out.size) {
      const size_t before_in = in.pos, before_out = out.pos;
      last = ZSTD_decompressStream(dctx.get(), &out, &in);
      if (ZSTD_isError(last))
        return makeError(where, std::string("compressed payload is corrupt (") + ZSTD_getErrorName(last) + ")");
      if (in.pos == before_in && out.pos == before_out)
        return makeError(where, "compressed payload is corrupt (it ends before the size the header gives)");
    }
  }
  // Every array is full: the frame must end here, with no byte left over.
  uint8_t spare = 0;
  ZSTD_outBuffer probe{&spare, 1, 0};
  if (last != 0) last = ZSTD_decompressStream(dctx.get(), &probe, &in);
  if (ZSTD_isError(last) || last != 0 || probe.pos != 0 || in.pos != in.size)
    return makeError(where, "compressed payload is corrupt (it inflates past the size the header gives)");
  return Ok{};
}

// A unit vector (norm within 1e-6 of 1), made exactly unit.
Result<std::array<double, 3>> unitAt(std::span<const uint8_t> in, size_t at, const char* what) {
  std::array<double, 3> v;
  for (int i = 0; i < 3; ++i) v[i] = get<double>(in, at + 8 * i);
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-6) return makeError(what, "not a unit vector");
  for (double& c : v) c /= n;
  return v;
}

// The tooth block of a version 2 header, checked: unit axes at right angles, known sources, a
// finite centre, a proper quarter turn.
Result<ToothAxes> readToothAxes(std::span<const uint8_t> in) {
  ToothAxes t;
  auto crown = unitAt(in, kCrownAt, "crown axis");
  if (!crown) return crown.error();
  auto mesial = unitAt(in, kMesialAt, "mesial axis");
  if (!mesial) return mesial.error();
  auto buccal = unitAt(in, kBuccalAt, "buccal axis");
  if (!buccal) return buccal.error();
  t.crown = *crown;
  t.mesial = *mesial;
  t.buccal = *buccal;
  const auto dot3 = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  if (std::abs(dot3(t.crown, t.mesial)) > 1e-6 || std::abs(dot3(t.crown, t.buccal)) > 1e-6 ||
      std::abs(dot3(t.mesial, t.buccal)) > 1e-6)
    return makeError("axes", "crown, mesial and buccal are not at right angles");
  for (int i = 0; i < 3; ++i) {
    t.occlusal_centre_mm[i] = get<double>(in, kCentreAt + 8 * i);
    if (!std::isfinite(t.occlusal_centre_mm[i])) return makeError("occlusal centre", "not finite");
  }
  for (int i = 0; i < 3; ++i)
    if (in[kSourcesAt + i] > uint8_t(AxisSource::Given)) return makeError("axis source", "unknown value " + std::to_string(in[kSourcesAt + i]));
  t.crown_source = AxisSource(in[kSourcesAt + 0]);
  t.mesial_source = AxisSource(in[kSourcesAt + 1]);
  t.buccal_source = AxisSource(in[kSourcesAt + 2]);
  if (in[kSourcesAt + 3] > 1) return makeError("occlusal centre", "flag is not 0 or 1");
  t.has_occlusal_centre = in[kSourcesAt + 3] == 1;
  int det = 0;
  for (int i = 0; i < 9; ++i) {
    t.turn[i] = int8_t(in[kTurnAt + i]);
    if (t.turn[i] < -1 || t.turn[i] > 1) return makeError("quarter turn", "entries must be -1, 0 or 1");
  }
  const auto& m = t.turn;
  det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
  int nonzero = 0;
  for (int8_t e : m) nonzero += e != 0;
  if (det != 1 || nonzero != 3) return makeError("quarter turn", "not a rotation by quarter turns");
  return t;
}

}  // namespace

std::vector<uint8_t> encodeVolumeFile(const VolumeFileData& d) {
  const VolumeFrame& f = d.frame;
  // Raw payload: the three arrays back to back.
  std::vector<uint8_t> raw((d.chunks.size() + d.blocks.size() + d.bricks.size()) * sizeof(uint32_t));
  size_t at = 0;
  for (const auto* words : {&d.chunks, &d.blocks, &d.bricks}) {
    if (!words->empty()) std::memcpy(raw.data() + at, words->data(), words->size() * sizeof(uint32_t));
    at += words->size() * sizeof(uint32_t);
  }
  std::vector<uint8_t> out(kHeaderBytes + ZSTD_compressBound(raw.size()), 0);
  const size_t packed = ZSTD_compress(out.data() + kHeaderBytes, out.size() - kHeaderBytes, raw.data(), raw.size(), kZstdLevel);
  out.resize(kHeaderBytes + packed);  // ZSTD_compress cannot fail with a bound-sized buffer

  std::memcpy(out.data(), kMagic, sizeof(kMagic));
  put<uint32_t>(out, kVersionAt, 2);  // 3 below, only with a source note
  put<uint32_t>(out, kHeaderBytesAt, uint32_t(kHeaderBytes));
  put<int32_t>(out, kLevelAt, f.level);
  put<double>(out, kVoxelAt, f.voxel_mm);
  for (int i = 0; i < 3; ++i) {
    put<double>(out, kOriginAt + 8 * i, f.origin_mm[i]);
    put<int32_t>(out, kSourceOffsetAt + 4 * i, f.source_offset[i]);
    put<int32_t>(out, kSourceDimsAt + 4 * i, f.source_dims[i]);
  }
  for (int i = 0; i < 12; ++i) put<double>(out, kScannerAt + 8 * i, f.scanner_from_grid[i]);
  put<uint64_t>(out, kChunkWordsAt, d.chunks.size());
  put<uint64_t>(out, kBlockWordsAt, d.blocks.size());
  put<uint64_t>(out, kBrickWordsAt, d.bricks.size());
  put<uint64_t>(out, kCompressedAt, packed);
  put<uint64_t>(out, kPayloadHashAt, XXH64(raw.data(), raw.size(), 0));
  put<uint64_t>(out, kHeaderHashAt, XXH64(out.data(), kHeaderHashAt, 0));
  const ToothAxes& t = f.tooth;
  for (int i = 0; i < 3; ++i) {
    put<double>(out, kCrownAt + 8 * i, t.crown[i]);
    put<double>(out, kMesialAt + 8 * i, t.mesial[i]);
    put<double>(out, kBuccalAt + 8 * i, t.buccal[i]);
    put<double>(out, kCentreAt + 8 * i, t.occlusal_centre_mm[i]);
  }
  out[kSourcesAt + 0] = uint8_t(t.crown_source);
  out[kSourcesAt + 1] = uint8_t(t.mesial_source);
  out[kSourcesAt + 2] = uint8_t(t.buccal_source);
  out[kSourcesAt + 3] = t.has_occlusal_centre ? 1 : 0;
  for (int i = 0; i < 9; ++i) out[kTurnAt + i] = uint8_t(t.turn[i]);
  if (d.layers_synthesized) {
    out[kLayersAt] = 1;
    out[kLayerTypeAt] = d.layer_type;
  }
  put<uint64_t>(out, kToothHashAt, XXH64(out.data() + kCrownAt, kToothHashAt - kCrownAt, 0));
  if (!d.source_note.empty() || d.layers_synthesized) {
    // Version 3: the note follows the payload (magic, length, text, XXH64 of the text); version 4
    // always has it. The header hash covers the version, so it is set before the hash is taken.
    const std::string note = d.source_note.substr(0, kMaxSourceNoteBytes);
    put<uint32_t>(out, kVersionAt, d.layers_synthesized ? 4 : 3);
    put<uint64_t>(out, kHeaderHashAt, XXH64(out.data(), kHeaderHashAt, 0));
    const size_t note_at = out.size();
    out.resize(note_at + kNoteHeadBytes + note.size() + 8);
    std::memcpy(out.data() + note_at, kNoteMagic, sizeof(kNoteMagic));
    put<uint64_t>(out, note_at + 8, note.size());
    std::memcpy(out.data() + note_at + kNoteHeadBytes, note.data(), note.size());
    put<uint64_t>(out, note_at + kNoteHeadBytes + note.size(), XXH64(note.data(), note.size(), 0));
  }
  return out;
}

Status writeVolumeFile(const std::string& path, const VolumeFileData& data) {
  const std::vector<uint8_t> bytes = encodeVolumeFile(data);
  return writeFileAtomic(path, bytes);
}

// Version 3's note after the payload: magic, length, text, checksum, and nothing after it.
Status readSourceNote(std::span<const uint8_t> in, size_t header_bytes, uint64_t packed, std::string& note,
                      const std::string& where) {
  if (packed > in.size() - header_bytes || in.size() - header_bytes - packed < kNoteHeadBytes + 8)
    return makeError(where, "truncated: the source note after the payload is missing");
  const size_t at = header_bytes + size_t(packed);
  if (std::memcmp(in.data() + at, kNoteMagic, sizeof(kNoteMagic)) != 0)
    return makeError(where, "the source note after the payload is corrupt (bad magic)");
  const uint64_t length = get<uint64_t>(in, at + 8);
  if (length > kMaxSourceNoteBytes) return makeError(where, "the source note is over " + std::to_string(kMaxSourceNoteBytes) + " bytes");
  if (in.size() - at - kNoteHeadBytes - 8 != length)
    return makeError(where, "truncated or padded source note (" + std::to_string(in.size() - at - kNoteHeadBytes - 8) +
                                " bytes where it says " + std::to_string(length) + ")");
  const char* text = reinterpret_cast<const char*>(in.data() + at + kNoteHeadBytes);
  if (get<uint64_t>(in, at + kNoteHeadBytes + size_t(length)) != XXH64(text, size_t(length), 0))
    return makeError(where, "source note checksum mismatch: the file is corrupt");
  note.assign(text, size_t(length));
  for (char c : note)
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\n') || c == 0x7f)
      return makeError(where, "the source note holds a control character");
  return Ok{};
}

Result<VolumeFileData> parseVolumeFile(std::span<const uint8_t> in, const std::string& where, uint64_t max_raw_bytes) {
  if (in.size() < kHeaderBytesV1) {
    if (in.size() >= sizeof(kMagic) && std::memcmp(in.data(), kMagic, sizeof(kMagic)) == 0)
      return makeError(where, "truncated header (" + std::to_string(in.size()) + " bytes)");
    if (auto other = refuseOtherKind(in, FileKind::Dvol, where, "a dentsim volume (.dvol)")) return *other;
    return makeError(where, "not a dentsim volume file (too short)");
  }
  if (std::memcmp(in.data(), kMagic, sizeof(kMagic)) != 0) {
    if (auto other = refuseOtherKind(in, FileKind::Dvol, where, "a dentsim volume (.dvol)")) return *other;
    return makeError(where, "not a dentsim volume file (bad magic)");
  }
  if (get<uint64_t>(in, kHeaderHashAt) != XXH64(in.data(), kHeaderHashAt, 0))
    return makeError(where, "header checksum mismatch: the file is corrupt");
  const uint32_t version = get<uint32_t>(in, kVersionAt);
  if (version < 1 || version > kVolumeFileVersion)
    return makeError(where, "unsupported volume file version " + std::to_string(version) + " (this dentsim reads 1 to " +
                                std::to_string(kVolumeFileVersion) + ")");
  const size_t header_bytes = version == 1 ? kHeaderBytesV1 : kHeaderBytes;
  if (get<uint32_t>(in, kHeaderBytesAt) != header_bytes) return makeError(where, "unexpected header size");
  if (in.size() < header_bytes) return makeError(where, "truncated header (" + std::to_string(in.size()) + " bytes)");

  VolumeFileData d;
  VolumeFrame& f = d.frame;
  if (version >= 2) {
    if (get<uint64_t>(in, kToothHashAt) != XXH64(in.data() + kCrownAt, kToothHashAt - kCrownAt, 0))
      return makeError(where, "tooth frame checksum mismatch: the file is corrupt");
    auto tooth = readToothAxes(in);
    if (!tooth) return makeError(where, "tooth frame: " + tooth.message());
    f.tooth = *tooth;
  }
  if (version >= 4) {
    if (in[kLayersAt] > 1) return makeError(where, "layer provenance is not 0 or 1");
    if (in[kLayerTypeAt] > kMaxLayerTypeCode)
      return makeError(where, "unknown synthesized tooth type " + std::to_string(in[kLayerTypeAt]));
    d.layers_synthesized = in[kLayersAt] == 1;
    d.layer_type = d.layers_synthesized ? in[kLayerTypeAt] : 0;
  }
  f.level = get<int32_t>(in, kLevelAt);
  if (f.level < minLevel || f.level > maxLevel)
    return makeError(where, "grid level " + std::to_string(f.level) + " outside 3..13");
  f.voxel_mm = get<double>(in, kVoxelAt);
  if (!(f.voxel_mm >= kMinVoxelMm && f.voxel_mm <= kMaxVoxelMm))
    return makeError(where, "voxel size " + num(f.voxel_mm) + " mm is outside " + num(kMinVoxelMm) + " .. " +
                                num(kMaxVoxelMm) + " mm");
  bool finite = true;
  for (int i = 0; i < 3; ++i) {
    f.origin_mm[i] = get<double>(in, kOriginAt + 8 * i);
    f.source_offset[i] = get<int32_t>(in, kSourceOffsetAt + 4 * i);
    f.source_dims[i] = get<int32_t>(in, kSourceDimsAt + 4 * i);
    finite = finite && std::isfinite(f.origin_mm[i]);
  }
  for (int i = 0; i < 12; ++i) {
    f.scanner_from_grid[i] = get<double>(in, kScannerAt + 8 * i);
    finite = finite && std::isfinite(f.scanner_from_grid[i]);
  }
  if (!finite) return makeError(where, "origin or scanner matrix is not finite");
  if (singularFrame(f.scanner_from_grid))
    return makeError(where, "scanner matrix is singular (its axes are zero or lie in one plane)");
  const int64_t dim = f.dim();
  for (int i = 0; i < 3; ++i) {
    const int64_t lo = f.source_offset[i], n = f.source_dims[i];
    if (n < 0 || lo < 0 || lo + n > dim) return makeError(where, "source box lies outside the grid");
  }

  const uint64_t chunk_words = get<uint64_t>(in, kChunkWordsAt);
  const uint64_t block_words = get<uint64_t>(in, kBlockWordsAt);
  const uint64_t brick_words = get<uint64_t>(in, kBrickWordsAt);
  const uint64_t packed = get<uint64_t>(in, kCompressedAt);
  if (chunk_words != chunkEntriesFor(f.level))
    return makeError(where, "chunk table size does not match level " + std::to_string(f.level));
  if (block_words % 512 != 0 || brick_words % 128 != 0) return makeError(where, "index or brick pool is not whole");
  // Each count is checked alone first so that the sum cannot overflow; all of it before anything is
  // allocated.
  const uint64_t limit_words = max_raw_bytes / 4;
  if (block_words > limit_words || brick_words > limit_words || chunk_words + block_words + brick_words > limit_words) {
    const uint64_t claimed = block_words > limit_words || brick_words > limit_words
                                 ? std::max(block_words, brick_words) * 4
                                 : (chunk_words + block_words + brick_words) * 4;
    return makeError(where, limitExceeded("payload of " + std::to_string(claimed) + " bytes", max_raw_bytes));
  }
  const uint64_t raw_bytes = (chunk_words + block_words + brick_words) * 4;
  if (version >= 3) {
    if (Status s = readSourceNote(in, header_bytes, packed, d.source_note, where); !s) return s.error();
    in = in.first(header_bytes + packed);
  }
  if (packed != in.size() - header_bytes)
    return makeError(where, in.size() - header_bytes < packed
                                ? "truncated: payload has " + std::to_string(in.size() - header_bytes) + " of " +
                                      std::to_string(packed) + " bytes"
                                : "unexpected bytes after the payload");
  // The frame's own size (absent or wrong in a forged one) must be what the counts say.
  const unsigned long long declared = ZSTD_getFrameContentSize(in.data() + header_bytes, packed);
  if (declared != raw_bytes) return makeError(where, "compressed payload is corrupt (size mismatch)");

  d.chunks.resize(chunk_words);
  d.blocks.resize(block_words);
  d.bricks.resize(brick_words);
  if (Status s = inflateInto(in.subspan(header_bytes, packed), {&d.chunks, &d.blocks, &d.bricks}, where); !s)
    return s.error();
  std::unique_ptr<XXH64_state_t, decltype(&XXH64_freeState)> hash(XXH64_createState(), &XXH64_freeState);
  XXH64_reset(hash.get(), 0);
  for (const auto* words : {&d.chunks, &d.blocks, &d.bricks})
    XXH64_update(hash.get(), words->data(), words->size() * sizeof(uint32_t));
  if (XXH64_digest(hash.get()) != get<uint64_t>(in, kPayloadHashAt))
    return makeError(where, "payload checksum mismatch: the file is corrupt");
  return d;
}

Result<bool> readLayersSynthesized(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return makeError(path, "cannot open the file");
  std::vector<uint8_t> head(kHeaderBytes, 0);
  file.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
  const std::span<const uint8_t> in(head.data(), size_t(file.gcount()));
  if (in.size() < kHeaderBytesV1 || std::memcmp(in.data(), kMagic, sizeof(kMagic)) != 0)
    return makeError(path, "not a dentsim volume file");
  if (get<uint64_t>(in, kHeaderHashAt) != XXH64(in.data(), kHeaderHashAt, 0))
    return makeError(path, "header checksum mismatch: the file is corrupt");
  const uint32_t version = get<uint32_t>(in, kVersionAt);
  if (version < 1 || version > kVolumeFileVersion) return makeError(path, "unsupported volume file version");
  if (version < 4) return false;
  if (in.size() < kHeaderBytes || get<uint64_t>(in, kToothHashAt) != XXH64(in.data() + kCrownAt, kToothHashAt - kCrownAt, 0))
    return makeError(path, "tooth frame checksum mismatch: the file is corrupt");
  return in[kLayersAt] == 1;
}

Result<VolumeFileData> readVolumeFile(const std::string& path, uint64_t max_raw_bytes) {
  // zstd gains at least 1/8 on any payload we write, so a file this large is never legitimate.
  auto bytes = readFileBytes(path, max_raw_bytes + (max_raw_bytes >> 3) + 4096 + kMaxSourceNoteBytes);
  if (!bytes) return bytes.error();
  return parseVolumeFile(*bytes, path, max_raw_bytes);
}

}  // namespace dentsim
