// libFuzzer entry for the .dvol reader and brick-index validation.
#include <cstddef>
#include <cstdint>

#include "io/dvol_file.h"
#include "volume/brick_volume.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto file = dentsim::parseVolumeFile(std::span(data, size), "fuzz.dvol", uint64_t{256} << 20);
  if (!file) return 0;
  auto v = dentsim::BrickVolume::fromWords(file->frame.level, std::move(file->chunks), std::move(file->blocks),
                                           std::move(file->bricks), "fuzz.dvol");
  if (v) (void)v->materialTotals();
  return 0;
}
