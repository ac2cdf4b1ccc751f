// Thresholds for a scan's tissues: scanner presets, given values, Otsu on the ROI, and the automatic cuts refined on the tooth's voxels.
#include "volume/tooth_thresholds.h"

#include "volume/ct_segment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace dentsim {

// Published CT numbers: enamel 2000..3000 HU, dentin 1200..2000 HU, cortical bone 700..1900 HU,
// carious dentin a few hundred HU below sound dentin, soft tissue and pulp 20..80 HU. CBCT values on a
// HU-like scale run lower and wider (scatter, beam hardening), hence the lower cuts.
const std::vector<ToothSegmentPreset>& toothSegmentPresets() {
  static const std::vector<ToothSegmentPreset> presets = {
      {"ct-hu", "multi-slice CT in Hounsfield units: hard tissue from 1000 HU, enamel from 2100 HU, caries from 500 HU",
       GreyUnit::Hounsfield, 1000.0, 2100.0, 500.0},
      {"cbct-hu", "cone-beam CT exported on a HU-like scale: hard tissue from 700 HU, enamel from 1600 HU, caries from 350 HU",
       GreyUnit::Hounsfield, 700.0, 1600.0, 350.0},
  };
  return presets;
}

std::string toothSegmentPresetNames() {
  std::string out;
  for (const ToothSegmentPreset& p : toothSegmentPresets()) out += (out.empty() ? "" : ", ") + std::string(p.name);
  return out;
}

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

Status checkOrder(const ToothThresholds& t, GreyUnit unit, const std::string& where) {
  const std::string u = std::string(" ") + greyUnitName(unit);
  if (t.caries_below) {
    if (!(t.hard < *t.caries_below && *t.caries_below < t.enamel))
      return makeError(where, "thresholds out of order: need dentin_above " + num(t.hard) + " < caries_below " +
                                  num(*t.caries_below) + " < enamel_above " + num(t.enamel) + u);
  } else if (!(t.hard < t.enamel)) {
    return makeError(where, "thresholds out of order: dentin_above " + num(t.hard) + u +
                                " is not below enamel_above " + num(t.enamel) + u);
  }
  return Ok{};
}

// Where the histogram is empty on both sides of a cut, every cut in that gap splits the voxels alike
// and Otsu's variance ties; its search keeps the first, just above the air's noise (-721 HU on a
// phantom with no blur), which reads as a threshold in soft tissue. The middle of the gap is the same
// split, told the way a reader expects.
double centredInEmptyGap(const GreyHistogram& h, double cut) {
  const double at = (cut - h.lo) / h.width;
  if (!(at >= 1.0) || !(at < double(h.count.size()))) return cut;
  size_t lo = size_t(std::lround(at)), hi = lo;  // the empty bins are [lo, hi)
  while (lo > 0 && h.count[lo - 1] == 0) --lo;
  while (hi < h.count.size() && h.count[hi] == 0) ++hi;
  if (lo == 0 || hi == h.count.size() || hi - lo < 2) return cut;
  return h.edge((lo + hi) / 2);
}

}  // namespace

// Presets first, then given values one by one, then Otsu on the ROI for whatever is still unset.
Result<ToothThresholds> chooseThresholds(const ToothSegmentOptions& o, GreyUnit unit,
                                         const std::function<GreyHistogram()>& roi_histogram) {
  ToothThresholds t;
  std::optional<double> hard, caries_below, enamel;
  if (!o.preset.empty()) {
    const auto& presets = toothSegmentPresets();
    const auto it = std::find_if(presets.begin(), presets.end(),
                                 [&](const ToothSegmentPreset& p) { return o.preset == p.name; });
    if (it == presets.end())
      return makeError(o.where, "unknown scanner preset \"" + o.preset + "\" (known: " + toothSegmentPresetNames() + ")");
    if (it->unit != unit)
      return makeError(o.where, "preset " + o.preset + " is for images in " + greyUnitName(it->unit) +
                                    ", this image is in " + greyUnitName(unit));
    hard = o.caries ? it->caries_above : it->dentin_above;
    if (o.caries) caries_below = it->dentin_above;
    enamel = it->enamel_above;
    t.from_hard = t.from_caries = t.from_enamel = "preset " + o.preset;
  }
  if (o.dentin_above) { hard = o.dentin_above; t.from_hard = "given"; }
  if (o.caries && o.caries_below) { caries_below = o.caries_below; t.from_caries = "given"; }
  if (o.enamel_above) { enamel = o.enamel_above; t.from_enamel = "given"; }
  for (const std::optional<double>& v : {hard, caries_below, enamel})
    if (v && !std::isfinite(*v)) return makeError(o.where, "a threshold is not a finite number");

  if (!hard || !enamel || (o.caries && !caries_below)) {
    // Three classes even with caries: a lesion is a small share of a ROI, too small for a class of its
    // own (4-class Otsu cuts through the lesion's own values); its cut comes from the tooth's dentin.
    const int classes = 3;
    const GreyHistogram h = roi_histogram();
    if (h.total == 0) return makeError(o.where, "the ROI holds no finite grey value");
    const std::vector<double> cuts = otsuThresholds(h, classes);
    const std::string how = "automatic (" + std::to_string(classes) + "-class Otsu on the ROI's histogram)";
    if (!hard) { hard = centredInEmptyGap(h, cuts.front()); t.from_hard = how; }
    if (o.caries && !caries_below) {
      caries_below = 0.5 * (cuts.front() + cuts.back());  // a placeholder until the tooth is known
      t.from_caries = "automatic (3 sigma below the tooth's dentin peak)";
      t.caries_automatic = true;
    }
    if (!enamel) {
      enamel = cuts.back();
      t.from_enamel = "automatic (half-way between the tooth's dentin and enamel peaks)";
      t.enamel_automatic = true;
    }
  }
  t.hard = *hard;
  t.caries_below = caries_below;
  t.enamel = *enamel;
  if (Status s = checkOrder(t, unit, o.where); !s) return s.error();
  return t;
}

// Automatic caries and enamel cuts, again from the tooth's voxels alone :
// caries, dentin and enamel values and their edges, without the air and soft tissue that swamp the
// ROI's histogram.
Status refineOnTooth(ToothThresholds& thr, GreyUnit unit, const std::string& where,
                     const std::function<GreyHistogram(double lo, double hi)>& tooth_histogram) {
  if (!thr.enamel_automatic && !thr.caries_automatic) return Ok{};
  if (thr.enamel_automatic) {
    const GreyHistogram h = tooth_histogram(thr.caries_automatic ? thr.hard : thr.dentinFloor(), std::numeric_limits<double>::infinity());
    if (h.total > 0) {
      // Otsu splits dentin from enamel, but the blurred edges of the surface (values between air and
      // dentin) pull its cut down. The cut is then half-way between the two sides' peaks: where a
      // blurred dentin-enamel edge crosses half its step, whatever the edges and the classes' sizes.
      const double floor = thr.caries_automatic ? thr.hard : thr.dentinFloor();
      const double otsu = otsuThresholds(h, 2).back();
      size_t below = 0, above = h.count.size() - 1;
      for (size_t b = 0; b < h.count.size(); ++b) {
        if (h.centre(b) < otsu && h.count[b] > h.count[below]) below = b;
        if (h.centre(b) >= otsu && (h.centre(above) < otsu || h.count[b] > h.count[above])) above = b;
      }
      const double cut = h.centre(above) > otsu && h.centre(below) < otsu ? 0.5 * (h.centre(below) + h.centre(above)) : otsu;
      thr.enamel = std::max(cut, std::nextafter(floor, 1e300));
    }
  }
  if (thr.caries_automatic) {
    // Sound dentin is the peak of the tooth's values below enamel (it outnumbers a lesion and the
    // blurred edges), and its spread is read from the peak's upper half, where neither lesion nor
    // edges reach: half width at half maximum = 1.1774 sigma. Demineralised tissue lies more than
    // 3 sigma below sound dentin, and at least at the hard-tissue cut.
    const GreyHistogram h = tooth_histogram(thr.hard, thr.enamel);
    if (h.total > 0) {
      size_t peak = 0;
      for (size_t b = 1; b < h.count.size(); ++b)
        if (h.count[b] > h.count[peak]) peak = b;
      size_t half = peak;
      while (half + 1 < h.count.size() && h.count[half] > 0.5 * h.count[peak]) ++half;
      const double sigma = std::max(h.width, (h.centre(half) - h.centre(peak)) / 1.1774);
      thr.caries_below = std::clamp(h.centre(peak) - 3.0 * sigma, std::nextafter(thr.hard, 1e300),
                                    std::nextafter(thr.enamel, -1e300));
    }
  }
  return checkOrder(thr, unit, where);
}

std::string thresholdsFrom(const ToothThresholds& t) {
  const bool automatic = t.from_hard.rfind("automatic", 0) == 0 && t.enamel_automatic &&
                         (!t.caries_below || t.from_caries.rfind("automatic", 0) == 0);
  if (automatic)
    return std::string("automatic (3-class Otsu on the ROI's histogram, enamel_above half-way between the tooth's "
                       "dentin and enamel peaks") +
           (t.caries_below ? ", caries_below 3 sigma below the tooth's dentin peak)" : ")");
  const bool same = t.from_hard == t.from_enamel && (!t.caries_below || t.from_caries == t.from_hard);
  if (same) return t.from_hard;
  std::string out = "dentin_above " + t.from_hard;
  if (t.caries_below) out += ", caries_below " + t.from_caries;
  return out + ", enamel_above " + t.from_enamel;
}

}  // namespace dentsim
