// Formats told apart by their first bytes, so that a reader handed the wrong kind of file names what it really is.
//
// Each reader calls refuseOtherKind() once its own format's check has failed (an STL's size does
// not match its count, a PLY lacks "ply"), never before: a binary STL's free 80-byte header may
// begin with anything, so a file that passes its own format's check is that format.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "core/result.h"

namespace dentsim {

enum class FileKind {
  Unknown,
  Ply,      // "ply\n" (or "ply\r\n")
  Gzip,     // 1f 8b
  Zstd,     // 28 b5 2f fd
  Nifti1,   // sizeof_hdr 348 (either byte order) and magic "n+1"/"ni1" at byte 344
  Nifti2,   // sizeof_hdr 540 (either byte order) and magic "n+2"/"ni2" at byte 4
  Dvol,     // "DENTSIMV" (dentsim's volume file)
  Dses,     // "DSESSION" (dentsim's session recording)
  Wav,      // "RIFF" size "WAVE"
  Png,      // 89 "PNG" 0d 0a 1a 0a
};

// Bytes of a file's start that sniffFileKind needs to tell every kind apart.
inline constexpr size_t kFileKindHeadBytes = 352;

// The kind a file's first bytes show (`head` may be shorter than kFileKindHeadBytes).
FileKind sniffFileKind(std::span<const uint8_t> head);
// "PLY mesh", "gzip-compressed", "NIfTI-1 image", ...: what a message calls the kind.
const char* fileKindName(FileKind kind);

// When `head` shows a known kind other than `expected`, the error
// "<where>: this is a <kind> file, not <expected_name>" (with a hint for compressed files);
// otherwise nullopt. `expected` itself is never refused.
std::optional<Error> refuseOtherKind(std::span<const uint8_t> head, FileKind expected, const std::string& where,
                                     const std::string& expected_name);

}  // namespace dentsim
