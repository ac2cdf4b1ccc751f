// The crown preparation's score: the measures taken from the finish line up, each criterion graded against the task's range, the caps, the report and the terminal line.
//
// Contents
//   1. Words and ranges
//   2. Measuring
//   3. Grading each criterion
//   4. The total
//   5. The report, the lines, the terminal line and the paint
#include "eval/crown_score.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_map>

#include "eval/score_image.h"
#include "io/input_budget.h"
#include "volume/tissue_table.h"

namespace dentsim {

namespace {

using ojson = nlohmann::ordered_json;

// The criteria's points, out of 100 (docs/SCORING.md, "Crown preparation").
constexpr double kOcclusalPoints = 20, kAxialPoints = 20, kTaperPoints = 15, kHeightPoints = 10,
                 kMarginWidthPoints = 15, kMarginLinePoints = 10, kUndercutPoints = 10;
// How far outside its range a figure is still near [mm, or the factor on a least].
constexpr double kOcclusalNearMm = 0.5;     // either side of the occlusal band
constexpr double kAxialNearBelowMm = 0.3;   // under the axial band: a thin crown wall
constexpr double kAxialNearAboveMm = 0.5;   // over it: less tooth left, but a crown still fits
constexpr double kHeightNearFactor = 0.8;   // of the least height and of the least ratio
constexpr double kMarginNearMm = 0.3;       // the width's lo down and its hi up
constexpr double kLineRoughWithinMm = 0.15; // the finish line's height wander, within
constexpr double kLineRoughNearMm = 0.30;   //   and near
constexpr double kLineGapShareNear = 0.10;  // the share of the circle without a line, near
constexpr double kLineCejNearMm = 0.5;      // the margin's height over the CEJ, either side of the task's band
constexpr double kUndercutWithinMm2 = 0.1;  // a shadow this small is the voxels' staircase, not an undercut
// A completion sample counts as reduced when it reached this share of its band's lo.
constexpr double kCompletionShareOfLo = 0.5;
// A preparation with this share of its samples reduced counts as done: the criteria earned in
// proportion earn min(1, reached share / this). Short of 1, because a careful preparation's own
// samples are not all reduced: at the foot of a shoulder and on a rounded line angle the gauge's
// ray is short. A region left untouched (a whole occlusal surface is about a quarter of the
// samples) is then graded by its own criterion without also costing the others.
constexpr double kCompleteAtShare = 0.8;
// Comparisons with a bound forgive the rounding of voxel_mm products.
constexpr double kEps = 1e-9;

constexpr const char* kSourceReduction =
    "Shillingburg et al., Fundamentals of Fixed Prosthodontics, 4th ed.; Goodacre et al. 2001, J Prosthet Dent 85:363-376";
constexpr const char* kSourceTaper =
    "Goodacre et al. 2001, J Prosthet Dent 85:363-376 (10-20 deg); 4-10 deg as some schools teach, up to 21-30 deg judged acceptable";
constexpr const char* kSourceHeight =
    "Goodacre et al. 2001, J Prosthet Dent 85:363-376 (4 mm on molars, 3 mm on other teeth; height/width 0.4)";
constexpr const char* kSourceMarginWidth =
    "Goodacre et al. 2001; Shillingburg et al., 4th ed. (a chamfer or shoulder 0.8-1.5 mm wide)";
constexpr const char* kSourceMarginLine =
    "the examiner's continuity and smoothness of the finish line; the height over the CEJ is the task's; "
    "the limits are dentsim's (docs/SCORING.md)";
constexpr const char* kSourceUndercut =
    "a fail criterion of its own: a crown cannot seat over surface hidden from the path of insertion";
constexpr const char* kSessionNotScored =
    "reported, not scored: a crown preparation is graded on its shape, as examiners grade it";

// ---- 1. words and ranges ----------------------------------------------------------------------

std::string fixed(double v, int digits = 2) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

// Shortest text of a bound: "10", "1.5", "0.15".
std::string bound(double v) {
  char text[48];
  std::snprintf(text, sizeof text, "%g", std::round(v * 1000.0) / 1000.0);
  return text;
}

// "10-20", or "-0.5 to 1.5" when a bound is negative (a margin under the CEJ).
std::string bandText(double lo, double hi) { return bound(lo) + (lo < 0 || hi < 0 ? " to " : "-") + bound(hi); }

// How far v lies outside [lo, hi]: negative below, positive above, 0 within.
double outside(double v, double lo, double hi) {
  if (v < lo - kEps) return v - lo;
  if (v > hi + kEps) return v - hi;
  return 0.0;
}

int rank(CrownVerdict v) { return int(v); }  // Within 0 < Near 1 < Outside 2

void grade(CrownCriterion& k, CrownVerdict verdict, std::optional<double> share) {
  k.measured = true;
  k.verdict = verdict;
  k.verdict_points = verdict == CrownVerdict::Within ? k.max : verdict == CrownVerdict::Near ? k.max / 2.0 : 0.0;
  k.share = share;
  k.points = k.verdict_points * share.value_or(1.0);
}

void notMeasured(CrownCriterion& k, const std::string& why, std::optional<double> share) {
  k.measured = false;
  k.verdict = CrownVerdict::Outside;
  k.verdict_points = 0.0;
  k.share = share;
  k.points = 0.0;
  k.why = why;
}

void describe(CrownCriterion& k, const char* name, double max, std::string band, std::string range, const char* source) {
  k.name = name;
  k.max = max;
  k.band = std::move(band);
  k.range = std::move(range);
  k.source = source;
}

void describeAll(CrownScore& s, const CrownTask& c) {
  auto& k = s.criteria;
  describe(k[0], "occlusal_reduction", kOcclusalPoints, bandText(c.occlusal_lo_mm, c.occlusal_hi_mm) + " mm",
           bandText(c.occlusal_lo_mm, c.occlusal_hi_mm) + " mm median (near " +
               bandText(c.occlusal_lo_mm - kOcclusalNearMm, c.occlusal_hi_mm + kOcclusalNearMm) + ")",
           kSourceReduction);
  describe(k[1], "axial_reduction", kAxialPoints, bandText(c.axial_lo_mm, c.axial_hi_mm) + " mm",
           bandText(c.axial_lo_mm, c.axial_hi_mm) + " mm, each wall's mean (near " +
               bandText(c.axial_lo_mm - kAxialNearBelowMm, c.axial_hi_mm + kAxialNearAboveMm) + ")",
           kSourceReduction);
  describe(k[2], "taper", kTaperPoints, bandText(c.toc_lo_deg, c.toc_hi_deg) + " deg",
           bandText(c.toc_lo_deg, c.toc_hi_deg) + " deg TOC in every plane (near " +
               bandText(c.toc_near_lo_deg, c.toc_near_hi_deg) + ")",
           kSourceTaper);
  describe(k[3], "height", kHeightPoints, ">= " + bound(c.min_height_mm) + " mm, >= " + bound(c.min_height_width_ratio),
           "height >= " + bound(c.min_height_mm) + " mm and height/width >= " + bound(c.min_height_width_ratio) +
               " (near >= " + bound(kHeightNearFactor * c.min_height_mm) + " mm and >= " +
               bound(kHeightNearFactor * c.min_height_width_ratio) + ")",
           kSourceHeight);
  describe(k[4], "margin_width", kMarginWidthPoints, bandText(c.margin_lo_mm, c.margin_hi_mm) + " mm",
           "least width >= " + bound(c.margin_lo_mm) + " mm and mean <= " + bound(c.margin_hi_mm) + " mm (near >= " +
               bound(c.margin_lo_mm - kMarginNearMm) + " and <= " + bound(c.margin_hi_mm + kMarginNearMm) + ")",
           kSourceMarginWidth);
  describe(k[5], "margin_line", kMarginLinePoints, "no gaps, <= " + bound(kLineRoughWithinMm) + " mm",
           "no gaps, roughness <= " + bound(kLineRoughWithinMm) + " mm, " +
               bandText(c.margin_above_cej_lo_mm, c.margin_above_cej_hi_mm) + " mm over the CEJ where known (near: gaps <= " +
               bound(100.0 * kLineGapShareNear) + " % of the circle, roughness <= " + bound(kLineRoughNearMm) + " mm, " +
               bandText(c.margin_above_cej_lo_mm - kLineCejNearMm, c.margin_above_cej_hi_mm + kLineCejNearMm) + " mm)",
           kSourceMarginLine);
  describe(k[6], "undercut", kUndercutPoints, "<= " + bound(kUndercutWithinMm2) + " mm^2",
           "shadow <= " + bound(kUndercutWithinMm2) + " mm^2 (near <= " + bound(c.undercut_tolerance_mm2) +
               "; beyond it the total is capped at " + bound(c.undercut_cap) + ")",
           kSourceUndercut);
}

constexpr const char* kWallNames[4] = {"mesial", "distal", "buccal", "lingual"};  // AxialWall's order

}  // namespace

const char* crownVerdictName(CrownVerdict verdict) {
  switch (verdict) {
    case CrownVerdict::Within: return "within";
    case CrownVerdict::Near: return "near";
    case CrownVerdict::Outside: return "outside";
  }
  return "outside";
}

const char* marginSectorDirection(int sector) {
  static const char* const kNames[8] = {"mesial", "mesiobuccal", "buccal", "distobuccal",
                                        "distal", "distolingual", "lingual", "mesiolingual"};
  const double deg = (std::clamp(sector, 0, kMarginSectors - 1) + 0.5) * 360.0 / kMarginSectors;
  return kNames[int(std::floor(deg / 45.0 + 0.5)) % 8];
}

// ---- 2. measuring ---------------------------------------------------------------------------------

namespace {

// The completion from a second reduction read whose bands' lo are half the task's and whose hi is
// out of reach: its under list is exactly the samples short of half their lo. Samples whose ray
// missed the preparation were taken off whole and count as reduced.
void measureCompletion(CrownScore& s, const BrickVolume& original, const BrickVolume& prepared, double voxel_mm,
                       const Vec3& axis, const Vec3& mesial, const CrownTask& c) {
  ReductionBands half;
  constexpr double kOutOfReach = std::numeric_limits<double>::max();
  half.occlusal_lo = kCompletionShareOfLo * c.occlusal_lo_mm;
  half.occlusal_hi = kOutOfReach;
  half.axial_lo = kCompletionShareOfLo * c.axial_lo_mm;
  half.axial_hi = kOutOfReach;
  auto r = measureReduction(original, prepared, voxel_mm, axis, mesial, s.margin_height_mm, half);
  if (!r) return;
  int met = r->occlusal.samples;
  for (const ReductionStats& w : r->axial) met += w.samples;
  // No sample's ray met the preparation: nothing stands above the finish line (the crown cut off
  // flat at the line), so there is no preparation to grade, whatever was taken off.
  if (met == 0) return;
  const int samples = met + r->unreached;
  s.completion_samples = samples;
  s.completion_reached = samples - int(r->under_voxels.size());
  s.reached_share = samples > 0 ? double(s.completion_reached) / double(samples) : 0.0;
  s.completion = std::min(1.0, s.reached_share / kCompleteAtShare);
}

// ---- 3. grading each criterion ------------------------------------------------------------------

void gradeOcclusal(CrownScore& s, const CrownTask& c) {
  CrownCriterion& k = s.criteria[size_t(CrownCriterionId::OcclusalReduction)];
  if (!s.reduction) return notMeasured(k, s.reduction_error, std::nullopt);
  const ReductionStats& o = s.reduction->occlusal;
  if (o.samples == 0) return notMeasured(k, "no occlusal sample met the preparation", std::nullopt);
  const double off = outside(o.median_mm, c.occlusal_lo_mm, c.occlusal_hi_mm);
  grade(k, off == 0.0 ? CrownVerdict::Within : std::abs(off) <= kOcclusalNearMm + kEps ? CrownVerdict::Near : CrownVerdict::Outside,
        std::nullopt);
  k.value = fixed(o.median_mm) + " mm";
  k.why = off == 0.0 ? "the median is in the band" : off < 0 ? "under-reduced by " + fixed(-off) + " mm" : "over-reduced by " + fixed(off) + " mm";
}

// Each wall's verdict and how far out it lies; the worst wall decides.
struct WallGrade {
  CrownVerdict verdict = CrownVerdict::Outside;
  double off = 0.0;
  bool measured = false;
};

WallGrade gradeWall(const ReductionStats& w, const CrownTask& c) {
  WallGrade g;
  if (w.samples == 0) return g;
  g.measured = true;
  g.off = outside(w.mean_mm, c.axial_lo_mm, c.axial_hi_mm);
  g.verdict = g.off == 0.0 ? CrownVerdict::Within
              : (g.off < 0 ? -g.off <= kAxialNearBelowMm + kEps : g.off <= kAxialNearAboveMm + kEps) ? CrownVerdict::Near
                                                                                                        : CrownVerdict::Outside;
  return g;
}

int worstWall(const CrownScore& s, const CrownTask& c) {
  int worst = 0;
  for (int w = 1; w < 4; ++w) {
    const WallGrade a = gradeWall(s.reduction->axial[size_t(w)], c), b = gradeWall(s.reduction->axial[size_t(worst)], c);
    // Among walls equally graded, the one farthest out; among walls all in the band, the one
    // farthest from its middle, so that the line names the wall nearest to leaving it.
    const double mid = 0.5 * (c.axial_lo_mm + c.axial_hi_mm);
    const double da = std::abs(s.reduction->axial[size_t(w)].mean_mm - mid), db = std::abs(s.reduction->axial[size_t(worst)].mean_mm - mid);
    if (rank(a.verdict) > rank(b.verdict) ||
        (a.verdict == b.verdict && (std::abs(a.off) > std::abs(b.off) || (a.off == 0.0 && b.off == 0.0 && da > db))))
      worst = w;
  }
  return worst;
}

void gradeAxial(CrownScore& s, const CrownTask& c) {
  CrownCriterion& k = s.criteria[size_t(CrownCriterionId::AxialReduction)];
  if (!s.reduction) return notMeasured(k, s.reduction_error, std::nullopt);
  const int worst = worstWall(s, c);
  const WallGrade g = gradeWall(s.reduction->axial[size_t(worst)], c);
  if (!g.measured) return notMeasured(k, std::string("no sample of the ") + kWallNames[worst] + " wall met the preparation", std::nullopt);
  grade(k, g.verdict, std::nullopt);
  k.value = fixed(s.reduction->axial[size_t(worst)].mean_mm) + " mm " + kWallNames[worst];
  k.why = std::string("the ") + kWallNames[worst] + " wall decides" +
          (g.off == 0.0 ? ": every wall's mean is in the band"
                        : g.off < 0 ? ", under-reduced by " + fixed(-g.off) + " mm" : ", over-reduced by " + fixed(g.off) + " mm");
}

void gradeTaper(CrownScore& s, const CrownTask& c) {
  CrownCriterion& k = s.criteria[size_t(CrownCriterionId::Taper)];
  if (!s.shape) return notMeasured(k, s.shape_error, s.completion);
  size_t worst = 0;
  double worst_off = -1.0;
  bool all_within = true, all_near = true;
  for (size_t p = 0; p < s.shape->planes.size(); ++p) {
    const double toc = s.shape->planes[p].toc_deg;
    const double off = std::abs(outside(toc, c.toc_lo_deg, c.toc_hi_deg));
    all_within = all_within && off == 0.0;
    all_near = all_near && outside(toc, c.toc_near_lo_deg, c.toc_near_hi_deg) == 0.0;
    if (off > worst_off) {
      worst_off = off;
      worst = p;
    }
  }
  grade(k, all_within ? CrownVerdict::Within : all_near ? CrownVerdict::Near : CrownVerdict::Outside, s.completion);
  k.value = fixed(s.shape->planes[worst].toc_deg, 1) + " deg " + s.shape->planes[worst].name;
  k.why = std::string("the ") + s.shape->planes[worst].name + " plane is the farthest from the range";
}

void gradeHeight(CrownScore& s, const CrownTask& c) {
  CrownCriterion& k = s.criteria[size_t(CrownCriterionId::Height)];
  if (!s.shape) return notMeasured(k, s.shape_error, s.completion);
  const double h = s.shape->height_mm, r = s.shape->height_width_ratio;
  const bool within = h >= c.min_height_mm - kEps && r >= c.min_height_width_ratio - kEps;
  const bool near = h >= kHeightNearFactor * c.min_height_mm - kEps && r >= kHeightNearFactor * c.min_height_width_ratio - kEps;
  grade(k, within ? CrownVerdict::Within : near ? CrownVerdict::Near : CrownVerdict::Outside, s.completion);
  k.value = fixed(h) + " mm, ratio " + fixed(r);
  k.why = within ? "both at least their least" : h < c.min_height_mm - kEps ? "too short" : "too short for its width";
}

void gradeMarginWidth(CrownScore& s, const CrownTask& c) {
  CrownCriterion& k = s.criteria[size_t(CrownCriterionId::MarginWidth)];
  if (!s.margin_found) return notMeasured(k, "no finish line found: nothing was prepared", s.coverage);
  const MarginLine& m = s.margin;
  const bool within = m.min_width_mm >= c.margin_lo_mm - kEps && m.mean_width_mm <= c.margin_hi_mm + kEps;
  const bool near = m.min_width_mm >= c.margin_lo_mm - kMarginNearMm - kEps && m.mean_width_mm <= c.margin_hi_mm + kMarginNearMm + kEps;
  grade(k, within ? CrownVerdict::Within : near ? CrownVerdict::Near : CrownVerdict::Outside, s.coverage);
  int at = 0;
  double least = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kMarginSectors; ++i)
    if (m.sectors[size_t(i)].found && m.sectors[size_t(i)].width_mm < least) {
      least = m.sectors[size_t(i)].width_mm;
      at = i;
    }
  k.value = "least " + fixed(m.min_width_mm) + " mm " + marginSectorDirection(at) + ", mean " + fixed(m.mean_width_mm) + " mm";
  k.why = within ? "the least width and the mean are in the band"
          : m.min_width_mm < c.margin_lo_mm - kEps ? std::string("too thin ") + marginSectorDirection(at)
                                                   : "too wide on the mean";
}

void gradeMarginLine(CrownScore& s, const CrownTask& c) {
  CrownCriterion& k = s.criteria[size_t(CrownCriterionId::MarginLine)];
  if (!s.margin_found) return notMeasured(k, "no finish line found: nothing was prepared", s.completion);
  const MarginLine& m = s.margin;
  const std::optional<double>& cej = m.mean_above_cej_mm;
  const double cej_off = cej ? std::abs(outside(*cej, c.margin_above_cej_lo_mm, c.margin_above_cej_hi_mm)) : 0.0;
  const bool within = m.gaps == 0 && m.roughness_mm <= kLineRoughWithinMm + kEps && cej_off == 0.0;
  const bool near = m.gap_share <= kLineGapShareNear + kEps && m.roughness_mm <= kLineRoughNearMm + kEps && cej_off <= kLineCejNearMm + kEps;
  grade(k, within ? CrownVerdict::Within : near ? CrownVerdict::Near : CrownVerdict::Outside, s.completion);
  k.value = std::to_string(m.gaps) + " gaps, roughness " + fixed(m.roughness_mm) + " mm" +
            (cej ? ", " + fixed(*cej) + " mm over the CEJ" : std::string(", CEJ not known"));
  std::string faults;
  const auto add = [&](const std::string& f) { faults += (faults.empty() ? "" : ", ") + f; };
  if (m.gaps > 0) add(std::to_string(m.gaps) + " gaps (" + fixed(100.0 * m.gap_share, 0) + " % of the circle)");
  if (m.roughness_mm > kLineRoughWithinMm + kEps) add("rough");
  if (cej_off > 0.0) add("off the CEJ band by " + fixed(cej_off) + " mm");
  k.why = faults.empty() ? "continuous, smooth" + std::string(cej ? ", at its height over the CEJ" : "") : faults;
}

void gradeUndercut(CrownScore& s, const CrownTask& c) {
  CrownCriterion& k = s.criteria[size_t(CrownCriterionId::Undercut)];
  if (!s.undercut) return notMeasured(k, s.undercut_error, s.completion);
  const double a = s.undercut->area_mm2;
  s.undercut_failed = a > c.undercut_tolerance_mm2 + kEps;
  grade(k, a <= kUndercutWithinMm2 + kEps ? CrownVerdict::Within : !s.undercut_failed ? CrownVerdict::Near : CrownVerdict::Outside,
        s.completion);
  size_t most = 0;
  for (size_t w = 1; w < 4; ++w)
    if (s.undercut->wall_area_mm2[w] > s.undercut->wall_area_mm2[most]) most = w;
  k.value = fixed(a, 3) + " mm^2";
  k.why = a <= kUndercutWithinMm2 + kEps ? "no undercut beyond the voxels' staircase"
                                           : std::string("most on the ") + kWallNames[most] + " side" +
                                                 (s.undercut_failed ? ": beyond the tolerance, the total is capped" : "");
}

}  // namespace

// ---- 4. the total -----------------------------------------------------------------------------------

ReductionBands crownReductionBands(const CrownTask& c) {
  ReductionBands b;
  b.occlusal_lo = c.occlusal_lo_mm;
  b.occlusal_hi = c.occlusal_hi_mm;
  b.axial_lo = c.axial_lo_mm;
  b.axial_hi = c.axial_hi_mm;
  return b;
}

Result<CrownScore> scoreCrownPreparation(const Task& task, const ToothVolume& initial, const ToothVolume& final_,
                                         const ToothDiff& diff) {
  const std::string where = "task " + task.name + ": crown";
  const CrownTask& c = task.crown;
  const double voxel_mm = initial.frame.voxel_mm;
  if (!finite(task.insertion_axis) || norm(task.insertion_axis) == 0) return makeError(where, "the insertion axis is zero");
  const Vec3 axis = normalized(task.insertion_axis);
  const auto& m = initial.frame.tooth.mesial;
  const Vec3 mesial(m[0], m[1], m[2]);
  if (norm(mesial - axis * dot(mesial, axis)) < 1e-6)
    return makeError(where, "the tooth's mesial direction lies along the insertion axis: the walls cannot be named");

  // The measures copy the teeth over their tissue's box, about two bytes a voxel at their peak (the
  // byte box of the margin, undercut and reduction measures, the bits of the loose-piece flood): a
  // box past the memory budget (a hostile or mislabelled .dvol) is refused before any is taken.
  const BrickBox bi = tissueBricks(initial.voxels), bf = tissueBricks(final_.voxels);
  if (!bi.empty() && !bf.empty()) {
    auto side = [](uint32_t lo0, uint32_t lo1, uint32_t hi0, uint32_t hi1) {
      return uint64_t(std::max(hi0, hi1) - std::min(lo0, lo1) + 1) * DS_BRICK_DIM;
    };
    const uint64_t voxels = side(bi.lo.x, bf.lo.x, bi.hi.x, bf.hi.x) * side(bi.lo.y, bf.lo.y, bi.hi.y, bf.hi.y) *
                            side(bi.lo.z, bf.lo.z, bi.hi.z, bf.hi.z);
    const uint64_t budget = memoryBudgetBytes();
    if (budget > 0 && 2 * voxels > budget)
      return makeError(where, "the teeth's tissue spans " + std::to_string(voxels) + " voxels: measuring it takes about " +
                                  gigabytesText(2 * voxels) + ", over the memory budget of " + gigabytesText(budget) + " (" +
                                  memoryBudgetOrigin() + ")");
  }
  CrownScore s;
  describeAll(s, c);
  // The measures read the teeth at half fill (volume/half_fill.h): the grains a bur leaves are not
  // tooth, nor is a sliver of wall the bur cut free of it (volume/loose_fragments.h).
  const BrickVolume& original = initial.voxels;
  BrickVolume prepared = final_.voxels;
  s.loose = dropLooseFragments(prepared);
  s.loose_mm3 = double(s.loose.voxels) * voxel_mm * voxel_mm * voxel_mm;
  auto margin = findMargin(original, prepared, voxel_mm, axis, mesial);
  if (!margin) return makeError(where, margin.message());
  s.margin = std::move(*margin);
  s.margin_found = s.margin.found_sectors > 0;
  s.coverage = double(s.margin.found_sectors) / double(kMarginSectors);
  if (s.margin_found) {
    // One height for every measure, the line's mean: a line that wanders is the margin_line
    // criterion's fault, and the mean keeps one low or high sector from moving every measure.
    s.margin_height_mm = s.margin.mean_height_mm;
    auto shape = measurePrepShape(prepared, voxel_mm, axis, mesial, s.margin_height_mm);
    if (shape) s.shape = std::move(*shape);
    else s.shape_error = shape.message();
    auto reduction = measureReduction(original, prepared, voxel_mm, axis, mesial, s.margin_height_mm, crownReductionBands(c));
    if (reduction) s.reduction = std::move(*reduction);
    else s.reduction_error = reduction.message();
    measureCompletion(s, original, prepared, voxel_mm, axis, mesial, c);
    auto undercut = measureUndercut(prepared, voxel_mm, axis, mesial, s.margin_height_mm);
    if (undercut) s.undercut = std::move(*undercut);
    else s.undercut_error = undercut.message();
  } else {
    const std::string none = "no finish line found: nothing was prepared";
    s.shape_error = s.reduction_error = s.undercut_error = none;
  }
  gradeOcclusal(s, c);
  gradeAxial(s, c);
  gradeTaper(s, c);
  gradeHeight(s, c);
  gradeMarginWidth(s, c);
  gradeMarginLine(s, c);
  gradeUndercut(s, c);

  double sum = 0.0;
  for (const CrownCriterion& k : s.criteria) {
    sum += k.points;
    s.criteria_total += k.verdict_points;
  }
  s.adjacent = scoreAdjacent(diff, task);
  s.total = clampScore(sum - s.adjacent.deduction, 0.0, s.total_max);
  // The two caps hold the total each on its own; the lower wins, and each says whether it held.
  const double undercut_cap = c.undercut_cap * s.total_max / 100.0;
  if (s.undercut_failed && s.total > undercut_cap) {
    s.total = undercut_cap;
    s.undercut_cap_applied = true;
  }
  s.pulp_exposed = diff.pulp_exposed;
  s.exposed_pulp_voxels = diff.exposed_pulp_voxels;
  if (s.pulp_exposed && s.total > pulpExposureCap(task, s.total_max)) {
    s.total = pulpExposureCap(task, s.total_max);
    s.pulp_cap_applied = true;
  }
  return s;
}

// ---- 5. the report, the lines, the terminal line and the paint ----------------------------------

namespace {

ojson statsJson(const ReductionStats& r) {
  return {{"samples", r.samples}, {"median_mm", r.median_mm}, {"mean_mm", r.mean_mm},         {"min_mm", r.min_mm},
          {"max_mm", r.max_mm},   {"under_share", r.under_share}, {"over_share", r.over_share}};
}

ojson criterionJson(const CrownCriterion& k) {
  ojson j = ojson::object();
  j["points"] = k.points;
  j["max"] = k.max;
  if (k.share) {
    j["table_points"] = k.verdict_points;
    j["earned_share"] = *k.share;
  }
  j["verdict"] = crownVerdictName(k.verdict);
  j["measured"] = k.measured;
  j["value"] = k.measured ? ojson(k.value) : ojson(nullptr);
  j["range"] = k.range;
  j["source"] = k.source;
  j["why"] = k.why;
  return j;
}

}  // namespace

ojson scoreReportJson(const Task& task, const ScoreInputs& inputs, const ToothDiff& diff, const SessionStats* stats,
                      const CrownScore& s) {
  const CrownTask& c = task.crown;
  ojson j = scoreReportHeader(task, inputs);
  // Nothing a crown is graded on needs the session: no part is left unscored without one.
  scoreReportTotals(j, s.total, s.total_max, s.criteria_total, {}, inputs);
  j["crown"] = {{"finish", c.finish},
                {"material", c.material},
                {"margin_found", s.margin_found},
                {"margin_height_mm", s.margin_found ? ojson(s.margin_height_mm) : ojson(nullptr)},
                {"insertion_axis", {task.insertion_axis.x, task.insertion_axis.y, task.insertion_axis.z}},
                {"rule", "within earns the criterion's points, near half, outside none"}};
  ojson comp = ojson::object();
  const auto& k = s.criteria;

  ojson occ = criterionJson(k[0]);
  occ["band_mm"] = {c.occlusal_lo_mm, c.occlusal_hi_mm};
  occ["occlusal"] = s.reduction ? statsJson(s.reduction->occlusal) : ojson(nullptr);
  comp[k[0].name] = std::move(occ);

  ojson ax = criterionJson(k[1]);
  ax["band_mm"] = {c.axial_lo_mm, c.axial_hi_mm};
  if (s.reduction) {
    ojson walls = ojson::object();
    for (size_t w = 0; w < 4; ++w) {
      walls[kWallNames[w]] = statsJson(s.reduction->axial[w]);
      walls[kWallNames[w]]["verdict"] = crownVerdictName(gradeWall(s.reduction->axial[w], c).verdict);
    }
    ax["walls"] = std::move(walls);
    ax["worst_wall"] = kWallNames[worstWall(s, c)];
    ax["unreached"] = s.reduction->unreached;
  } else {
    ax["walls"] = nullptr;
  }
  comp[k[1].name] = std::move(ax);

  ojson tp = criterionJson(k[2]);
  tp["range_deg"] = {c.toc_lo_deg, c.toc_hi_deg};
  tp["near_deg"] = {c.toc_near_lo_deg, c.toc_near_hi_deg};
  if (s.shape) {
    ojson planes = ojson::array();
    for (const TaperPlane& p : s.shape->planes)
      planes.push_back({{"plane", p.name},
                        {"toc_deg", p.toc_deg},
                        {"wall_deg", {p.wall_deg[0], p.wall_deg[1]}},
                        {"verdict", crownVerdictName(outside(p.toc_deg, c.toc_lo_deg, c.toc_hi_deg) == 0.0 ? CrownVerdict::Within
                                                     : outside(p.toc_deg, c.toc_near_lo_deg, c.toc_near_hi_deg) == 0.0
                                                         ? CrownVerdict::Near
                                                         : CrownVerdict::Outside)}});
    tp["planes"] = std::move(planes);
  } else {
    tp["planes"] = nullptr;
  }
  comp[k[2].name] = std::move(tp);

  ojson ht = criterionJson(k[3]);
  ht["height_mm"] = s.shape ? ojson(s.shape->height_mm) : ojson(nullptr);
  ht["width_md_mm"] = s.shape ? ojson(s.shape->width_md_mm) : ojson(nullptr);
  ht["width_bl_mm"] = s.shape ? ojson(s.shape->width_bl_mm) : ojson(nullptr);
  ht["height_width_ratio"] = s.shape ? ojson(s.shape->height_width_ratio) : ojson(nullptr);
  ht["min_height_mm"] = c.min_height_mm;
  ht["min_height_width_ratio"] = c.min_height_width_ratio;
  comp[k[3].name] = std::move(ht);

  ojson mw = criterionJson(k[4]);
  mw["band_mm"] = {c.margin_lo_mm, c.margin_hi_mm};
  mw["finish"] = c.finish;
  mw["mean_width_mm"] = s.margin_found ? ojson(s.margin.mean_width_mm) : ojson(nullptr);
  mw["min_width_mm"] = s.margin_found ? ojson(s.margin.min_width_mm) : ojson(nullptr);
  if (s.margin_found) {
    ojson widths = ojson::array();
    for (const MarginSector& sec : s.margin.sectors) widths.push_back(sec.found ? ojson(sec.width_mm) : ojson(nullptr));
    mw["sector_widths_mm"] = std::move(widths);
  }
  mw["coverage"] = s.coverage;
  comp[k[4].name] = std::move(mw);

  ojson ml = criterionJson(k[5]);
  ml["found_sectors"] = s.margin.found_sectors;
  ml["sectors"] = kMarginSectors;
  ml["gaps"] = s.margin.gaps;
  ml["gap_share"] = s.margin_found ? s.margin.gap_share : 1.0;
  ml["roughness_mm"] = s.margin_found ? ojson(s.margin.roughness_mm) : ojson(nullptr);
  ml["above_cej_mm"] = s.margin.mean_above_cej_mm ? ojson(*s.margin.mean_above_cej_mm) : ojson(nullptr);
  ml["above_cej_band_mm"] = {c.margin_above_cej_lo_mm, c.margin_above_cej_hi_mm};
  ml["height_mm"] = s.margin_found ? ojson(s.margin.mean_height_mm) : ojson(nullptr);
  ml["lowest_height_mm"] = s.margin_found ? ojson(s.margin.lowest_height_mm) : ojson(nullptr);
  int with_cej = 0;
  for (const MarginSector& sec : s.margin.sectors) with_cej += sec.cej_height_mm ? 1 : 0;
  ml["sectors_with_cej"] = with_cej;
  comp[k[5].name] = std::move(ml);

  ojson uc = criterionJson(k[6]);
  uc["area_mm2"] = s.undercut ? ojson(s.undercut->area_mm2) : ojson(nullptr);
  if (s.undercut) {
    ojson walls = ojson::object();
    for (size_t w = 0; w < 4; ++w) walls[kWallNames[w]] = s.undercut->wall_area_mm2[w];
    uc["wall_area_mm2"] = std::move(walls);
    uc["hidden_voxels"] = s.undercut->voxels.size();
  }
  uc["within_mm2"] = kUndercutWithinMm2;
  uc["tolerance_mm2"] = c.undercut_tolerance_mm2;
  comp[k[6].name] = std::move(uc);
  j["components"] = std::move(comp);

  j["completion"] = {{"share", s.completion},
                     {"rule", "taper, height, margin_line and undercut are earned at min(1, reached_share / complete_at), "
                              "reached_share the share of the original's surface above the margin reduced by at least "
                              "share_of_lo of its band's lo; margin_width at the finish line's coverage of the circle"},
                     {"reached_share", s.reached_share},
                     {"complete_at", kCompleteAtShare},
                     {"samples", s.completion_samples},
                     {"reached", s.completion_reached},
                     {"share_of_lo", kCompletionShareOfLo},
                     {"margin_coverage", s.coverage}};
  j["loose_fragments"] = {{"pieces", s.loose.pieces},
                          {"voxels", s.loose.voxels},
                          {"volume_mm3", s.loose_mm3},
                          {"rule", "pieces of solid tooth not joined by a face to the largest piece (the tooth with its "
                                   "root) are cut free: they fall away in the mouth, and are measured as gone"}};
  ojson d = ojson::object();
  if (s.adjacent.has_neighbour) d["adjacent"] = adjacentDeductionJson(task, s.adjacent);
  d["undercut_cap"] = {{"undercut_failed", s.undercut_failed},
                       {"area_mm2", s.undercut ? ojson(s.undercut->area_mm2) : ojson(nullptr)},
                       {"tolerance_mm2", c.undercut_tolerance_mm2},
                       {"cap", c.undercut_cap * s.total_max / 100.0},
                       {"cap_of_100", c.undercut_cap},
                       {"applied", s.undercut_cap_applied}};
  d["pulp_exposure"] = pulpExposureCapJson(task, s.pulp_exposed, s.pulp_cap_applied, s.total_max);
  j["deductions"] = std::move(d);
  j["pulp_exposed"] = s.pulp_exposed;
  // Against no ideal the zones would count the whole preparation as cut outside a caries zone: a
  // crown has none, so its report gives them only against an ideal.
  if (diff.has_ideal) j["zones"] = scoreZonesJson(diff);
  j["warnings"] = inputs.warnings;
  j["volumes"] = scoreVolumesJson(diff);
  ojson session = scoreSessionJson(stats, inputs);
  session["scored"] = false;
  session["why_not_scored"] = kSessionNotScored;
  j["session"] = std::move(session);
  return j;
}

std::vector<ScoreLine> scoreLines(const CrownScore& s) {
  std::vector<ScoreLine> lines;
  for (const CrownCriterion& k : s.criteria) {
    ScoreLine line;
    line.name = k.name;
    line.points = k.points;
    line.max = k.max;
    line.detail = (k.measured ? k.value : std::string("not measured")) + " (" + k.band + ") " + crownVerdictName(k.verdict);
    lines.push_back(std::move(line));
  }
  if (s.adjacent.has_neighbour) {
    ScoreLine line;
    line.name = "adjacent";
    line.points = s.adjacent.deduction;
    line.deduction = true;
    lines.push_back(std::move(line));
  }
  return lines;
}

std::string scoreSummary(const CrownScore& s, const ScoreInputs& /*inputs*/) {
  std::string line = "crown preparation score " + fixed(s.total) + " / " + fixed(s.total_max, 0) + " (";
  for (size_t i = 0; i < s.criteria.size(); ++i) {
    const CrownCriterion& k = s.criteria[i];
    std::string label = k.name;
    std::replace(label.begin(), label.end(), '_', ' ');
    line += (i ? ", " : "") + label + " " + fixed(k.points, 1) + " / " + fixed(k.max, 0) + " " + crownVerdictName(k.verdict);
  }
  if (s.adjacent.damaged) line += ", adjacent tooth damaged -" + fixed(s.adjacent.deduction);
  if (s.undercut_cap_applied) line += ", capped: undercut";
  if (s.pulp_cap_applied) line += ", capped: pulp exposed";
  line += "; " + fixed(100.0 * s.completion, 1) + "% of the preparation done, so taper, height, margin line and undercut earned at that share";
  line += "; time and force reported, not scored): ";
  if (!s.margin_found) {
    line += "no finish line found: nothing was prepared";
  } else {
    line += "margin at " + fixed(s.margin_height_mm) + " mm, " + std::to_string(s.margin.found_sectors) + " of " +
            std::to_string(kMarginSectors) + " sectors";
    for (const CrownCriterion& k : s.criteria)
      if (k.measured) {
        std::string label = k.name;
        std::replace(label.begin(), label.end(), '_', ' ');
        line += "; " + label + " " + k.value;
      }
  }
  if (s.loose.pieces > 0)
    line += "; " + std::to_string(s.loose.pieces) + (s.loose.pieces == 1 ? " piece" : " pieces") + " cut free (" +
            fixed(s.loose_mm3, 3) + " mm^3), measured as gone";
  line += s.pulp_exposed ? "; pulp exposed" : "; pulp not exposed";
  if (s.adjacent.has_neighbour) line += "; adjacent tooth " + fixed(s.adjacent.removed_mm3, 3) + " mm^3 removed";
  return line;
}

CutMarks reductionPaint(const CrownPrepReduction& r, const BrickVolume* prepared) {
  constexpr uint64_t kMask = (uint64_t{1} << 21) - 1;
  // Where rays of several samples meet one prepared voxel, the shortest band wins: under, then
  // within, then over. The gauge held square to the surface is the shortest ray to a voxel; the
  // longer ones come in obliquely from samples farther off (a bevel's rays across the occlusal
  // table), and would paint a table cut to depth red. Where any square reading says more must come
  // off, that is what the voxel shows.
  std::unordered_map<uint64_t, int> band_rank;  // 1 over, 2 within, 3 under
  const auto rankAll = [&](const std::vector<uint64_t>& keys, int rank) {
    for (uint64_t key : keys) band_rank[key] = std::max(band_rank[key], rank);
  };
  rankAll(r.prepared_over, 1);
  rankAll(r.prepared_within, 2);
  rankAll(r.prepared_under, 3);
  constexpr uint32_t kCodeOfRank[4] = {0, kPaintRed, kPaintGreen, kPaintBlue};
  CutMarks paint;
  for (const auto& [key, rank] : band_rank)
    paint.add(uint32_t(key & kMask), uint32_t((key >> 21) & kMask), uint32_t(key >> 42), kCodeOfRank[rank]);
  if (!prepared) return paint;
  // Each painted voxel lends its colour to its unpainted tooth neighbours (26), in the same order of
  // precedence: a picture's ray stops at the first voxel at least half full, which under a thin
  // outer voxel the gauge met is the one behind it, and the map would otherwise be speckled.
  const int64_t dim = prepared->dim();
  for (int rank = 3; rank >= 1; --rank)
    for (const auto& [key, kr] : band_rank) {
      if (kr != rank) continue;
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int64_t x = int64_t(key & kMask) + dx, y = int64_t((key >> 21) & kMask) + dy, z = int64_t(key >> 42) + dz;
            if (x < 0 || y < 0 || z < 0 || x >= dim || y >= dim || z >= dim) continue;
            const auto ux = uint32_t(x), uy = uint32_t(y), uz = uint32_t(z);
            if (paint.at(ux, uy, uz) == 0 && isToothTissue(voxelMaterial(prepared->voxel(ux, uy, uz))))
              paint.add(ux, uy, uz, kCodeOfRank[rank]);
          }
    }
  return paint;
}

CutMarks crownPaint(const CrownScore& s, const BrickVolume* prepared) {
  constexpr uint64_t kMask = (uint64_t{1} << 21) - 1;
  CutMarks paint = s.reduction ? reductionPaint(*s.reduction, prepared) : CutMarks{};
  const auto mark = [&](uint64_t key, uint32_t code) {
    paint.add(uint32_t(key & kMask), uint32_t((key >> 21) & kMask), uint32_t((key >> 42) & kMask), code);
  };
  // CutMarks keeps the larger code where two mark one voxel: the undercut over the line over the map.
  for (uint64_t key : s.margin.line_voxels) mark(key, kPaintYellow);
  if (s.undercut)
    for (uint64_t key : s.undercut->voxels) mark(key, kPaintMagenta);
  return paint;
}

}  // namespace dentsim
