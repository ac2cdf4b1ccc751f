// PNG images: an RGB picture in memory, encoded and written atomically through stb, and read back.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"

namespace dentsim {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;    // (height x width x 3), row 0 at the top
  std::array<uint8_t, 3> pixel(int x, int y) const {
    const size_t o = (size_t(y) * size_t(width) + size_t(x)) * 3;
    return {rgb[o], rgb[o + 1], rgb[o + 2]};
  }
};

// PNG bytes of an image.
Result<std::vector<uint8_t>> encodePng(const RgbImage& image);
// Writes a PNG atomically (temporary sibling, fsync, rename). Errors name the path.
Status writePng(const std::string& path, const RgbImage& image);
// Reads a PNG as RGB (grey and alpha are converted; alpha is dropped). Errors name the path.
Result<RgbImage> readPng(const std::string& path);

}  // namespace dentsim
