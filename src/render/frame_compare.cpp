// Frame against frame: mean absolute difference, covered pixels and crack pixels.
#include "render/frame_compare.h"

#include <cassert>
#include <cstdlib>

namespace dentsim::render {

FrameDifference compareFrames(const RgbImage& reference, const RgbImage& image, const std::array<uint8_t, 3>& background) {
  assert(reference.width == image.width && reference.height == image.height);
  FrameDifference d;
  const int w = reference.width, h = reference.height;
  const auto is_background = [&](const RgbImage& img, int x, int y) {
    const size_t o = (size_t(y) * size_t(w) + size_t(x)) * 3;
    return img.rgb[o] == background[0] && img.rgb[o + 1] == background[1] && img.rgb[o + 2] == background[2];
  };
  uint64_t sum = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t o = (size_t(y) * size_t(w) + size_t(x)) * 3;
      int most = 0;
      for (int c = 0; c < 3; ++c) {
        const int diff = std::abs(int(reference.rgb[o + size_t(c)]) - int(image.rgb[o + size_t(c)]));
        sum += uint64_t(diff);
        most = diff > most ? diff : most;
      }
      if (most > 8) ++d.differing;
      if (is_background(reference, x, y)) continue;
      ++d.covered;
      if (!is_background(image, x, y)) continue;
      bool inside = x >= 2 && y >= 2 && x + 2 < w && y + 2 < h;
      for (int dy = -2; dy <= 2 && inside; ++dy)
        for (int dx = -2; dx <= 2 && inside; ++dx) inside = !is_background(reference, x + dx, y + dy);
      if (inside) ++d.cracks;
    }
  d.mean_abs = w * h > 0 ? double(sum) / (3.0 * double(w) * double(h)) : 0.0;
  return d;
}

}  // namespace dentsim::render
