// Where a scan's tissues start: grey-value thresholds from a scanner preset, given values or automatic Otsu, the automatic ones refined on the tooth's own voxels.
//
// Entry points:
//   toothSegmentPresets()               the named thresholds of each kind of scanner
//   chooseThresholds(options, unit, roi_histogram)
//                                       presets, then given values, then Otsu on the ROI
//   refineOnTooth(thr, unit, where, tooth_histogram)
//                                       automatic enamel and caries cuts again, on the tooth alone
//   thresholdsFrom(thr)                 how they were chosen, in words for the report
//
// The rules, with their reasons, are in docs/PATIENT_SCANS.md ("How a tooth is segmented",
// Thresholds). All values are in the image's unit (HU or raw).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "io/grey_image.h"
#include "volume/otsu_thresholds.h"

namespace dentsim {

// Thresholds for a kind of scanner, in its unit. They are starting points from published tissue
// values, not calibrations: a given threshold still overrides a preset's.
struct ToothSegmentPreset {
  const char* name;          // what --preset takes ("ct-hu")
  const char* description;   // one line for --help
  GreyUnit unit;             // the image must be in this unit
  double dentin_above;       // hard tissue starts here (without caries)
  double enamel_above;       // enamel starts here
  double caries_above;       // with caries: hard tissue (caries included) starts here
};

// Every preset, in the order --help lists them.
const std::vector<ToothSegmentPreset>& toothSegmentPresets();

// "ct-hu, cbct-hu" for messages and help.
std::string toothSegmentPresetNames();

// The thresholds in use, and where each came from. Without caries: hard <= dentin < enamel; with
// caries: hard <= caries < caries_below <= dentin < enamel.
struct ToothThresholds {
  double hard = 0;                     // hard tissue starts here (dentin_above) [image unit]
  std::optional<double> caries_below;  // with caries: dentin starts here [image unit]
  double enamel = 0;                   // enamel_above [image unit]
  std::string from_hard, from_caries, from_enamel;          // "given", "preset NAME", "automatic (...)"
  bool enamel_automatic = false, caries_automatic = false;  // still to be refined on the tooth's voxels
  // The lower bound of dentin: caries_below with caries, else the hard threshold.
  double dentinFloor() const { return caries_below.value_or(hard); }
};

struct ToothSegmentOptions;  // ct_segment.h

// Presets first, then given values one by one, then 3-class Otsu on roi_histogram() (called only
// when a threshold is still unset) for the rest. Errors (one line, naming options.where): an unknown
// preset or one for another unit, a threshold that is not finite, a ROI with no finite value,
// thresholds out of order.
Result<ToothThresholds> chooseThresholds(const ToothSegmentOptions& options, GreyUnit unit,
                                         const std::function<GreyHistogram()>& roi_histogram);

// The automatic enamel and caries cuts again, from tooth_histogram(lo, hi): the robust histogram of
// the tooth's values v with lo <= v < hi. Given and preset thresholds are left alone. Error: the
// refined thresholds out of order.
Status refineOnTooth(ToothThresholds& thr, GreyUnit unit, const std::string& where,
                     const std::function<GreyHistogram(double lo, double hi)>& tooth_histogram);

// How the thresholds were chosen, in one phrase: "automatic (...)", "given", "preset NAME", or per
// threshold when they differ.
std::string thresholdsFrom(const ToothThresholds& t);

}  // namespace dentsim
