// ToothVolume <-> .dvol: the io layer moves words, this layer checks what they mean.
#include "volume/tooth_file.h"

#include <algorithm>

#include "io/dvol_file.h"

namespace dentsim {

Status saveTooth(const std::string& path, ToothVolume& tooth) {
  tooth.voxels.compact();
  VolumeFileData d;
  d.frame = tooth.frame;
  d.frame.level = tooth.voxels.level();
  const auto copy = [](std::span<const uint32_t> s) { return std::vector<uint32_t>(s.begin(), s.end()); };
  d.chunks = copy(tooth.voxels.chunkWords());
  d.blocks = copy(tooth.voxels.blockWords());
  d.bricks = copy(tooth.voxels.brickWords());
  d.source_note = tooth.source_note;
  d.layers_synthesized = tooth.layers == LayerSource::Synthesized;
  d.layer_type = d.layers_synthesized ? std::min(tooth.synthesized_type, kMaxLayerTypeCode) : 0;
  return writeVolumeFile(path, d);
}

namespace {

Result<ToothVolume> toothOf(Result<VolumeFileData> file, const std::string& where) {
  if (!file) return file.error();
  VolumeFileData& d = *file;
  auto voxels = BrickVolume::fromWords(d.frame.level, std::move(d.chunks), std::move(d.blocks), std::move(d.bricks), where);
  if (!voxels) return voxels.error();
  return ToothVolume{d.frame, std::move(*voxels), std::move(d.source_note),
                     d.layers_synthesized ? LayerSource::Synthesized : LayerSource::Measured, d.layer_type};
}

}  // namespace

Result<ToothVolume> loadTooth(const std::string& path) { return toothOf(readVolumeFile(path), path); }

Result<ToothVolume> parseTooth(std::span<const uint8_t> bytes, const std::string& where) {
  return toothOf(parseVolumeFile(bytes, where), where);
}

}  // namespace dentsim
