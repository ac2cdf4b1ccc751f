// The checks that a segmented scan can be a human tooth, in words (volume/tooth_sanity.h).
#include "volume/tooth_sanity.h"

#include <algorithm>
#include <cstdio>

#include "volume/tissue_table.h"

namespace dentsim {

ToothSize segmentedToothSize(const ToothSegmentReport& report, const std::array<double, 3>& pitch_mm) {
  ToothSize size;
  const double voxel_mm3 = pitch_mm[0] * pitch_mm[1] * pitch_mm[2];
  uint64_t hard = 0;
  // The tooth's own hard tissue: a neighbour (an adjacent tooth) is not part of its volume.
  for (size_t t = 0; t < kTissueCount; ++t)
    if (isToothTissue(kTissueTable[t].material) && kTissueTable[t].material != Material::Pulp) hard += report.tissue_voxels[t];
  size.hard_mm3 = double(hard) * voxel_mm3;
  for (size_t a = 0; a < 3; ++a) {
    const int64_t voxels = report.tooth_hi[a] - report.tooth_lo[a] + 1;
    size.length_mm = std::max(size.length_mm, double(std::max<int64_t>(voxels, 0)) * pitch_mm[a]);
  }
  return size;
}

std::string humanToothSizeProblem(const ToothSize& size) {
  char buf[200];
  if (size.hard_mm3 > human_tooth::kMaxHardMm3 || size.hard_mm3 < human_tooth::kMinHardMm3) {
    std::snprintf(buf, sizeof buf, "its hard tissue is %.0f mm^3, and a human tooth's is %.0f..%.0f mm^3 (a molar about 600..1000)",
                  size.hard_mm3, human_tooth::kMinHardMm3, human_tooth::kMaxHardMm3);
    return buf;
  }
  if (size.length_mm > human_tooth::kMaxLengthMm) {
    std::snprintf(buf, sizeof buf, "it is %.1f mm long, and a human tooth is at most %.0f mm", size.length_mm,
                  human_tooth::kMaxLengthMm);
    return buf;
  }
  return "";
}

std::string dentinThresholdProblem(double dentin_above, GreyUnit unit) {
  if (unit != GreyUnit::Hounsfield || dentin_above >= human_tooth::kSoftTissueHu) return "";
  char buf[160];
  std::snprintf(buf, sizeof buf, "the dentin threshold %.4g HU is below soft tissue (%.0f HU and up)", dentin_above,
                human_tooth::kSoftTissueHu);
  return buf;
}

std::string coarseVoxelProblem(const std::array<double, 3>& pitch_mm) {
  if (*std::max_element(pitch_mm.begin(), pitch_mm.end()) <= human_tooth::kMaxEnamelVoxelMm) return "";
  char buf[200];
  std::snprintf(buf, sizeof buf, "voxels of %.3g x %.3g x %.3g mm are coarser than the %.1f mm enamel can be thin",
                pitch_mm[0], pitch_mm[1], pitch_mm[2], human_tooth::kMaxEnamelVoxelMm);
  return buf;
}

}  // namespace dentsim
