// NIfTI-1/-2 volumes (.nii, .nii.gz) through libnifti: segmented labels (checked reading, atomic writing), and a scanner's grey values.
//
// Contents
//   1. LabelImage: a label grid and where it sits in the scanner
//   2. Entry points: readNiftiLabels, writeNiftiLabels
//   3. Rules the reader applies to hostile or unusual files
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"
#include "io/grey_image.h"
#include "io/input_budget.h"

namespace dentsim {

// ---- 1. LabelImage --------------------------------------------------------------------------
// Labels are stored as int16: a 600 x 600 x 400 micro-CT holds 144M voxels, which is 288 MB as
// int16 and 576 MB as int32, and segmentations use small codes. A file whose labels do not fit in
// int16 (possible with uint16, int32, uint32 or float data) is refused with the offending value.
using Label = int16_t;

struct LabelImage {
  std::array<int32_t, 3> dims{0, 0, 0};         // voxels along i, j, k
  std::array<double, 3> pitch_mm{1.0, 1.0, 1.0}; // voxel edge along i, j, k [mm]
  // Scanner position [mm] of the centre of voxel (i,j,k): row r is
  // m[4r+0]*i + m[4r+1]*j + m[4r+2]*k + m[4r+3]  (3 x 4, row-major).
  std::array<double, 12> scanner_from_voxel{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  std::vector<Label> labels;                     // (dims[0] * dims[1] * dims[2]), i fastest

  int64_t voxelCount() const { return int64_t{dims[0]} * dims[1] * dims[2]; }
  size_t index(int64_t i, int64_t j, int64_t k) const {
    return static_cast<size_t>(i + dims[0] * (j + int64_t{dims[1]} * k));
  }
};

// Bounds the reader enforces before it allocates anything.
struct NiftiReadLimits {
  int64_t max_voxels = int64_t{1} << 30;    // 1024^3 voxels
  uint64_t max_bytes = uint64_t{4} << 30;   // voxel data as stored in the file [B]
  // The labels in memory (2 bytes a voxel), the only full-size copy the reader makes [B]; by
  // default the input budget (io/input_budget.h), raised with --max-input-mb.
  uint64_t max_label_bytes = inputBudget().max_bytes;
  // Grey values only: asked before the floats are allocated (io/grey_image.h); empty: no plan.
  ScanReadApproval approve;
};

// ---- 2. Entry points ------------------------------------------------------------------------
// Reads a 3D label image from a .nii or .nii.gz file (NIfTI-1 or NIfTI-2, either byte order).
// Every error is one line "PATH: problem" (missing file, not a regular file, not a NIfTI file or
// another known kind named, truncated, unsupported datatype, oversized or wrong dimensionality, over
// the input budget, scaled data, labels out of range, no label at all).
Result<LabelImage> readNiftiLabels(const std::string& path, const NiftiReadLimits& limits = {});

// Writes `image` as NIfTI-1 with uint8 labels (every label must be in 0..255), gzip-compressed when
// `path` ends in ".nii.gz". pixdim = pitch, qform and sform both scanner (code 1) from
// scanner_from_voxel, units mm. The file appears atomically: a temporary sibling, then a rename.
Status writeNiftiLabels(const std::string& path, const LabelImage& image);

// Reads a scanner's grey values (a CT, CBCT or micro-CT exported by 3D Slicer or a scanner's
// software) from a .nii or .nii.gz file, under the same checks as the labels, except that any of the
// datatypes is taken as it is and scl_slope/scl_inter are applied (slope 0: none). The floats must
// fit twice limits.max_label_bytes (the same input budget: 4 bytes a voxel rather than 2). The unit is
// Raw: NIfTI does not say whether values are Hounsfield units. Errors as readNiftiLabels ("holds no
// scan" when every voxel is 0).
Result<GreyImage> readNiftiGrey(const std::string& path, const NiftiReadLimits& limits = {});

// libnifti reads only from files, so there is no in-memory parser: fuzz tests write their mutated
// bytes to a temporary file and call readNiftiLabels.

// ---- 3. Reader rules ------------------------------------------------------------------------
// - The name must end in .nii or .nii.gz and the header must carry the single-file magic
//   ("n+1" or "n+2"): a two-file .hdr/.img pair or an Analyze header is refused.
// - dim[0] is 3, or 4/5 with the extra dimensions equal to 1. Each extent is positive, the product
//   is within limits.max_voxels and the stored bytes within limits.max_bytes.
// - Datatypes: uint8, int8, int16, uint16, int32, uint32; float32/float64 only when every value is
//   an exact integer (libnifti itself replaces NaN and infinity by 0 while reading floats).
// - scl_slope/scl_inter must be the identity (slope 0, or slope 1 with intercept 0): scaling a
//   label would change its meaning, so a scaled file is refused rather than guessed at.
// - pixdim[1..3] must be finite and positive. Spatial units metre and micron are converted to mm;
//   unknown units are taken as mm.
// - The scanner matrix comes from the sform when sform_code > 0, else the qform when
//   qform_code > 0, else the pitch alone; it must be finite and non-singular.
// - Uncompressed files must hold all the voxel bytes the header promises (checked before
//   allocating); a gzip file whose stored size could not possibly inflate to them (deflate
//   compresses at most about 1032:1) is refused before allocating too, and any short read while
//   inflating is reported as truncated.
// - Only a regular file is opened (a FIFO or a device is refused before libnifti can block on it).
// - The labels (2 bytes a voxel) must fit limits.max_label_bytes, checked from the header before
//   they are allocated; the voxels are then streamed from the file in 1 MiB slabs, so memory is
//   the labels alone whatever the stored type, and a gzip bomb costs no more than its labels.
// - At least one voxel must hold a label other than 0: a volume of zeros "holds no tooth".

}  // namespace dentsim
