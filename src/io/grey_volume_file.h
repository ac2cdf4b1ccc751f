// A scanner's grey-value volume from NIfTI (.nii, .nii.gz) or NRRD (.nrrd, .nhdr), the files 3D Slicer and research tools write.
//
// Contents
//   1. readNrrdGrey: NRRD through Teem's nrrd library
//   2. readGreyVolume: by file name, NIfTI or NRRD
#pragma once

#include <string>

#include "core/result.h"
#include "io/grey_image.h"
#include "io/input_budget.h"

namespace dentsim {

// The float volume may take twice the input budget: a scanner stores 2 bytes a voxel, and the grey
// image holds 4 (io/grey_image.h). Both the DICOM and these readers hold to it.
inline uint64_t greyBudgetBytes() { return 2 * inputBudget().max_bytes; }

// ---- 1. readNrrdGrey -------------------------------------------------------------------------
// A 3D NRRD (one attached .nrrd, or a detached .nhdr with its data file) of any scalar type, raw,
// ASCII, hex, gzip or bzip2 encoded. Placement: "space directions" and "space origin" when given (in
// the file's own space, e.g. left-posterior-superior), else the axes' spacings along x, y, z. Space
// units "mm", "um"/"micron" and "m" are converted to mm; none given is read as mm. The header is read
// first and the volume's floats checked against `max_bytes` before the data is loaded. Errors are one
// line "PATH: problem" (Teem's own reason appended).
// `approve`, when set, is asked before the data is loaded (io/grey_image.h).
Result<GreyImage> readNrrdGrey(const std::string& path, uint64_t max_bytes = greyBudgetBytes(),
                               const ScanReadApproval& approve = {});

// ---- 2. readGreyVolume -----------------------------------------------------------------------
// .nii / .nii.gz through readNiftiGrey, .nrrd / .nhdr through readNrrdGrey; any other name is an error
// that lists them (a DICOM folder goes to readDicomSeries).
Result<GreyImage> readGreyVolume(const std::string& path, uint64_t max_bytes = greyBudgetBytes(),
                                 const ScanReadApproval& approve = {});

}  // namespace dentsim
