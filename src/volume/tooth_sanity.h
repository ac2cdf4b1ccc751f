// Whether a segmented scan can be a human tooth: its hard-tissue volume, its length, the dentin threshold and the voxel size, against the ranges of real teeth.
//
// Contents
//   1. human_tooth: the ranges, with their sources
//   2. ToothSize and segmentedToothSize: what a segmentation found, in mm
//   3. The checks: each returns "" when the scan passes, else what is wrong in words
//
// The checks say what is wrong; the caller says what to do about it, in its own flags.
#pragma once

#include <array>
#include <string>

#include "io/grey_image.h"
#include "volume/ct_segment.h"

namespace dentsim {

// ---- 1. the ranges ----------------------------------------------------------------------------
// Typical volumes of permanent teeth (enamel + dentin + cementum; the pulp left out), from micro-CT
// and CBCT volumetry: a lower central incisor about 200..300 mm^3, a premolar 400..600, a permanent
// molar about 600..1000, a canine (the longest tooth, about 27 mm) up to about 1 000. The bounds
// below sit a factor of 3 to 4 outside them, so a small primary tooth or a large molar with a
// lesion passes, and a piece of noise or a tooth fused to its bone and neighbours (a head CT
// segmented at a soft-tissue threshold made 62 000 mm^3) does not.
namespace human_tooth {
constexpr double kMinHardMm3 = 50.0;       // below the crown of the smallest primary incisor [mm^3]
constexpr double kMaxHardMm3 = 3000.0;     // three of the largest molars [mm^3]
constexpr double kMaxLengthMm = 35.0;      // the longest canine is about 32 mm, crown to apex [mm]
// Enamel is 0.3..2.5 mm thick (thinnest at the cervical line, thickest over the cusps), so a voxel
// edge over 0.3 mm holds enamel only as partial volume: a clinical CT (0.5..1 mm) shows a tooth but
// not its layers, a CBCT (0.1..0.3 mm) or a micro-CT (0.01..0.05 mm) does.
constexpr double kMaxEnamelVoxelMm = 0.3;  // [mm]
// Soft tissue and pulp are 20..80 HU and water 0 HU: hard tissue cannot start below that. A
// threshold under it takes soft tissue into the tooth.
constexpr double kSoftTissueHu = 0.0;      // [HU]
}  // namespace human_tooth

// ---- 2. the size found ------------------------------------------------------------------------
struct ToothSize {
  double hard_mm3 = 0.0;   // enamel, dentin and caries of the tooth, not of a neighbour [mm^3]
  double length_mm = 0.0;  // the longest edge of the tooth's bounding box in the scan's axes [mm]
};

// The size of segmentTooth's tooth: its voxels of every grey class at the scan's voxel volume, and
// the longest edge of its hard voxels' box. The box edge is a lower bound of the tooth's true
// length (a tooth lying diagonally is longer), so a refusal on it is never a false one.
ToothSize segmentedToothSize(const ToothSegmentReport& report, const std::array<double, 3>& pitch_mm);

// ---- 3. the checks ----------------------------------------------------------------------------
// "" when size is within human_tooth's range; else one phrase naming the volume or length found and
// the range: "its hard tissue is 61873 mm^3, and a human tooth's is 50..3000 mm^3".
std::string humanToothSizeProblem(const ToothSize& size);

// "" unless the image is in HU and dentin_above is below soft tissue; else one phrase naming it.
std::string dentinThresholdProblem(double dentin_above, GreyUnit unit);

// "" when every voxel edge is at most kMaxEnamelVoxelMm; else one phrase naming the voxel.
std::string coarseVoxelProblem(const std::array<double, 3>& pitch_mm);

}  // namespace dentsim
