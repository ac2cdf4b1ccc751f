// One tooth out of a scanner's grey-value volume (CT, CBCT, micro-CT): thresholds, the tooth's own voxels, tissue labels for importLabels.
//
// Contents
//   1. Scanner presets (named thresholds: in tooth_thresholds.h)
//   2. ToothSegmentOptions, ToothSegmentReport
//   3. segmentTooth: a GreyImage into a LabelImage of enamel, dentin and caries
//   4. Where the rules are written
//
// Pulp is not labelled here. Its grey values are those of soft tissue, and telling an enclosed pulp
// chamber from the air around the tooth is a question of shape, not of value: importLabels does it
// with fill_enclosed = pulp and a seal (seal_mm about 0.3 mm closes the apical foramina), so the
// output of segmentTooth goes into importLabels with toothSegmentLabelMap() (section 3).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/interrupter.h"
#include "core/result.h"
#include "io/grey_image.h"
#include "io/nifti_labels.h"
#include "volume/label_import.h"
#include "volume/otsu_thresholds.h"
#include "volume/tissue_boundary_rules.h"
#include "volume/tissue_table.h"
#include "volume/tooth_thresholds.h"

namespace dentsim {

// ---- 1. presets -----------------------------------------------------------------------------
// ToothSegmentPreset, toothSegmentPresets() and toothSegmentPresetNames() are in tooth_thresholds.h,
// with the rest of the threshold choice.

// ---- 2. options and report ------------------------------------------------------------------
// A box in scanner space [mm]: its two corners, inclusive, in any order per axis.
struct MmBox {
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
};

// Thresholds are grey values in the image's unit (HU or raw); a voxel belongs to the class whose
// lower threshold it reaches. Without caries:  background < dentin_above <= dentin < enamel_above
// <= enamel. With caries, three cuts:  background < dentin_above <= caries < caries_below <= dentin <
// enamel_above <= enamel, so dentin_above is always where hard tissue starts.
struct ToothSegmentOptions {
  std::optional<MmBox> roi;                      // crop to this box first (scanner mm); unset: whole image
  std::optional<std::array<double, 3>> seed_mm;  // a point in the tooth (scanner mm): keep only its tooth
  std::optional<double> dentin_above;            // hard tissue starts here [image unit]; unset: automatic
  std::optional<double> enamel_above;            // enamel starts here [image unit]; unset: automatic
  std::string preset;                            // a name from toothSegmentPresets(); empty: none
  bool caries = false;                           // find caries (demineralised tissue open to the surface)
  std::optional<double> caries_below;            // with caries: dentin starts here [image unit]; unset: automatic
  // Pieces of one tissue (or holes) smaller than this are relabelled [mm^3]. 0.01 mm^3 is a cube of
  // 0.22 mm: below any structure the simulator cuts (enamel is 0.3..2.5 mm thick, a bur tip 0.5 mm)
  // and above the specks that noise leaves: 10 voxels at 0.1 mm (CBCT), 250 at 34 um (micro-CT),
  // none at 0.3 mm, where one voxel is already larger. 0: off.
  double min_island_mm3 = 0.01;
  // The seeded tooth is cut from its neighbours where the hard tissue narrows: two bulges of the
  // hard mask stay apart when the lower one's inscribed-ball radius exceeds the join's by h or more
  // [mm]. 0.3 mm is below the half-thickness of a root's dentin wall (about 1 mm) and of the
  // alveolar bone, so a tooth's own parts merge, and above the radius of a contact point or a
  // blurred periodontal gap (<= 0.2 mm), so neighbours part.
  double split_h_mm = 0.3;
  // Partial-volume width [voxels]: an intermediate-class voxel within this many voxels (box
  // distance) of both the outside and a brighter class is an edge blur, not a tissue. 2 covers the
  // 10-90 % rise of an edge blurred by a Gaussian of sigma up to about 1 voxel. It is also the
  // number of layers the edge rule may peel. 0 turns both rules off (plain thresholds).
  int partial_volume_voxels = 2;
  int margin_voxels = 3;  // empty voxels kept around the tooth's bounding box (within the ROI)
  // A tooth smaller than this is an error [mm^3]: the smallest permanent tooth's crown alone is over
  // 100 mm^3, so 1 mm^3 is a speck of noise, which is what a ROI of air splits into.
  double min_tooth_mm3 = 1.0;
  std::string where;      // names the source in errors
};

// What was chosen and how: what `dentsim voxelize` and `info` print.
struct ToothSegmentReport {
  double dentin_above = 0, enamel_above = 0;  // the thresholds used [image unit]
  std::optional<double> caries_below;         // with caries [image unit]
  GreyUnit unit = GreyUnit::Raw;
  // "automatic (...)", "given", "preset NAME", or per threshold when they differ.
  std::string thresholds_from;
  std::array<int64_t, 3> roi_lo{}, roi_hi{};  // the ROI as an inclusive voxel box of the image
  std::array<int64_t, 3> out_lo{}, out_hi{};  // the output's inclusive voxel box of the image
  std::array<int64_t, 3> tooth_lo{}, tooth_hi{};  // the tooth's hard voxels' inclusive box of the image (no margin)
  // Voxels of each tissue in the output, by tissue table row: 0 for a tissue no grey class gives
  // (pulp; tooth_cell::isGreyClass in tissue_boundary_rules.h).
  std::array<uint64_t, kTissueCount> tissue_voxels{};
  uint64_t islands_removed = 0, island_voxels = 0;  // pieces (tissue and holes) relabelled
  uint64_t partial_volume_voxels = 0;         // voxels reassigned by the partial-volume rule
  uint64_t edge_voxels = 0;                   // tooth voxels emptied by the edge rule
  uint64_t caries_rejected_voxels = 0;        // caries-range voxels not open to the surface or too thin
  bool seeded = false;
  uint64_t hard_component_voxels = 0;         // the connected hard tissue the tooth came from
  uint64_t neighbour_voxels_cut = 0;          // hard voxels of that component cut away from the tooth
  uint64_t tooth_voxels = 0;                  // hard voxels of the tooth before classification
  double min_island_voxels = 0;               // min_island_mm3 in voxels
};

// ---- 3. entry point -------------------------------------------------------------------------
// Labels one tooth of `image` with the tissue table's nifti_label codes: 1 enamel, 2 dentin,
// 4 caries, 0 anything else (air, soft tissue, pulp, bone, other teeth). The output is the tooth's
// voxel bounding box plus margin_voxels on each side, clipped to the ROI; its pitch is the image's
// and its scanner_from_voxel the image's with the offset moved to the box's first voxel.
//
// Errors (one line, naming options.where): an empty image or one whose values do not match its
// dims; an ROI outside the image or holding no voxel centre; an unknown preset or one for another
// unit; thresholds out of order (naming the values and unit); no voxel reaching the hard-tissue
// threshold; a seed outside the image or the ROI, or not in hard tissue; a cancel through
// `interrupter`. `report`, when given, is reset first and filled as the steps run.
//
// Memory: three bits a voxel of the ROI (hard mask, tooth, pieces seen); with a seed, about 12 bytes
// a voxel of the seeded piece's bounding box while it is cut (the pulp-filled grid, a float
// distance, then a 16-bit depth, the flood order and a region id); one byte a voxel of the output
// box for the classes, and the output's 2. No copy of the grey values is made.
Result<LabelImage> segmentTooth(const GreyImage& image, const ToothSegmentOptions& options,
                                Interrupter& interrupter = nullInterrupter(), ToothSegmentReport* report = nullptr);

// segmentTooth's labels back to tissues, for importLabels: one entry per grey class, the class's
// tissue (tooth_cell::kClassTissue) under its tissue table label, so a class added there is mapped
// here without a second list to keep in step.
inline LabelMap toothSegmentLabelMap() {
  LabelMap map;
  for (size_t c = 1; c < tooth_cell::kClassTissue.size(); ++c)
    if (const TissueRow* row = findTissue(tooth_cell::kClassTissue[c])) map[row->nifti_label] = row->material;
  return map;
}

// ---- 4. rules -------------------------------------------------------------------------------
// The rules of every step (ROI, thresholds, the tooth and its cut, tissues, partial volume, edges,
// caries, islands) are in docs/PATIENT_SCANS.md, "How a tooth is segmented".

namespace internal {
// The Otsu search lives in otsu_thresholds.h; this is the name ct_segment's tests know it by.
using dentsim::otsuCuts;
}  // namespace internal

}  // namespace dentsim
