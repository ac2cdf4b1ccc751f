// How far a frame drawn with screen-sized detail is from the full-detail frame of the same state: grey levels, and holes where the background shows through.
#pragma once

#include <array>
#include <cstdint>

#include "io/png_file.h"

namespace dentsim::render {

struct FrameDifference {
  double mean_abs = 0.0;          // mean over pixels and channels of |image - reference| [grey levels 0..255]
  uint64_t differing = 0;         // pixels whose largest channel difference is over 8 grey levels
  uint64_t covered = 0;           // pixels of the reference that are not background
  uint64_t cracks = 0;            // pixels where the image shows background inside the reference's cover
};

// Compares `image` with `reference` (same size). A crack pixel shows `background` exactly in the
// image, while the reference shows something there and at every pixel within 2 pixels of it: a hole
// in a surface, not a silhouette one pixel narrower. Precondition: equal sizes.
FrameDifference compareFrames(const RgbImage& reference, const RgbImage& image, const std::array<uint8_t, 3>& background);

}  // namespace dentsim::render
