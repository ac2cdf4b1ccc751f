// The .dvol volume file: versioned, zstd-compressed, checksummed, written atomically.
//
// Layout (little-endian): a 352-byte header (magic "DENTSIMV", version, grid frame, array counts,
// sizes, XXH64 of the raw payload and of the first 216 bytes; then the tooth's frame with its own
// XXH64, from version 4 with the layers' provenance in it; version 1 ends its 224-byte header before the tooth), then one zstd frame holding the raw payload: the
// chunk, block and brick words of the brick volume, in that order. io reads and writes the words;
// dentsim_volume checks what they mean (BrickVolume::fromWords).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/volume_frame.h"
#include "io/input_budget.h"

namespace dentsim {

// 2 adds the tooth frame (version 1 files load with the default frame); 3 adds a source note after
// the payload, and is written only when there is a note, so files without one stay version 2; 4 adds
// the layers' provenance to the tooth block (always with a note, empty or not), written only for
// synthesized layers, so measured teeth stay readable by a dentsim that knows 3.
inline constexpr uint32_t kVolumeFileVersion = 4;
inline constexpr uint8_t kMaxLayerTypeCode = 4;  // volume/tooth_layer_synth.h's ToothType: 0 unknown .. 4 incisor
inline constexpr size_t kMaxSourceNoteBytes = 64 * 1024;  // a source note's longest text [B]
// Voxel edges a file may give [mm]: 1 nm up to 10 cm. Below, the grid of even level 13 spans less
// than a cell; above, one voxel is larger than any tooth or jaw.
inline constexpr double kMinVoxelMm = 1e-6, kMaxVoxelMm = 100.0;

struct VolumeFileData {
  VolumeFrame frame;               // grid placement
  std::vector<uint32_t> chunks;    // (chunkDim^3) chunk entries
  std::vector<uint32_t> blocks;    // (blockCount x 512) brick entries
  std::vector<uint32_t> bricks;    // (brickCount x 128) packed voxels
  // Where the voxels came from and what was chosen on the way (a scan's thresholds, its tooth's box),
  // as lines of text for `dentsim info`; empty: none recorded. Printable text and newlines only.
  std::string source_note;
  // Whether enamel, dentin and pulp were synthesized from one closed surface rather than measured;
  // versions before 4 load as measured.
  bool layers_synthesized = false;
  uint8_t layer_type = 0;  // with layers_synthesized: the tooth type code whose proportions were used (0..kMaxLayerTypeCode)
};

// Writes atomically; an error names the path. A note longer than kMaxSourceNoteBytes is cut there.
Status writeVolumeFile(const std::string& path, const VolumeFileData& data);
// Reads and checks magic (naming the real format of another kind of file), version, sizes,
// limits, frame (voxel size within kMinVoxelMm..kMaxVoxelMm, a finite non-singular matrix) and
// checksums. The raw payload the header's counts give must fit max_raw_bytes (by default the input
// budget, io/input_budget.h) before anything is allocated, and the zstd frame is inflated straight
// into the arrays with a hard stop at that size, so a small file never costs more than its counts
// allow. Every error is one line naming the path and the problem.
Result<VolumeFileData> readVolumeFile(const std::string& path, uint64_t max_raw_bytes = inputBudget().max_bytes);
// The same checks on bytes in memory (the fuzz tests call this); `where` names the source.
Result<VolumeFileData> parseVolumeFile(std::span<const uint8_t> bytes, const std::string& where,
                                       uint64_t max_raw_bytes = inputBudget().max_bytes);
// Whether a volume file's layers are synthesized, from its header alone (magic, version and the
// header's and tooth block's checksums checked, not the payload), for a list that shows many files.
// Errors: the file cannot be read, or its header is not a sound .dvol header; one line naming it.
Result<bool> readLayersSynthesized(const std::string& path);
// Serialises to bytes (what writeVolumeFile writes).
std::vector<uint8_t> encodeVolumeFile(const VolumeFileData& data);

}  // namespace dentsim
