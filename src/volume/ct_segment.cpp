// One tooth from grey values: the steps of segmentTooth in order, from the ROI and the tooth's hard piece to the tissue labels.
//
// The algorithms it calls live one per file: tooth_thresholds (presets, given, Otsu, refined on the
// tooth), otsu_thresholds, voxel_grid_ops (bits, floods, dilation), seeded_split (with
// distance_transform), tissue_boundary_rules (classes, partial volume, edges, caries), and
// label_import's cleanSmallPieces for islands. The rules are in
// docs/PATIENT_SCANS.md, "How a tooth is segmented".
//
// Contents
//   1. Small tools (progress, scanner geometry, messages)
//   2. The ROI: its voxel box and a view of the image
//   3. The tooth: the largest hard piece, or the seeded piece cut from its neighbours
//   4. segmentTooth: ROI, thresholds, hard mask, seed, tooth, output box, the boundary rules
//      (tissue_boundary_rules.h), islands, labels
#include "volume/ct_segment.h"

#include "volume/brick_volume.h"
#include "volume/label_import.h"
#include "volume/otsu_thresholds.h"
#include "volume/seeded_split.h"
#include "volume/tissue_boundary_rules.h"
#include "volume/tissue_table.h"
#include "volume/tooth_thresholds.h"
#include "volume/voxel_grid_ops.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>

namespace dentsim {

namespace {

// ---- 1. small tools -------------------------------------------------------------------------

// Progress over consecutive steps: step k of the job covers [begin, end) of the bar.
struct Stage {
  Interrupter& interrupter;
  double begin = 0.0, end = 1.0;
  bool report(double fraction) const { return interrupter.progress(begin + (end - begin) * fraction); }
};

// Hands a sub-job's progress (keepSeededPart, cleanSmallPieces) on into one step of this job and
// remembers a cancel, so the error can name the segmentation rather than the sub-job.
class StageInterrupter : public Interrupter {
 public:
  explicit StageInterrupter(const Stage& stage) : stage_(stage) {}
  bool progress(double fraction) override {
    cancelled = cancelled || !stage_.report(fraction);
    return !cancelled;
  }
  bool cancelled = false;

 private:
  Stage stage_;
};

Error cancelled(const std::string& where) { return makeError(where, "segmentation cancelled"); }

// The inverse of a 3 x 4 affine map (rows r: m[4r..4r+2] linear, m[4r+3] offset); false when singular.
bool invertAffine(const std::array<double, 12>& m, std::array<double, 12>& inv) {
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
  const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  if (!std::isfinite(det) || std::abs(det) < 1e-300) return false;
  const double r[9] = {(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det,
                       (f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det,
                       (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det};
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) inv[size_t(4 * row + col)] = r[3 * row + col];
    inv[size_t(4 * row + 3)] = -(r[3 * row] * m[3] + r[3 * row + 1] * m[7] + r[3 * row + 2] * m[11]);
  }
  return true;
}

std::array<double, 3> applyAffine(const std::array<double, 12>& m, const std::array<double, 3>& p) {
  std::array<double, 3> out{};
  for (size_t r = 0; r < 3; ++r) out[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
  return out;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string mmPoint(const std::array<double, 3>& p) {
  return "(" + num(p[0]) + ", " + num(p[1]) + ", " + num(p[2]) + ") mm";
}

// ---- 2. the ROI: its voxel box and a view of the image ---------------------------------------

// The ROI as a view of the image: local index -> the image's value.
struct RoiView {
  const GreyImage& image;
  IndexBox box;
  std::array<int32_t, 3> d;
  float value(uint64_t l) const {
    const std::array<int64_t, 3> c = voxelCoords(l, d);
    return image.values[image.index(box.lo[0] + c[0], box.lo[1] + c[1], box.lo[2] + c[2])];
  }
  // Calls f(local index, value) over the ROI in memory order.
  template <class F>
  void forEach(F&& f) const {
    uint64_t l = 0;
    for (int64_t z = box.lo[2]; z <= box.hi[2]; ++z)
      for (int64_t y = box.lo[1]; y <= box.hi[1]; ++y) {
        const float* row = &image.values[image.index(box.lo[0], y, z)];
        for (int64_t x = 0; x < d[0]; ++x, ++l) f(l, row[x]);
      }
  }
};

// The ROI as a voxel box of the image.
Result<IndexBox> roiBox(const GreyImage& image, const std::array<double, 12>& inv, const ToothSegmentOptions& o) {
  IndexBox box;
  box.hi = {image.dims[0] - 1, image.dims[1] - 1, image.dims[2] - 1};
  if (!o.roi) return box;
  const MmBox& r = *o.roi;
  std::array<double, 3> vmin, vmax;
  vmin.fill(std::numeric_limits<double>::infinity());
  vmax.fill(-std::numeric_limits<double>::infinity());
  for (int c = 0; c < 8; ++c) {
    const std::array<double, 3> p = {(c & 1) ? r.hi[0] : r.lo[0], (c & 2) ? r.hi[1] : r.lo[1], (c & 4) ? r.hi[2] : r.lo[2]};
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      return makeError(o.where, "the ROI has a corner that is not a finite number");
    const std::array<double, 3> v = applyAffine(inv, p);
    for (size_t a = 0; a < 3; ++a) {
      vmin[a] = std::min(vmin[a], v[a]);
      vmax[a] = std::max(vmax[a], v[a]);
    }
  }
  const std::string said = "the ROI " + mmPoint(r.lo) + " .. " + mmPoint(r.hi);
  constexpr double kSlack = 1e-6;  // voxels: corners placed on voxel centres by float arithmetic
  for (size_t a = 0; a < 3; ++a) {
    const double lo = std::ceil(vmin[a] - kSlack), hi = std::floor(vmax[a] + kSlack);
    if (lo > hi) return makeError(o.where, said + " holds no voxel centre");
    if (hi < 0 || lo > double(image.dims[a] - 1))
      return makeError(o.where, said + " lies outside the image (" + std::to_string(image.dims[0]) + " x " +
                                    std::to_string(image.dims[1]) + " x " + std::to_string(image.dims[2]) + " voxels)");
    box.lo[a] = int64_t(std::max(lo, 0.0));
    box.hi[a] = int64_t(std::min(hi, double(image.dims[a] - 1)));
  }
  return box;
}

// ---- 3. the tooth ---------------------------------------------------------------------------

// The 0/1 grid of `mask` over a local box of the ROI.
std::vector<uint8_t> gridOf(const VoxelBits& mask, const std::array<int32_t, 3>& roi_d, const IndexBox& sub) {
  std::vector<uint8_t> out(sub.count());
  size_t i = 0;
  for (int64_t z = sub.lo[2]; z <= sub.hi[2]; ++z)
    for (int64_t y = sub.lo[1]; y <= sub.hi[1]; ++y)
      for (int64_t x = sub.lo[0]; x <= sub.hi[0]; ++x, ++i)
        out[i] = mask.test(voxelIndex({x, y, z}, roi_d)) ? 1 : 0;
  return out;
}

// The tooth's voxels in the ROI and their bounding box (ROI-local).
struct ToothMask {
  VoxelBits bits;
  IndexBox box;
};

// The closing radius that seals the pulp for the cut's fill [mm]: voxelize's default --seal-mm, about
// an apical foramen's radius, so the canals close as they do when importLabels fills the pulp.
constexpr double kSplitSealMm = 0.2;

// The seed's hard piece cut at narrow joins (keepSeededPart), or without a seed the largest hard piece.
Result<ToothMask> findTooth(const RoiView& roi, const VoxelBits& hard, std::optional<uint64_t> seed,
                            const std::array<double, 3>& pitch, const ToothSegmentOptions& options, const Stage& stage,
                            std::deque<uint64_t>& queue, ToothSegmentReport& rep) {
  const uint64_t n_roi = roi.box.count();
  ToothMask tooth{VoxelBits(n_roi), IndexBox{}};
  if (!seed) {
    VoxelBits seen(n_roi);
    uint64_t best = 0, best_start = 0;
    for (uint64_t l = 0; l < n_roi; ++l) {
      if (!hard.test(l) || seen.test(l)) continue;
      const VoxelPiece p = floodPiece(hard, seen, roi.d, l, queue);
      if (p.voxels > best) {
        best = p.voxels;
        best_start = l;
      }
    }
    const VoxelPiece largest = floodPiece(hard, tooth.bits, roi.d, best_start, queue);
    tooth.box = largest.box;
    rep.hard_component_voxels = rep.tooth_voxels = largest.voxels;
    return tooth;
  }
  const VoxelPiece piece = floodPiece(hard, tooth.bits, roi.d, *seed, queue);
  rep.hard_component_voxels = piece.voxels;
  if (!stage.report(0.2)) return cancelled(options.where);
  // The flood order holds 32-bit indices into the piece's box.
  if (piece.box.count() > std::numeric_limits<uint32_t>::max())
    return makeError(options.where, "the seed's hard tissue spans " + std::to_string(piece.box.count()) +
                                        " voxels, more than the cut handles (2^32): set an ROI around the tooth");
  const std::array<int32_t, 3> pd = piece.box.dims();
  const std::array<int64_t, 3> sc = voxelCoords(*seed, roi.d);
  const uint64_t seed_in_piece = voxelIndex({sc[0] - piece.box.lo[0], sc[1] - piece.box.lo[1], sc[2] - piece.box.lo[2]}, pd);
  std::vector<uint8_t> kept = gridOf(tooth.bits, roi.d, piece.box);
  StageInterrupter sub(Stage{stage.interrupter, stage.begin + 0.2 * (stage.end - stage.begin), stage.end});
  // A digital shape's depth rises in steps of up to 0.41 voxel (1 to sqrt 2 voxels), so a bump of
  // less than half a voxel is the grid's, not a part: at 1 mm a 0.3 mm height, pulp filled, still
  // let a seed in tooth_2 keep only 45 of its 624 voxels (tests/volume/seeded_split_tooth2_test.cpp).
  const double h_mm = std::max(options.split_h_mm, 0.5 * std::max({pitch[0], pitch[1], pitch[2]}));
  if (!keepSeededPart(kept, pd, pitch, seed_in_piece, h_mm, kSplitSealMm, sub))
    return cancelled(options.where);
  tooth.bits = VoxelBits(n_roi);
  tooth.box.lo = {roi.d[0], roi.d[1], roi.d[2]};
  size_t i = 0;
  for (int64_t z = piece.box.lo[2]; z <= piece.box.hi[2]; ++z)
    for (int64_t y = piece.box.lo[1]; y <= piece.box.hi[1]; ++y)
      for (int64_t x = piece.box.lo[0]; x <= piece.box.hi[0]; ++x, ++i) {
        if (!kept[i]) continue;
        tooth.bits.set(voxelIndex({x, y, z}, roi.d));
        ++rep.tooth_voxels;
        const int64_t c[3] = {x, y, z};
        for (size_t a = 0; a < 3; ++a) {
          tooth.box.lo[a] = std::min(tooth.box.lo[a], c[a]);
          tooth.box.hi[a] = std::max(tooth.box.hi[a], c[a]);
        }
      }
  rep.neighbour_voxels_cut = piece.voxels - rep.tooth_voxels;
  return tooth;
}

}  // namespace

// ---- 4. segmentTooth ------------------------------------------------------------------------

Result<LabelImage> segmentTooth(const GreyImage& image, const ToothSegmentOptions& options,
                                Interrupter& interrupter, ToothSegmentReport* report) {
  ToothSegmentReport local;
  ToothSegmentReport& rep = report ? *report : local;
  rep = ToothSegmentReport{};
  rep.unit = image.unit;
  const std::string& where = options.where;
  const std::string unit = std::string(" ") + greyUnitName(image.unit);

  if (image.dims[0] <= 0 || image.dims[1] <= 0 || image.dims[2] <= 0 || image.values.empty())
    return makeError(where, "the image is empty");
  if (image.values.size() != uint64_t(image.voxelCount()))
    return makeError(where, "the image holds " + std::to_string(image.values.size()) + " values for " +
                                std::to_string(image.voxelCount()) + " voxels");
  if (options.min_island_mm3 < 0 || !std::isfinite(options.min_island_mm3))
    return makeError(where, "min_island_mm3 must be a number >= 0, not " + num(options.min_island_mm3));
  if (options.partial_volume_voxels < 0 || options.margin_voxels < 0 || !(options.split_h_mm >= 0))
    return makeError(where, "partial-volume width, margin and split height must be >= 0");
  std::array<double, 12> inv{};
  if (!invertAffine(image.scanner_from_voxel, inv)) return makeError(where, "the scanner matrix is singular");

  interrupter.start("segmenting the tooth");
  const Stage job{interrupter, 0.0, 1.0};

  // ROI and thresholds.
  Result<IndexBox> roi_box = roiBox(image, inv, options);
  if (!roi_box) return roi_box.error();
  const RoiView roi{image, *roi_box, roi_box->dims()};
  rep.roi_lo = roi.box.lo;
  rep.roi_hi = roi.box.hi;
  Result<ToothThresholds> chosen = chooseThresholds(options, image.unit, [&] {
    return robustHistogram([&](auto&& f) { roi.forEach([&](uint64_t, float v) { f(v); }); });
  });
  if (!chosen) return chosen.error();
  ToothThresholds thr = *chosen;
  if (!job.report(0.1)) return cancelled(where);

  // The hard mask over the ROI.
  const uint64_t n_roi = roi.box.count();
  VoxelBits hard(n_roi);
  uint64_t hard_count = 0;
  roi.forEach([&](uint64_t l, float v) {
    if (v >= thr.hard) {
      hard.set(l);
      ++hard_count;
    }
  });
  if (hard_count == 0)
    return makeError(where, "no voxel reaches the dentin threshold " + num(thr.hard) + unit);

  // The seed, when given, in ROI-local coordinates.
  std::optional<uint64_t> seed_local;
  if (options.seed_mm) {
    const std::array<double, 3>& s = *options.seed_mm;
    const std::array<double, 3> v = applyAffine(inv, s);
    std::array<int64_t, 3> c{};
    for (size_t a = 0; a < 3; ++a) {
      const double r = std::round(v[a]);
      if (!(r >= 0 && r <= double(image.dims[a] - 1)))
        return makeError(where, "the seed " + mmPoint(s) + " is outside the image");
      c[a] = int64_t(r);
    }
    for (size_t a = 0; a < 3; ++a)
      if (c[a] < roi.box.lo[a] || c[a] > roi.box.hi[a])
        return makeError(where, "the seed " + mmPoint(s) + " is outside the ROI");
    const uint64_t l = voxelIndex({c[0] - roi.box.lo[0], c[1] - roi.box.lo[1], c[2] - roi.box.lo[2]}, roi.d);
    if (!hard.test(l))
      return makeError(where, "the seed " + mmPoint(s) + " is not in hard tissue: value " +
                                  num(image.values[image.index(c[0], c[1], c[2])]) + unit + " (dentin_above " +
                                  num(thr.hard) + unit + ")");
    seed_local = l;
    rep.seeded = true;
  }

  // The tooth: the seed's piece cut at narrow joins, or the largest piece.
  std::deque<uint64_t> queue;
  Result<ToothMask> found = findTooth(roi, hard, seed_local, image.pitch_mm, options, Stage{interrupter, 0.1, 0.6}, queue, rep);
  if (!found) return found.error();
  // A ROI of air or soft tissue alone still splits into "classes" of noise; what it calls a tooth is
  // then a speck. No tooth is smaller than min_tooth_mm3, so a speck is an error, not a tooth.
  const double tooth_mm3 = double(rep.tooth_voxels) * image.pitch_mm[0] * image.pitch_mm[1] * image.pitch_mm[2];
  if (tooth_mm3 < options.min_tooth_mm3)
    return makeError(where, std::string(rep.seeded ? "the seed's tooth" : "the largest piece of hard tissue") + " is only " +
                                num(tooth_mm3) + " mm^3 (hard from " + num(thr.hard) + unit +
                                "): no tooth here; check the ROI, or give the thresholds");
  const IndexBox& tooth_box = found->box;
  hard = VoxelBits();
  if (!job.report(0.6)) return cancelled(where);

  // The output box: the tooth's box and a margin, within the ROI (local, then image coordinates).
  IndexBox out_local;
  for (size_t a = 0; a < 3; ++a) {
    out_local.lo[a] = std::max<int64_t>(0, tooth_box.lo[a] - options.margin_voxels);
    out_local.hi[a] = std::min<int64_t>(roi.d[a] - 1, tooth_box.hi[a] + options.margin_voxels);
    rep.out_lo[a] = roi.box.lo[a] + out_local.lo[a];
    rep.out_hi[a] = roi.box.lo[a] + out_local.hi[a];
    rep.tooth_lo[a] = roi.box.lo[a] + tooth_box.lo[a];
    rep.tooth_hi[a] = roi.box.lo[a] + tooth_box.hi[a];
  }
  const std::array<int32_t, 3> od = out_local.dims();
  const uint64_t n_out = out_local.count();
  ToothBoxCells box{image, rep.out_lo, od, std::vector<uint8_t>(n_out, 0)};
  {
    size_t o = 0;
    for (int64_t z = out_local.lo[2]; z <= out_local.hi[2]; ++z)
      for (int64_t y = out_local.lo[1]; y <= out_local.hi[1]; ++y)
        for (int64_t x = out_local.lo[0]; x <= out_local.hi[0]; ++x, ++o)
          if (found->bits.test(voxelIndex({x, y, z}, roi.d))) box.cells[o] = tooth_cell::kToothMark;
  }
  found->bits = VoxelBits();

  // Thresholds refined on the tooth, then classes and their means.
  const auto tooth_histogram = [&](double lo, double hi) {
    return robustHistogram([&](auto&& f) {
      for (uint64_t o = 0; o < box.cells.size(); ++o) {
        if (box.cells[o] != tooth_cell::kToothMark) continue;
        const float v = box.value(o);
        if (v >= lo && v < hi) f(v);
      }
    });
  };
  if (Status s = refineOnTooth(thr, image.unit, where, tooth_histogram); !s) return s.error();
  rep.dentin_above = thr.hard;
  rep.enamel_above = thr.enamel;
  rep.caries_below = thr.caries_below;
  rep.thresholds_from = thresholdsFrom(thr);
  const ClassMeans means = classify(box, thr);
  if (!job.report(0.7)) return cancelled(where);

  // Partial volume, then the outside again (the rule empties the rim), then edges and caries.
  const int w = options.partial_volume_voxels;
  if (w > 0) rep.partial_volume_voxels = applyPartialVolume(box, w, options.caries, means, queue);
  if (!job.report(0.8)) return cancelled(where);

  markOutside(box.cells, box.d, queue);
  const std::array<double, 2> dark = darkMeans(box, thr.hard, means.mean[0]);
  rep.edge_voxels = applyEdgeRule(box, w, dark, means);
  if (options.caries) rep.caries_rejected_voxels = keepOpenCaries(box, std::max(w, 1), dark, means, queue);
  if (!job.report(0.85)) return cancelled(where);

  // Islands, through importLabels' own rule, on voxel codes.
  std::vector<uint8_t>& cells = box.cells;
  for (uint8_t& c : cells) {
    using namespace tooth_cell;
    const Material m = kClassTissue[classOf(c)];
    c = m == Material::Empty ? Voxel(0) : makeVoxel(m);
  }
  const double voxel_mm3 = image.pitch_mm[0] * image.pitch_mm[1] * image.pitch_mm[2];
  rep.min_island_voxels = options.min_island_mm3 / voxel_mm3;
  const int64_t min_voxels = int64_t(std::ceil(rep.min_island_voxels - 1e-9));
  if (min_voxels > 1) {
    PieceCleanup cleanup;
    StageInterrupter sub(Stage{interrupter, 0.85, 0.99});
    Status s = cleanSmallPieces(cells, od, min_voxels, cleanup, sub, where);
    if (sub.cancelled) return cancelled(where);
    if (!s) return s.error();
    for (size_t m = 0; m < cleanup.pieces.size(); ++m) {
      rep.islands_removed += cleanup.pieces[m];
      rep.island_voxels += cleanup.voxels[m];
    }
  }

  // The label image: tissue table labels, the image's geometry shifted to the box.
  LabelImage out;
  out.dims = od;
  out.pitch_mm = image.pitch_mm;
  out.scanner_from_voxel = image.scanner_from_voxel;
  const std::array<double, 3> origin = applyAffine(image.scanner_from_voxel,
                                                   {double(rep.out_lo[0]), double(rep.out_lo[1]), double(rep.out_lo[2])});
  for (size_t r = 0; r < 3; ++r) out.scanner_from_voxel[4 * r + 3] = origin[r];
  out.labels.resize(n_out);
  for (uint64_t o = 0; o < n_out; ++o) {
    const Material m = static_cast<Material>(voxelMaterial(cells[o]));
    const TissueRow* row = findTissue(m);
    out.labels[o] = row ? Label(row->nifti_label) : Label(0);
    if (row) ++rep.tissue_voxels[size_t(row - kTissueTable)];
  }
  if (!job.report(1.0)) return cancelled(where);
  interrupter.end();
  return out;
}

}  // namespace dentsim
