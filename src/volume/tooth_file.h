// Loading and saving a ToothVolume as a .dvol file, with every entry of the brick index checked.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "core/result.h"
#include "volume/brick_volume.h"

namespace dentsim {

// Compacts the voxels (so the file has no holes) and writes `path` atomically.
Status saveTooth(const std::string& path, ToothVolume& tooth);
// Reads `path`; errors name the file and the problem (checksum, truncation, bad entry, ...).
Result<ToothVolume> loadTooth(const std::string& path);
// The same from bytes in memory (an embedded course tooth); `where` names them in errors.
Result<ToothVolume> parseTooth(std::span<const uint8_t> bytes, const std::string& where);

}  // namespace dentsim
