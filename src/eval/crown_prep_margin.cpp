// The crown preparation's finish line: cut and uncut prepared surface, the line per sector, its width, gaps, roughness and the CEJ.
//
// The rules (docs/CROWN_PREPARATION.md says the same for examiners):
//
// Surface. Only tooth tissues count (isToothTissue): a neighbouring tooth is air here. A prepared
// surface voxel is a prepared tooth voxel with a face neighbour that is not prepared tooth. It is
// *cut* when one such neighbour was tooth in the original (the surface moved inward there), else
// *uncut*. Uncut surface whose only open faces look down the axis (a root's apex, the grid's bottom
// face of a cropped tooth) is not wall: a cut down to it reached no finish line.
//
// The line. A cut voxel lies on the finish line when one of its 26 neighbours, with a lower centre
// along the axis, is uncut wall: there the prepared surface leaves the original one. Each such
// voxel's height is that of its lowest face toward removed tooth (the top face of a shoulder's
// floor, the outer face of a chamfer's rim). The voxels fall in kMarginSectors wedges by the angle
// of their centres around the axis line through the original tooth's centroid (0 at mesial, turning
// toward buccal = axis x mesial); a sector's line is its lowest voxel's height. A sector with no
// such voxel has no line: nothing was cut there, or the cut ran down the root with no uncut wall
// below it.
//
// Width. Where the axial wall stands in from the original surface at the line, as an examiner
// reads a section: the original's outer radius at the line's layer, less the prepared axial wall's
// radius extrapolated down to the line from a least-squares line through the wall between 1.5 and
// 2.5 mm above it (above a 1.5 mm chamfer's curve, in the gingival band where the taper is read).
// Radii are the outermost surface voxel's centre in the sector's wedge and height bin (one voxel
// tall), plus half a voxel for its outer face. A wall with fewer than 3 bins in that band (a
// preparation under 2.5 mm tall there) takes the largest shortfall above the line instead.
//
// Gaps: runs of sectors without a line, around the circle (all sectors missing: one gap).
// Roughness: the RMS, over sectors found with both neighbours found, of a sector's height less the
// mean of its neighbours' (a second difference: a straight line tilted across the tooth reads
// near 0, a zig-zag its teeth).
// CEJ: per sector, the lowest centre of the original's enamel surface voxels there.
#include "eval/crown_prep_margin.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "eval/crown_prep_reduction.h"

namespace dentsim {
namespace {

// The flags of the margin's voxel box.
constexpr uint8_t kOriginal = 1;   // tooth in the original
constexpr uint8_t kPrepared = 2;   // tooth in the prepared tooth
constexpr uint8_t kEnamel = 4;     // enamel in the original
constexpr uint8_t kCut = 8;        // prepared surface that was moved inward
constexpr uint8_t kWall = 16;      // uncut prepared surface open sideways or up

constexpr int kFace[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
// The axial wall is fitted this far above the line [mm], and needs this many bins there.
constexpr double kWallFitLoMm = 1.5;
constexpr double kWallFitHiMm = 2.5;
constexpr int kMinWallBins = 3;
constexpr double kNone = -std::numeric_limits<double>::infinity();

// A voxel on the line, for the line voxels' list.
struct LineVoxel {
  int sector = 0;
  double height = 0;  // [voxels]
  uint64_t key = 0;
};

// Least-squares value at h0 of the line through (h, r).
double fitAt(const std::vector<double>& h, const std::vector<double>& r, double h0) {
  const double n = double(h.size());
  double hm = 0, rm = 0;
  for (size_t i = 0; i < h.size(); ++i) hm += h[i], rm += r[i];
  hm /= n, rm /= n;
  double shr = 0, shh = 0;
  for (size_t i = 0; i < h.size(); ++i) shr += (h[i] - hm) * (r[i] - rm), shh += (h[i] - hm) * (h[i] - hm);
  return shh > 0 ? rm + shr / shh * (h0 - hm) : rm;
}

}  // namespace

Result<MarginLine> findMargin(const BrickVolume& original, const BrickVolume& prepared, double voxel_mm,
                              const Vec3& insertion_axis, const Vec3& mesial) {
  const std::string where = "crown margin";
  if (Status st = checkCrownTeeth(original, prepared, voxel_mm, where); !st) return st.error();
  const Result<CrownFrame> frame = crownFrame(insertion_axis, mesial, where);
  if (!frame) return frame.error();
  const Vec3 a = frame->axis, m = frame->mesial, b = frame->buccal;

  // 1. Both teeth in one box.
  CrownVoxelBox box = crownVoxelBox(original, &prepared);
  markTooth(box, original, kOriginal, kEnamel);
  markTooth(box, prepared, kPrepared);
  Vec3 centroid;
  double originals = 0, prepareds = 0;
  double h_min = std::numeric_limits<double>::infinity(), h_max = -h_min;
  const int32_t x0 = box.lo[0], y0 = box.lo[1], z0 = box.lo[2];
  const int32_t x1 = x0 + box.n[0], y1 = y0 + box.n[1], z1 = z0 + box.n[2];
  for (int32_t z = z0; z < z1; ++z)
    for (int32_t y = y0; y < y1; ++y)
      for (int32_t x = x0; x < x1; ++x) {
        const uint8_t f = box.bits[box.index(x, y, z)];
        if (!(f & (kOriginal | kPrepared))) continue;
        const Vec3 p(x + 0.5, y + 0.5, z + 0.5);
        if (f & kOriginal) centroid += p, originals += 1;
        if (f & kPrepared) prepareds += 1;
        const double h = dot(p, a);
        h_min = std::min(h_min, h), h_max = std::max(h_max, h);
      }
  if (originals == 0) return makeError(where, "the original holds no tooth");
  if (prepareds == 0) return makeError(where, "the prepared tooth holds no tooth");
  centroid = centroid / originals;

  // 2. Surface flags, the sectors' profiles (outermost surface centre per height bin) and the CEJ.
  const double sector_rad = 2 * std::numbers::pi / kMarginSectors;
  auto sectorOf = [&](const Vec3& p, double* radius) {
    const Vec3 d = p - centroid;
    const double u = dot(d, m), v = dot(d, b);
    *radius = std::sqrt(u * u + v * v);
    double phi = std::atan2(v, u);
    if (phi < 0) phi += 2 * std::numbers::pi;
    return std::min(kMarginSectors - 1, int(phi / sector_rad));
  };
  auto binOf = [&](double h) { return size_t(std::lround(h - h_min)); };
  const size_t bins = binOf(h_max) + 1;
  std::vector<double> r_orig(size_t(kMarginSectors) * bins, kNone), r_prep(size_t(kMarginSectors) * bins, kNone);
  std::array<double, kMarginSectors> cej;
  cej.fill(std::numeric_limits<double>::infinity());
  for (int32_t z = z0; z < z1; ++z)
    for (int32_t y = y0; y < y1; ++y)
      for (int32_t x = x0; x < x1; ++x) {
        uint8_t& f = box.bits[box.index(x, y, z)];
        if (!(f & (kOriginal | kPrepared))) continue;
        const uint8_t inner = box.faceNeighboursAnd(x, y, z);
        const bool orig_surface = (f & kOriginal) && !(inner & kOriginal);
        const bool prep_surface = (f & kPrepared) && !(inner & kPrepared);
        if (!orig_surface && !prep_surface) continue;
        const Vec3 p(x + 0.5, y + 0.5, z + 0.5);
        double radius = 0;
        const int s = sectorOf(p, &radius);
        const size_t cell = size_t(s) * bins + binOf(dot(p, a));
        if (orig_surface) {
          r_orig[cell] = std::max(r_orig[cell], radius);
          if (f & kEnamel) cej[size_t(s)] = std::min(cej[size_t(s)], dot(p, a));
        }
        if (!prep_surface) continue;
        r_prep[cell] = std::max(r_prep[cell], radius);
        bool cut = false, wall = false;
        for (const auto& o : kFace) {
          const uint8_t g = box.at(x + o[0], y + o[1], z + o[2]);
          if (g & kPrepared) continue;
          if (g & kOriginal) cut = true;
          else if (dot(Vec3(o[0], o[1], o[2]), a) > -0.5) wall = true;
        }
        f |= cut ? kCut : (wall ? kWall : 0);
      }

  // 3. Cut voxels with uncut wall below them, and each sector's lowest.
  std::array<double, kMarginSectors> line;
  line.fill(std::numeric_limits<double>::infinity());
  std::array<size_t, kMarginSectors> line_bin{};
  std::vector<LineVoxel> on_line;
  for (int32_t z = z0; z < z1; ++z)
    for (int32_t y = y0; y < y1; ++y)
      for (int32_t x = x0; x < x1; ++x) {
        if (!(box.bits[box.index(x, y, z)] & kCut)) continue;
        const Vec3 p(x + 0.5, y + 0.5, z + 0.5);
        const double h = dot(p, a);
        bool margin = false;
        for (int dz = -1; dz <= 1 && !margin; ++dz)
          for (int dy = -1; dy <= 1 && !margin; ++dy)
            for (int dx = -1; dx <= 1 && !margin; ++dx)
              margin = (box.at(x + dx, y + dy, z + dz) & kWall) && dot(Vec3(dx, dy, dz), a) < -1e-9;
        if (!margin) continue;
        double face = std::numeric_limits<double>::infinity();
        for (const auto& o : kFace) {
          const uint8_t g = box.at(x + o[0], y + o[1], z + o[2]);
          if ((g & kOriginal) && !(g & kPrepared)) face = std::min(face, h + 0.5 * dot(Vec3(o[0], o[1], o[2]), a));
        }
        double radius = 0;
        const int s = sectorOf(p, &radius);
        on_line.push_back({s, face, reductionVoxelKey(uint32_t(x), uint32_t(y), uint32_t(z))});
        if (face < line[size_t(s)]) line[size_t(s)] = face, line_bin[size_t(s)] = binOf(h);
      }

  // 4. Per sector: height, width, CEJ.
  MarginLine out;
  for (int s = 0; s < kMarginSectors; ++s) {
    MarginSector& sec = out.sectors[size_t(s)];
    if (std::isfinite(cej[size_t(s)])) sec.cej_height_mm = cej[size_t(s)] * voxel_mm;
    if (!std::isfinite(line[size_t(s)])) continue;
    sec.found = true;
    sec.height_mm = line[size_t(s)] * voxel_mm;
    const double* orig = &r_orig[size_t(s) * bins];
    const double* prep = &r_prep[size_t(s) * bins];
    const size_t lb = line_bin[size_t(s)];
    double outer = orig[lb];
    if (outer == kNone) {  // the line's layer holds no original surface in the wedge: take the nearest below
      for (size_t i = lb; i-- > 0 && outer == kNone;) outer = orig[i];
    }
    std::vector<double> hs, rs;
    double deepest = 0;
    for (size_t i = lb + 1; i < bins; ++i) {
      const double above = (h_min + double(i) - line[size_t(s)]) * voxel_mm;
      if (above > kWallFitHiMm) break;
      if (prep[i] == kNone) continue;
      deepest = std::max(deepest, outer - prep[i]);
      if (above >= kWallFitLoMm) hs.push_back(h_min + double(i)), rs.push_back(prep[i]);
    }
    const double width = int(hs.size()) >= kMinWallBins ? outer - fitAt(hs, rs, line[size_t(s)]) : deepest;
    // Both radii would add half a voxel for their outer faces: the difference needs neither.
    sec.width_mm = outer == kNone ? 0 : width * voxel_mm;
  }

  // 5. Around the line: counts, widths, heights, gaps, roughness, CEJ.
  double width_sum = 0, height_sum = 0, cej_sum = 0;
  int cej_count = 0;
  out.min_width_mm = std::numeric_limits<double>::infinity();
  out.lowest_height_mm = std::numeric_limits<double>::infinity();
  for (const MarginSector& sec : out.sectors) {
    if (!sec.found) continue;
    ++out.found_sectors;
    width_sum += sec.width_mm;
    height_sum += sec.height_mm;
    out.min_width_mm = std::min(out.min_width_mm, sec.width_mm);
    out.lowest_height_mm = std::min(out.lowest_height_mm, sec.height_mm);
    if (sec.cej_height_mm) cej_sum += sec.height_mm - *sec.cej_height_mm, ++cej_count;
  }
  out.gap_share = double(kMarginSectors - out.found_sectors) / kMarginSectors;
  if (out.found_sectors == 0) {
    out.min_width_mm = 0;
    out.lowest_height_mm = 0;
    out.gaps = 1;
    return out;
  }
  out.mean_width_mm = width_sum / out.found_sectors;
  out.mean_height_mm = height_sum / out.found_sectors;
  if (cej_count > 0) out.mean_above_cej_mm = cej_sum / cej_count;
  auto found = [&](int s) { return out.sectors[size_t((s + kMarginSectors) % kMarginSectors)].found; };
  auto height = [&](int s) { return out.sectors[size_t((s + kMarginSectors) % kMarginSectors)].height_mm; };
  double rough_sum = 0;
  int rough_count = 0;
  for (int s = 0; s < kMarginSectors; ++s) {
    if (!found(s) && found(s - 1)) ++out.gaps;  // a gap starts here
    if (found(s) && found(s - 1) && found(s + 1)) {
      const double e = height(s) - 0.5 * (height(s - 1) + height(s + 1));
      rough_sum += e * e, ++rough_count;
    }
  }
  if (rough_count > 0) out.roughness_mm = std::sqrt(rough_sum / rough_count);

  // 6. The line's voxels: each sector's within a voxel of its height.
  for (const LineVoxel& v : on_line)
    if (v.height <= line[size_t(v.sector)] + 1.0) out.line_voxels.push_back(v.key);
  std::sort(out.line_voxels.begin(), out.line_voxels.end());
  out.line_voxels.erase(std::unique(out.line_voxels.begin(), out.line_voxels.end()), out.line_voxels.end());
  return out;
}

}  // namespace dentsim
