// Magic-byte recognition of the formats dentsim reads or may be handed by mistake.
#include "io/file_kind.h"

#include <cstring>

namespace dentsim {
namespace {

bool startsWith(std::span<const uint8_t> head, const char* magic, size_t n, size_t at = 0) {
  return head.size() >= at + n && std::memcmp(head.data() + at, magic, n) == 0;
}

// sizeof_hdr, the first 32-bit word of a NIfTI header, in either byte order.
bool headerSizeIs(std::span<const uint8_t> head, uint32_t size) {
  if (head.size() < 4) return false;
  const uint32_t le = uint32_t(head[0]) | uint32_t(head[1]) << 8 | uint32_t(head[2]) << 16 | uint32_t(head[3]) << 24;
  const uint32_t be = uint32_t(head[3]) | uint32_t(head[2]) << 8 | uint32_t(head[1]) << 16 | uint32_t(head[0]) << 24;
  return le == size || be == size;
}

}  // namespace

FileKind sniffFileKind(std::span<const uint8_t> head) {
  if (startsWith(head, "ply\n", 4) || startsWith(head, "ply\r\n", 5)) return FileKind::Ply;
  if (startsWith(head, "\x1f\x8b", 2)) return FileKind::Gzip;
  if (startsWith(head, "\x28\xb5\x2f\xfd", 4)) return FileKind::Zstd;
  if (startsWith(head, "DENTSIMV", 8)) return FileKind::Dvol;
  if (startsWith(head, "DSESSION", 8)) return FileKind::Dses;
  if (startsWith(head, "RIFF", 4) && startsWith(head, "WAVE", 4, 8)) return FileKind::Wav;
  if (startsWith(head, "\x89PNG\r\n\x1a\n", 8)) return FileKind::Png;
  // The magic's 4th byte is NUL in both NIfTI versions.
  if (headerSizeIs(head, 348) && (startsWith(head, "n+1", 4, 344) || startsWith(head, "ni1", 4, 344)))
    return FileKind::Nifti1;
  if (headerSizeIs(head, 540) && (startsWith(head, "n+2", 4, 4) || startsWith(head, "ni2", 4, 4)))
    return FileKind::Nifti2;
  return FileKind::Unknown;
}

const char* fileKindName(FileKind kind) {
  switch (kind) {
    case FileKind::Ply: return "PLY mesh";
    case FileKind::Gzip: return "gzip-compressed";
    case FileKind::Zstd: return "zstd-compressed";
    case FileKind::Nifti1: return "NIfTI-1 image";
    case FileKind::Nifti2: return "NIfTI-2 image";
    case FileKind::Dvol: return "dentsim volume (.dvol)";
    case FileKind::Dses: return "dentsim session (.dses)";
    case FileKind::Wav: return "WAV sound";
    case FileKind::Png: return "PNG picture";
    case FileKind::Unknown: break;
  }
  return "unknown";
}

std::optional<Error> refuseOtherKind(std::span<const uint8_t> head, FileKind expected, const std::string& where,
                                     const std::string& expected_name) {
  const FileKind found = sniffFileKind(head);
  if (found == FileKind::Unknown || found == expected) return std::nullopt;
  std::string text = std::string("this is a ") + fileKindName(found) + " file, not " + expected_name;
  // A .nii.gz is a gzip file too: the hint says what the compressed bytes may hold.
  if (found == FileKind::Gzip) text += " (perhaps a .nii.gz label volume; decompress it or pass it where that kind is read)";
  if (found == FileKind::Zstd) text += " (decompress it first)";
  return makeError(where, text);
}

}  // namespace dentsim
