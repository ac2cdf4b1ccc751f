// The three-slice series the DICOM fuzzer reads its input in, shared with the seed writer so that the seeds join it.
#pragma once

#include "io/dicom_series.h"

namespace dentsim::fuzz {

// Fixed, not generated: a seed must carry the fuzzer's series UID, or every read stops at "mixed
// series" and the fuzzer never reaches the grid, geometry and pixel checks. (2.25: a UID from a number.)
inline constexpr const char* kDicomFuzzSeriesUid = "2.25.40402026112900000000000000000001";

// 8 x 6 pixels of 0.5 mm, 3 slices 0.5 mm apart at the origin; the input replaces the middle slice
// (slice-0002.dcm; the writer numbers from 1), so it must fit between its neighbours.
inline GreyImage dicomFuzzImage() {
  GreyImage g;
  g.dims = {8, 6, 3};
  g.scanner_from_voxel = {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0};
  g.values.resize(144);
  for (size_t n = 0; n < g.values.size(); ++n) g.values[n] = float(n) * 10.0f - 500.0f;  // a ramp [HU]
  return g;
}

inline DicomWriteOptions dicomFuzzOptions() {
  DicomWriteOptions o;
  o.series_uid = kDicomFuzzSeriesUid;
  return o;
}

inline constexpr const char* kDicomFuzzSlice = "slice-0002.dcm";

}  // namespace dentsim::fuzz
