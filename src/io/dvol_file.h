// The .dvol volume file: versioned, zstd-compressed, checksummed, written atomically.
//
// Layout (little-endian): a 352-byte header (magic "DENTSIMV", version, grid frame, array counts,
// sizes, XXH64 of the raw payload and of the first 216 bytes; then the tooth's frame with its own
// XXH64; version 1 ends its 224-byte header before the tooth), then one zstd frame holding the raw payload: the
// chunk, block and brick words of the brick volume, in that order. io reads and writes the words;
// dentsim_volume checks what they mean (BrickVolume::fromWords).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/volume_frame.h"

namespace dentsim {

inline constexpr uint32_t kVolumeFileVersion = 2;  // 2 adds the tooth frame; version 1 files load with the default frame
inline constexpr uint64_t kVolumeFileDefaultMaxBytes = uint64_t{8} << 30;  // raw payload limit [B]

struct VolumeFileData {
  VolumeFrame frame;               // grid placement
  std::vector<uint32_t> chunks;    // (chunkDim^3) chunk entries
  std::vector<uint32_t> blocks;    // (blockCount x 512) brick entries
  std::vector<uint32_t> bricks;    // (brickCount x 128) packed voxels
};

// Writes atomically; an error names the path.
Status writeVolumeFile(const std::string& path, const VolumeFileData& data);
// Reads and checks magic, version, sizes, limits and checksums; the payload must not inflate
// past max_raw_bytes. Every error is one line naming the path and the problem.
Result<VolumeFileData> readVolumeFile(const std::string& path,
                                      uint64_t max_raw_bytes = kVolumeFileDefaultMaxBytes);
// The same checks on bytes in memory (the fuzz tests call this); `where` names the source.
Result<VolumeFileData> parseVolumeFile(std::span<const uint8_t> bytes, const std::string& where,
                                       uint64_t max_raw_bytes = kVolumeFileDefaultMaxBytes);
// Serialises to bytes (what writeVolumeFile writes).
std::vector<uint8_t> encodeVolumeFile(const VolumeFileData& data);

}  // namespace dentsim
