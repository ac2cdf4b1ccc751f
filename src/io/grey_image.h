// A scanner's grey-value volume (CT, CBCT, micro-CT) as read from DICOM, NIfTI or NRRD: the values, where they sit, and what they mean.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/result.h"

namespace dentsim {

// A scan reader's question once the header says the size and before it allocates the values: may
// `voxels` be read, with `stored_bytes` a voxel held at once as the file stores them besides the
// floats (0 where the reader goes slice by slice)? A command's memory plan answers
// (volume/voxelize_plan.h); an error refuses the read, as it is.
using ScanReadApproval = std::function<Status(uint64_t voxels, uint32_t stored_bytes)>;

// A scanner matrix (3 x 4, as in GreyImage and LabelImage) with each voxel axis rescaled to `pitch`,
// direction, sign and offset kept: a header's wrong pitch replaced by the true one (--voxel-size).
inline std::array<double, 12> scannerWithPitch(const std::array<double, 12>& m, const std::array<double, 3>& pitch) {
  std::array<double, 12> out = m;
  for (size_t c = 0; c < 3; ++c) {
    const double len = std::sqrt(m[c] * m[c] + m[4 + c] * m[4 + c] + m[8 + c] * m[8 + c]);
    for (size_t r = 0; r < 3; ++r) out[4 * r + c] = len > 0 ? m[4 * r + c] / len * pitch[c] : 0.0;
  }
  return out;
}

// What a grey value measures. A DICOM CT series with rescale type HU (or modality CT and no
// rescale type) is in Hounsfield units; everything else (most CBCT and micro-CT exports, NIfTI and
// NRRD files) is a raw scanner value whose scale only the scanner knows.
enum class GreyUnit { Hounsfield, Raw };

inline const char* greyUnitName(GreyUnit u) { return u == GreyUnit::Hounsfield ? "HU" : "raw"; }

// Float holds every value a scanner writes: 16-bit stored values, signed or not, after a rescale
// slope and intercept that need not be integers. A 600 x 600 x 400 micro-CT is 576 MB as float.
struct GreyImage {
  std::array<int32_t, 3> dims{0, 0, 0};          // voxels along i, j, k
  std::array<double, 3> pitch_mm{1.0, 1.0, 1.0}; // voxel edge along i, j, k [mm]
  // Scanner position [mm] of the centre of voxel (i,j,k): row r is
  // m[4r+0]*i + m[4r+1]*j + m[4r+2]*k + m[4r+3]  (3 x 4, row-major), as in LabelImage.
  std::array<double, 12> scanner_from_voxel{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  std::vector<float> values;  // (dims[0] * dims[1] * dims[2]), i fastest
  GreyUnit unit = GreyUnit::Raw;
  // From the file's header where it has them (DICOM), else empty: `info`-style reports and the
  // choice of a scanner preset read them.
  std::string modality;      // CT, CBCT exports often say CT too
  std::string manufacturer;  // e.g. "Planmeca"
  std::string model;         // the scanner's model name
  std::string description;   // series description

  int64_t voxelCount() const { return int64_t{dims[0]} * dims[1] * dims[2]; }
  size_t index(int64_t i, int64_t j, int64_t k) const {
    return static_cast<size_t>(i + dims[0] * (j + int64_t{dims[1]} * k));
  }
};

}  // namespace dentsim
