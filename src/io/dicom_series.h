// A scanner's DICOM files (CT, CBCT, micro-CT) read through GDCM into one grey-value volume, and a series written back for tests and teaching material.
//
// Contents
//   1. What the reader reports of a series (DicomSeriesInfo)
//   2. readDicomSeries: a folder (or one multi-frame file) into a GreyImage
//   3. readDicomFile: one file's frames, for checks of single files
//   4. writeDicomSeries: a GreyImage as one slice per file
//   5. The rules the reader applies
//
// GDCM, not DCMTK: Debian's GDCM decodes every compressed transfer syntax scanners use (JPEG
// baseline and lossless, JPEG-LS, JPEG 2000, RLE) in one library, while Debian's DCMTK has no
// JPEG 2000 decoder, which some CBCT exports use. docs/PATIENT_SCANS.md says more.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/interrupter.h"
#include "core/result.h"
#include "io/grey_image.h"
#include "io/input_budget.h"

namespace dentsim {

// ---- 1. DicomSeriesInfo ---------------------------------------------------------------------
struct DicomSeriesInfo {
  std::string series_uid;         // (0020,000E)
  std::string transfer_syntax;    // name of the first file's transfer syntax
  int32_t files = 0;              // files that hold the series' pixels
  int32_t files_skipped = 0;      // files in the folder that are not images (DICOMDIR, reports, other files)
  double slice_spacing_mm = 0.0;  // distance between slice centres along the slice normal [mm]
  double rescale_slope = 1.0;     // stored value -> unit: value * slope + intercept
  double rescale_intercept = 0.0;
  int32_t bits_stored = 0;
  bool signed_pixels = false;     // Pixel Representation 1
};

struct DicomReadOptions {
  std::string series_uid;                          // the series to read from a folder holding several; empty: the only one
  uint64_t max_bytes = 2 * inputBudget().max_bytes;  // the volume as float (4 bytes a voxel) must fit [B]; io/grey_volume_file.h says why twice
  // For fuzzing and tests only: read once, in this process, without the checking child (section 5),
  // as libFuzzer sees neither coverage nor crashes in a child. The same checks and max_bytes apply,
  // but a GDCM assertion or a forged element length now ends or bloats the caller (the DICOM fuzzer
  // screens its inputs for those itself). Never set it where a user's file is read.
  bool in_process = false;
  ScanReadApproval approve;  // asked before the values are allocated (io/grey_image.h); empty: no plan
};

// ---- 2. readDicomSeries ---------------------------------------------------------------------
// `path` is a folder of slices (searched recursively) or one file (a multi-frame volume). The volume's
// voxel (i, j, k) is column i, row j of the k-th slice in order along the slice normal (row
// direction x column direction), whatever the files are called. Values are stored value * slope +
// intercept (each file's own), in HU for CT with rescale type HU or none, raw otherwise.
// Every error is one line naming the file or folder and the problem (section 5).
Result<GreyImage> readDicomSeries(const std::string& path, const DicomReadOptions& options = {},
                                  Interrupter& interrupter = nullInterrupter(), DicomSeriesInfo* info = nullptr);

// ---- 3. readDicomFile -----------------------------------------------------------------------
// One file's pixels (a slice: dims[2] == 1; a multi-frame file: one k per frame) with its rescale
// applied and its geometry (a single slice's third axis is its normal, with its slice thickness or
// 1 mm). Colour, non-image and undecodable files are one-line errors.
Result<GreyImage> readDicomFile(const std::string& path, uint64_t max_bytes = 2 * inputBudget().max_bytes,
                                DicomSeriesInfo* info = nullptr);

// ---- 4. writeDicomSeries --------------------------------------------------------------------
struct DicomWriteOptions {
  std::string modality = "CT";
  std::string series_description = "dentsim";
  std::string series_uid;          // empty: a new one
  bool signed_pixels = true;       // int16 (true) or uint16 stored values
  double rescale_slope = 1.0;      // value = stored * slope + intercept; each value is rounded to the nearest stored one
  double rescale_intercept = 0.0;
  bool hounsfield = true;          // rescale type HU (else US, unspecified)
  // File names: "slice-NNNN.dcm" in slice order, or (true) names that sort in a scrambled order, as
  // some scanners' exports do, to show that the reader orders by position.
  bool scramble_names = false;
};

// Writes `image` as one CT Image Storage file per k slice, explicit VR little endian, into the folder
// `dir` (created; it must be empty or missing). Position, orientation, spacing and rescale come
// from the image. Values outside the stored type's range are clamped. Returns the files written.
Result<std::vector<std::string>> writeDicomSeries(const std::string& dir, const GreyImage& image,
                                                  const DicomWriteOptions& options = {});

// ---- 5. Reader rules ------------------------------------------------------------------------
// - Files are grouped by Series Instance UID. Several series in the folder without options.series_uid
//   is "mixed series", listing each with its slice count and description.
// - Files that are not DICOM (no "DICM" preamble and not readable as DICOM) and DICOM files without
//   pixel data (DICOMDIR, structured reports) are skipped and counted; a file that says it is DICOM but
//   cannot be read is "truncated or damaged", with its name. Deflated files are read (their size is
//   not compared with their inflated elements' lengths).
// - Every slice must share rows, columns, pixel spacing, orientation, Modality and Rescale Type (else
//   "mixed series", listing what was found).
// - Pixels must be in the file, checked from the header before any buffer is made: Rows x Columns x
//   frames x samples x Bits Allocated must fit an uncompressed Pixel Data element; a compressed one
//   holds a fragment a frame at least, and its decoded size must be the header's.
// - Geometry must be a scanner's: positions finite and within 10 m of the origin, Pixel Spacing, the
//   slice step and a single file's Slice Thickness or frame spacing at most 100 mm.
// - Slices are sorted by their position along the normal; two at one position is an error, a gap of
//   more than 1.5 spacings is "missing slice" (with where and how many), spacings that differ by more
//   than 10 % are "unevenly spaced", and positions that move across the normal from slice to slice are
//   "gantry tilt" (with the angle), as is a non-zero Gantry/Detector Tilt.
// - Pixels: one sample (MONOCHROME1 or 2), 8 to 16 bits stored (32 allowed), signed or not; bits above
//   Bits Stored are masked and the sign extended. A transfer syntax GDCM cannot decode is named.
// - The float volume must fit options.max_bytes (twice the input budget), checked before allocating.
// - Every read runs first in a forked child (io/sandboxed_read.h) whose data segment may grow by
//   max_bytes + 256 MB: GDCM's assertions (Debian keeps them) and its allocation of a forged element
//   length end the child, not dentsim, and the file it was on is named. Call these from a process
//   with no other threads running (the command line), as a forked child inherits only the caller's
//   thread and any lock another thread held stays locked in it. The child's processor time is
//   limited too (RLIMIT_CPU: 30 s and 2 s a MiB of input), and the parent kills it after twice that
//   and 30 s more: a file GDCM never finishes is a line naming it, not a hang.
//   options.in_process (fuzzing and tests only) skips the child: the one read runs in the caller.
// - An image whose sequences nest more than 8 deep is refused when its header is read: GDCM's
//   length of it, which the truncation check needs, grows about sixfold a level.

}  // namespace dentsim
