// The rules on a segmented tooth's output box that undo the scanner's blur at tissue boundaries: classes by value, partial volume, edges, open caries.
//
// Entry points, in the order segmentTooth runs them (each states what it needs marked first):
//   classify             tooth cells (kToothMark) into caries, dentin, enamel; each class's mean
//   applyPartialVolume   intermediate-class voxels between the outside and a brighter class
//   markOutside          empty cells connected to the box's border (kOutside)
//   darkMeans            the mean of the outside and of enclosed space
//   applyEdgeRule        tooth voxels facing empty space that are darker than half-way
//   keepOpenCaries       caries pieces open to the surface and thicker than a rim
//
// The rules, with their reasons, are in docs/PATIENT_SCANS.md ("How a tooth is segmented":
// Tissues, Partial volume, Edges, Caries). Grey values are in the image's unit (HU or raw).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include "io/grey_image.h"
#include "volume/tissue_table.h"
#include "volume/tooth_thresholds.h"
#include "volume/voxel_grid_ops.h"

namespace dentsim {

// One byte a cell of the output box: the class in bits 0-1, then flag bits the rules set and clear.
namespace tooth_cell {
constexpr uint8_t kClassMask = 0x03;
constexpr uint8_t kCaries = 1, kDentin = 2, kEnamel = 3;  // 0: not tooth
constexpr uint8_t kToothMark = kDentin;    // a tooth cell before classify gives it a class
constexpr uint8_t kNearEmpty = 1u << 2;    // within w of the outside
constexpr uint8_t kNearEnamel = 1u << 3;   // within w of enamel
constexpr uint8_t kNearHard = 1u << 4;     // within w of dentin or enamel
constexpr uint8_t kOutside = 1u << 5;      // empty and connected to the box's border through empty
constexpr uint8_t kScratchA = 1u << 6, kScratchB = 1u << 7;  // the rules' own, clear between them
inline uint8_t classOf(uint8_t cell) { return cell & kClassMask; }

// The tissue each class becomes, by class: the tissues a scan's grey values tell apart, darkest
// first, since the rules compare classes by brightness. Pulp is no class: its grey values are soft
// tissue's, and importLabels fills it as the space the dentin encloses (ct_segment.h).
constexpr std::array<Material, 4> kClassTissue = {Material::Empty, Material::Caries, Material::Dentin, Material::Enamel};
static_assert(kClassTissue[kCaries] == Material::Caries && kClassTissue[kDentin] == Material::Dentin &&
                  kClassTissue[kEnamel] == Material::Enamel,
              "kClassTissue follows the class codes");

// Whether tissue m is one of the classes, that is, read from the grey values.
constexpr bool isGreyClass(Material m) {
  for (size_t c = 1; c < kClassTissue.size(); ++c)
    if (kClassTissue[c] == m) return true;
  return false;
}
}  // namespace tooth_cell

// The output box's cells over the image's grey values.
struct ToothBoxCells {
  const GreyImage& image;
  std::array<int64_t, 3> lo;   // the image voxel of cell 0
  std::array<int32_t, 3> d;    // cells along i, j, k
  std::vector<uint8_t> cells;  // (d[0] * d[1] * d[2]), i fastest
  float value(uint64_t o) const {
    const std::array<int64_t, 3> c = voxelCoords(o, d);
    return image.values[image.index(lo[0] + c[0], lo[1] + c[1], lo[2] + c[2])];
  }
};

// Mean grey value of each class in the box [image unit] (index 0: non-tooth voxels below the hard
// threshold).
struct ClassMeans {
  std::array<double, 4> mean{};
  double midpoint(uint8_t dark, uint8_t bright) const { return 0.5 * (mean[dark] + mean[bright]); }
};

// Cells holding kToothMark get their class by value; every other cell must hold 0, and keeps it.
// Class 0's mean is over the non-tooth cells below the hard threshold (cut-away hard tissue is in
// no mean). A class with no cell takes a threshold as its mean: class 0 and caries the hard one,
// dentin its floor, enamel enamel_above.
ClassMeans classify(ToothBoxCells& box, const ToothThresholds& thr);

// The partial-volume rule with width w >= 1 [cells]; caries: caries voxels take part. Decisions
// come from the classes before any change. Returns the voxels reassigned; flags end clear.
uint64_t applyPartialVolume(ToothBoxCells& box, int w, bool caries, const ClassMeans& means,
                            std::deque<uint64_t>& queue);

// Sets kOutside on the empty cells reached from the box's border through empty cells, and clears it
// elsewhere. The rest of the empty space is enclosed: the pulp, when its canal is closed in the box.
void markOutside(std::vector<uint8_t>& cells, const std::array<int32_t, 3>& d, std::deque<uint64_t>& queue);

// Mean value [image unit] of the empty space facing the tooth: [0] the outside, [1] enclosed space;
// `fallback` where there is none. Cut-away hard tissue (value >= hard) is in neither. Needs kOutside.
std::array<double, 2> darkMeans(const ToothBoxCells& box, double hard, double fallback);

// The edge rule, peeled up to `layers` times. Needs kOutside; emptied cells facing the outside
// become outside. Returns the voxels emptied.
uint64_t applyEdgeRule(ToothBoxCells& box, int layers, const std::array<double, 2>& dark, const ClassMeans& means);

// The caries rule with width w >= 1 [cells]. Needs kOutside; flags end clear. Returns the caries
// voxels rejected (made dentin or empty).
uint64_t keepOpenCaries(ToothBoxCells& box, int w, const std::array<double, 2>& dark, const ClassMeans& means,
                        std::deque<uint64_t>& queue);

}  // namespace dentsim
