// Enamel, dentin and pulp for a tooth known only by its shape: axis, roots and CEJ from cross-sections, layers by published proportions.
//
// Contents
//   1. Tooth types and their published proportions (the sources cited above the table)
//   2. The tooth as a dense local grid, its depth and its smoothed shape
//   3. The crown axis: the principal axis, then the wide end
//   4. Slices along the axis: areas, root pieces, each root's apex
//   5. Heights: furcation, height of contour, CEJ; roots, type, mesial
//   6. The layers: enamel cap, pulp chamber and canals, dentin
//   7. synthesizeLayers
// The known answer's comparison is in tooth_layer_compare.cpp.
#include "volume/tooth_layer_synth.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <deque>
#include <limits>

#include "core/text_format.h"
#include "volume/distance_transform.h"
#include "volume/tissue_table.h"
#include "volume/tooth_frame.h"
#include "volume/voxel_grid_ops.h"

namespace dentsim {

// ---- 1. tooth types -----------------------------------------------------------------------------
namespace {

// What the layers are made of, per type. The dental anatomy behind the numbers:
//  [TC]  Nanci A. Ten Cate's Oral Histology, 8th ed., 2013, ch. 7: enamel reaches about 2.5 mm over
//        the cusps and thins to a knife edge at the cemento-enamel junction.
//  [SG]  Shillingburg HT, Grace CS. Thickness of enamel and dentin. J South Calif Dent Assoc
//        1973;41:33-52: enamel of the axial walls about 1-1.5 mm at the height of contour of posterior
//        teeth, 0.3-0.5 mm near the CEJ, thicker occlusally; incisors about 1 mm labially.
//  [GR]  Grine FE. Enamel thickness of deciduous and permanent molars in modern Homo sapiens. Am J
//        Phys Anthropol 2005;126:14-31, and Macho GA, Berner ME. Enamel thickness of human maxillary
//        molars reconsidered. Am J Phys Anthropol 1993;92:189-200: average enamel thickness of human
//        permanent molars about 1.1-1.3 mm, cuspal enamel about 1.5-2.5 mm, thinnest in the fissures.
//  [WH]  Nelson SJ, Ash MM. Wheeler's Dental Anatomy, Physiology and Occlusion, 9th ed., 2010, the
//        tables of measurements: crown/root lengths (maxillary central incisor 10.5/13 mm, canine
//        10/17, first premolar 8.5/14, first molars 7.5/12-14) and crown widths (molars 10-11 mm,
//        premolars 7 mm, canines 7-8 mm, incisors 5-8.5 mm mesiodistally).
//  [KR]  Krasner P, Rankow HJ. Anatomy of the pulp-chamber floor. J Endod 2004;30:5-16: the floor of
//        the pulp chamber lies at the level of the CEJ, in the tooth's centre (law of centrality), its
//        walls concentric to the outer surface at the CEJ (law of concentricity).
//  [DM]  Deutsch AS, Musikant BL. Morphological measurements of anatomic landmarks in human maxillary
//        and mandibular molar pulp chambers. J Endod 2004;30:388-390: molar pulp chambers about 1.5-2
//        mm high, their roof near the CEJ's level, about 6 mm below the cusp tips.
//  [KU]  Kuttler Y. Microscopic investigation of root apexes. J Am Dent Assoc 1955;50:544-552: the
//        canal ends at the apical constriction, about 0.5-1 mm short of the apex; here 1 mm.
// [KR] puts the chamber's floor at the CEJ's level and [DM] its roof near it; they differ by the
// chamber's height. Both micro-CT molars' chambers lie just below their CEJ, so the roof is put at
// the CEJ's level. The values are as read from these works; docs/LAYER_SYNTHESIS.md lists them.
struct TypeProportions {
  ToothType type;
  const char* name;
  double enamel_full_mm;     // at the cusp tips, under the smoothed shape; less down to the CEJ [TC][SG][GR] [mm]
  double enamel_fissure_mm;  // at least this much in the fissures, where the smoothed shape thins it [GR] [mm]
  double crown_fraction;     // crown length / tooth length, for a tooth whose waist does not show [WH]
  double chamber_height_mm;  // the pulp chamber, down from its roof at the CEJ's level [DM][KR] [mm]
};

constexpr TypeProportions kTypes[] = {
    {ToothType::Molar, "molar", 1.7, 0.6, 0.36, 2.0},
    {ToothType::Premolar, "premolar", 1.5, 0.6, 0.38, 1.5},
    {ToothType::Canine, "canine", 1.4, 0.6, 0.37, 1.5},
    {ToothType::Incisor, "incisor", 1.1, 0.5, 0.45, 1.2},
};

const TypeProportions& proportions(ToothType type) {
  for (const TypeProportions& p : kTypes)
    if (p.type == type) return p;
  return kTypes[0];  // Unknown never reaches the layers; a molar is the safe default
}

// Method constants, the same for every tooth (tuned once on the micro-CT molars, docs/LAYER_SYNTHESIS.md).
constexpr double kSmoothMm = 0.6;          // box radius of the smoothing that thickens cusps and thins fissures [mm]
constexpr double kTaperFraction = 1.0;     // the enamel grows from a knife edge at the CEJ to full over this share of the crown
constexpr double kChamberFraction = 0.35;  // the chamber's radius / its slice piece's inscribed radius [KR]
constexpr double kCanalFraction = 0.17;    // a canal's radius / its root's inscribed radius
constexpr double kApexGapMm = 1.0;         // canals end this short of each root's apex [KU] [mm]
constexpr int kMinLengthVoxels = 16;       // shorter teeth cannot hold three layers and a canal

}  // namespace

const char* toothTypeName(ToothType type) {
  for (const TypeProportions& p : kTypes)
    if (p.type == type) return p.name;
  return "unknown";
}

std::optional<ToothType> parseToothType(const std::string& name) {
  for (const TypeProportions& p : kTypes)
    if (name == p.name) return p.type;
  return std::nullopt;
}

std::string toothTypeNames() { return "molar, premolar, canine or incisor"; }

namespace {
// ---- 2. the local grid --------------------------------------------------------------------------
// The tooth's bounding box with a margin, one byte a voxel, i fastest. Voxels beyond the volume's
// grid are empty.
struct LocalGrid {
  std::array<int64_t, 3> origin{};  // grid voxel of local (0,0,0)
  std::array<int32_t, 3> dims{};
  std::vector<uint8_t> inside;      // 1: tooth tissue
  std::vector<uint8_t> fill;        // the voxel's fill (0..31)
  std::vector<uint32_t> tooth;      // local indices of the tooth voxels, in index order
  size_t size() const { return inside.size(); }
  Vec3 centre(uint64_t l) const {   // grid voxel centre [voxels]
    const auto c = voxelCoords(l, dims);
    return {double(origin[0] + c[0]) + 0.5, double(origin[1] + c[1]) + 0.5, double(origin[2] + c[2]) + 0.5};
  }
};

constexpr int kMargin = 2;

LocalGrid gatherTooth(const BrickVolume& volume, const VoxelBox& box) {
  LocalGrid g;
  for (int a = 0; a < 3; ++a) {
    g.origin[size_t(a)] = box.lo[size_t(a)] - kMargin;
    g.dims[size_t(a)] = int32_t(box.hi[size_t(a)] - box.lo[size_t(a)] + 1 + 2 * kMargin);
  }
  const size_t n = size_t(g.dims[0]) * size_t(g.dims[1]) * size_t(g.dims[2]);
  g.inside.assign(n, 0);
  g.fill.assign(n, 0);
  volume.forEachBrick([&](const BrickView& b) {
    const int64_t bx = int64_t(b.coord.x) * DS_BRICK_DIM, by = int64_t(b.coord.y) * DS_BRICK_DIM,
                  bz = int64_t(b.coord.z) * DS_BRICK_DIM;
    if (bx + DS_BRICK_DIM <= box.lo[0] || bx > box.hi[0] || by + DS_BRICK_DIM <= box.lo[1] || by > box.hi[1] ||
        bz + DS_BRICK_DIM <= box.lo[2] || bz > box.hi[2])
      return;
    if (b.uniform && !isToothTissue(voxelMaterial(b.value))) return;
    for (uint32_t o = 0; o < DS_BRICK_VOXELS; ++o) {
      const Voxel v = b.at(o);
      if (!isToothTissue(voxelMaterial(v)) || voxelFill(v) == 0) continue;
      const std::array<int64_t, 3> c{bx + (o & 7u) - g.origin[0], by + ((o >> 3) & 7u) - g.origin[1],
                                     bz + (o >> 6) - g.origin[2]};
      const uint64_t l = voxelIndex(c, g.dims);
      g.inside[l] = 1;
      g.fill[l] = uint8_t(voxelFill(v));
    }
  });
  for (uint64_t l = 0; l < n; ++l)
    if (g.inside[l]) g.tooth.push_back(uint32_t(l));
  return g;
}

// Per voxel, the distance from its centre to the nearest voxel outside `mask` [mm].
std::vector<float> depthMm(const std::vector<uint8_t>& mask, const std::array<int32_t, 3>& dims, double voxel_mm) {
  std::vector<float> d = squaredDistanceToOutside(mask, dims, {voxel_mm, voxel_mm, voxel_mm});
  for (float& x : d) x = std::sqrt(x);
  return d;
}

// The tooth blurred by a box of radius r twice (a tent of radius 2r) and cut at half: convex
// parts (cusps) shrink and concave ones (fissures) fill, so that a layer of one depth under this
// shape is thicker over the cusps and thinner in the fissures, as real enamel is [GR].
std::vector<uint8_t> smoothedShape(const LocalGrid& g, int r) {
  std::vector<float> a(g.size()), b(g.size());
  for (size_t l = 0; l < g.size(); ++l) a[l] = g.inside[l];
  const std::array<int64_t, 3> stride{1, g.dims[0], int64_t(g.dims[0]) * g.dims[1]};
  std::vector<float> line;
  for (int pass = 0; pass < 2; ++pass)
    for (int axis = 0; axis < 3; ++axis) {
      // Each line along `axis` once, from its first voxel: the other two axes span the starts.
      const int64_t n = g.dims[size_t(axis)], s = stride[size_t(axis)];
      const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
      line.resize(size_t(n));
      for (int64_t cv = 0; cv < g.dims[size_t(v)]; ++cv)
        for (int64_t cu = 0; cu < g.dims[size_t(u)]; ++cu) {
          const int64_t start = cu * stride[size_t(u)] + cv * stride[size_t(v)];
          for (int64_t i = 0; i < n; ++i) line[size_t(i)] = a[size_t(start + i * s)];
          double sum = 0;
          for (int64_t i = 0; i < std::min<int64_t>(r, n); ++i) sum += line[size_t(i)];
          for (int64_t i = 0; i < n; ++i) {
            if (i + r < n) sum += line[size_t(i + r)];
            if (i - r - 1 >= 0) sum -= line[size_t(i - r - 1)];
            b[size_t(start + i * s)] = float(sum / double(2 * r + 1));
          }
        }
      std::swap(a, b);
    }
  std::vector<uint8_t> out(g.size());
  for (size_t l = 0; l < g.size(); ++l) out[l] = a[l] >= 0.5f ? 1 : 0;
  return out;
}

// ---- 3. the crown axis --------------------------------------------------------------------------
// The eigenvector of the largest eigenvalue of a symmetric 3x3 matrix (cyclic Jacobi).
Vec3 principalAxis(std::array<std::array<double, 3>, 3> m) {
  std::array<std::array<double, 3>, 3> v{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
    if (off < 1e-18 * (m[0][0] * m[0][0] + m[1][1] * m[1][1] + m[2][2] * m[2][2]) + 1e-300) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (std::abs(m[size_t(p)][size_t(q)]) < 1e-300) continue;
        const double theta = (m[size_t(q)][size_t(q)] - m[size_t(p)][size_t(p)]) / (2 * m[size_t(p)][size_t(q)]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (size_t k = 0; k < 3; ++k) {  // m <- m * J
          const double mkp = m[k][size_t(p)], mkq = m[k][size_t(q)];
          m[k][size_t(p)] = c * mkp - s * mkq;
          m[k][size_t(q)] = s * mkp + c * mkq;
        }
        for (size_t k = 0; k < 3; ++k) {  // m <- J^T * m
          const double mpk = m[size_t(p)][k], mqk = m[size_t(q)][k];
          m[size_t(p)][k] = c * mpk - s * mqk;
          m[size_t(q)][k] = s * mpk + c * mqk;
        }
        for (size_t k = 0; k < 3; ++k) {  // v <- v * J
          const double vkp = v[k][size_t(p)], vkq = v[k][size_t(q)];
          v[k][size_t(p)] = c * vkp - s * vkq;
          v[k][size_t(q)] = s * vkp + c * vkq;
        }
      }
  }
  size_t best = 0;
  for (size_t k = 1; k < 3; ++k)
    if (m[k][k] > m[best][best]) best = k;
  return normalized(Vec3{v[0][best], v[1][best], v[2][best]});
}

// The tooth's long axis, signed toward the wide end: the crown is bulky and the roots taper, so
// the outer third of the tooth at the crown end holds more of it than the third at the root end.
Vec3 crownFromShape(const LocalGrid& g) {
  Vec3 mean{};
  for (uint32_t l : g.tooth) mean += g.centre(l);
  mean = mean / double(g.tooth.size());
  std::array<std::array<double, 3>, 3> cov{};
  for (uint32_t l : g.tooth) {
    const Vec3 d = g.centre(l) - mean;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cov[size_t(i)][size_t(j)] += d[i] * d[j];
  }
  Vec3 axis = principalAxis(cov);
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  for (uint32_t l : g.tooth) {
    const double t = dot(g.centre(l), axis);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  const double third = (hi - lo) / 3.0;
  uint64_t low_end = 0, high_end = 0;
  for (uint32_t l : g.tooth) {
    const double t = dot(g.centre(l), axis);
    low_end += t < lo + third;
    high_end += t > hi - third;
  }
  return high_end >= low_end ? axis : -axis;
}

// ---- 4. slices along the axis -------------------------------------------------------------------
// One connected piece of one slice: a root, the root trunk, the crown, or a cusp near the top.
struct SlicePiece {
  int bin = 0;            // the slice, 1 voxel thick, counted from the apex
  uint32_t voxels = 0;    // voxels of this bin in the piece
  float max_depth = 0;    // the piece's inscribed radius [mm]
  int apex_bin = 0;       // the lowest bin of the root this piece continues
  Vec3 sum{};             // sum of voxel centres, for the centroid
};

struct Slices {
  double t0 = 0;                       // dot(centre, crown) of the apex [voxels]
  int bins = 0;                        // slices from apex to crown tip
  std::vector<int32_t> bin_of;         // per tooth voxel (index into LocalGrid::tooth)
  std::vector<int32_t> piece_of;       // per tooth voxel: its SlicePiece
  std::vector<SlicePiece> pieces;
  std::vector<std::vector<int32_t>> bin_pieces;  // per bin, its pieces
  std::vector<uint32_t> area;          // per bin, voxels
};

// Cuts the tooth into slices one voxel thick across `crown`. A piece is 6-connected within a slab
// two voxels thick around its slice (an oblique digital plane one voxel thick need not be
// connected), and follows the pieces of the slice below it for its root's apex.
Slices sliceTooth(const LocalGrid& g, const Vec3& crown, const std::vector<float>& depth) {
  Slices s;
  const size_t n = g.tooth.size();
  std::vector<double> t(n);
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  for (size_t k = 0; k < n; ++k) {
    t[k] = dot(g.centre(g.tooth[k]), crown);
    lo = std::min(lo, t[k]);
    hi = std::max(hi, t[k]);
  }
  s.t0 = lo;
  s.bins = int(std::floor(hi - lo)) + 1;
  s.bin_of.resize(n);
  s.piece_of.assign(n, -1);
  s.area.assign(size_t(s.bins), 0);
  s.bin_pieces.resize(size_t(s.bins));
  std::vector<std::vector<uint32_t>> members(size_t(s.bins));
  for (size_t k = 0; k < n; ++k) {
    s.bin_of[k] = std::min(s.bins - 1, int(std::floor(t[k] - lo)));
    ++s.area[size_t(s.bin_of[k])];
    members[size_t(s.bin_of[k])].push_back(uint32_t(k));
  }
  // slot: the tooth-voxel number of a local voxel, or -1.
  std::vector<int32_t> slot(g.size(), -1);
  for (size_t k = 0; k < n; ++k) slot[g.tooth[k]] = int32_t(k);
  std::vector<int32_t> in_slab(n, -1), seen(n, -1);
  const int64_t sy = g.dims[0], sz = int64_t(g.dims[0]) * g.dims[1];
  const int64_t steps[6] = {-1, 1, -sy, sy, -sz, sz};
  std::deque<uint32_t> queue;
  for (int b = 0; b < s.bins; ++b) {
    for (int nb = std::max(0, b - 1); nb <= std::min(s.bins - 1, b + 1); ++nb)
      for (uint32_t k : members[size_t(nb)])
        if (t[k] >= lo + b - 0.5 && t[k] < lo + b + 1.5) in_slab[k] = b;
    for (uint32_t k0 : members[size_t(b)]) {
      if (seen[k0] == b) continue;
      const int32_t id = int32_t(s.pieces.size());
      SlicePiece piece;
      piece.bin = b;
      piece.apex_bin = b;
      seen[k0] = b;
      queue.push_back(k0);
      while (!queue.empty()) {
        const uint32_t k = queue.front();
        queue.pop_front();
        if (s.bin_of[k] == b) {
          s.piece_of[k] = id;
          ++piece.voxels;
          piece.max_depth = std::max(piece.max_depth, depth[g.tooth[k]]);
          piece.sum += g.centre(g.tooth[k]);
        }
        // The margin keeps every tooth voxel's face neighbours inside the local grid.
        for (const int64_t step : steps) {
          const int32_t j = slot[size_t(int64_t(g.tooth[k]) + step)];
          if (j < 0) continue;
          // The slice below: this piece continues that root, down to its apex.
          if (s.bin_of[size_t(j)] == b - 1 && s.bin_of[k] == b && s.piece_of[size_t(j)] >= 0)
            piece.apex_bin = std::min(piece.apex_bin, s.pieces[size_t(s.piece_of[size_t(j)])].apex_bin);
          if (in_slab[size_t(j)] != b || seen[size_t(j)] == b) continue;
          seen[size_t(j)] = b;
          queue.push_back(uint32_t(j));
        }
      }
      if (piece.voxels == 0) continue;  // only slab voxels of the neighbours: no piece of this bin
      s.pieces.push_back(piece);
      s.bin_pieces[size_t(b)].push_back(id);
    }
  }
  return s;
}

// ---- 5. heights, roots, type, mesial ------------------------------------------------------------
struct ToothHeights {
  int furcation_bin = 0;  // highest slice where the roots are apart; 0: one root
  int widest_bin = 0;     // the crown's height of contour
  int cej_bin = 0;        // the CEJ: the cervical waist, or the knee where the crown bulges out
  int roots = 1;
};

// Pieces large enough to be a root, not a speck of the surface: at least (0.3 mm)^2 and 4 voxels.
int significantPieces(const Slices& s, int bin, double voxel_mm) {
  const double min_voxels = std::max(4.0, 0.09 / (voxel_mm * voxel_mm));
  int count = 0;
  for (int32_t id : s.bin_pieces[size_t(bin)]) count += double(s.pieces[size_t(id)].voxels) >= min_voxels;
  return count;
}

ToothHeights findHeights(const Slices& s, double voxel_mm, ToothType known_type) {
  ToothHeights h;
  const int n = s.bins;
  // The furcation: the highest slice of the lower 65 % with two pieces or more (the cusps part
  // the slices near the crown's top too, above that).
  const int lower = int(0.65 * n);
  std::vector<int> count(static_cast<size_t>(n));
  for (int b = 0; b < n; ++b) count[size_t(b)] = significantPieces(s, b, voxel_mm);
  for (int b = lower; b >= 0; --b)
    if (count[size_t(b)] >= 2) {
      h.furcation_bin = b;
      break;
    }
  // Roots: the most pieces that the slices below the furcation hold over at least 1.5 mm.
  const int span = std::max(2, int(std::lround(1.5 / voxel_mm)));
  for (int k = 2; k <= 5 && h.furcation_bin > 0; ++k) {
    int bins_with = 0;
    for (int b = 0; b <= h.furcation_bin; ++b) bins_with += count[size_t(b)] >= k;
    if (bins_with >= span) h.roots = k;
  }
  if (h.roots == 1) h.furcation_bin = 0;
  // Height of contour: the widest slice above the furcation and the tooth's lower 40 %.
  const int from = std::max(h.furcation_bin + 1, int(0.4 * n));
  h.widest_bin = from;
  for (int b = from; b < n; ++b)
    if (s.area[size_t(b)] > s.area[size_t(h.widest_bin)]) h.widest_bin = b;
  // The CEJ: the cervical waist, a narrowest slice between the roots and the height of contour
  // that is narrower than a slice below it as well (a true waist, at least 3 % narrower on both
  // sides).
  const int waist_from = h.furcation_bin > 0 ? h.furcation_bin + 1 : int(0.3 * n);
  int cej = -1;
  uint32_t best = std::numeric_limits<uint32_t>::max();
  for (int b = waist_from; b <= h.widest_bin; ++b) {
    uint32_t below = 0;
    for (int c = waist_from; c < b; ++c) below = std::max(below, s.area[size_t(c)]);
    const double a = s.area[size_t(b)];
    if (a < 0.97 * below && a < 0.97 * s.area[size_t(h.widest_bin)] && s.area[size_t(b)] < best) {
      best = s.area[size_t(b)];
      cej = b;
    }
  }
  // Many molars show no waist in the area: from the furcation up the root trunk widens into the
  // crown (both micro-CT molars do). Their constriction is a knee: the trunk's outline flares
  // less and less, and at the CEJ the crown's bulge sets in. The knee is the most positive second
  // difference of the slices' equivalent radius over 1 mm steps. The trunk has bends of its own
  // (the furcation's), so the knee is sought within 1.5 mm of where the type's crown/root ratio
  // puts the CEJ [WH], and that ratio decides alone when no knee shows.
  const int one_mm = std::max(1, int(std::lround(1.0 / voxel_mm)));
  const ToothType ratio_type = known_type == ToothType::Unknown ? ToothType::Molar : known_type;
  const int by_ratio = std::clamp(int(std::lround((1.0 - proportions(ratio_type).crown_fraction) * (n - 1))),
                                  std::min(waist_from, h.widest_bin), h.widest_bin);
  if (cej < 0) {
    const auto radius = [&](int b) { return std::sqrt(double(s.area[size_t(std::clamp(b, 0, n - 1))]) / M_PI); };
    const int reach = int(std::lround(1.5 / voxel_mm));
    double sharpest = 0;
    for (int b = std::max(waist_from + one_mm, by_ratio - reach); b <= std::min(h.widest_bin - one_mm, by_ratio + reach);
         ++b) {
      const double bend = radius(b + one_mm) - 2 * radius(b) + radius(b - one_mm);
      if (bend > sharpest) {
        sharpest = bend;
        cej = b;
      }
    }
  }
  if (cej < 0) cej = by_ratio;
  h.cej_bin = std::min(cej, h.widest_bin);
  return h;
}

// The type from size and roots: three roots, or two under a crown 9 mm wide or more, make a molar;
// two under a narrower crown a premolar; one root: a canine when the tooth is long, an incisor when
// its crown ends in an edge, else a premolar [WH].
ToothType guessType(const Slices& s, const ToothHeights& h, double voxel_mm) {
  const double widest_mm = 2.0 * std::sqrt(double(s.area[size_t(h.widest_bin)]) / M_PI) * voxel_mm;
  const double length_mm = double(s.bins) * voxel_mm;
  if (h.roots >= 3 || (h.roots == 2 && widest_mm >= 8.0)) return ToothType::Molar;
  if (h.roots == 2) return ToothType::Premolar;
  if (widest_mm >= 9.0) return ToothType::Molar;  // fused roots
  if (length_mm >= 24.0) return ToothType::Canine;
  // An incisal edge: near the top the slices are a small part of the widest.
  const int near_top = h.widest_bin + int(0.7 * (s.bins - 1 - h.widest_bin));
  if (double(s.area[size_t(near_top)]) < 0.35 * double(s.area[size_t(h.widest_bin)])) return ToothType::Incisor;
  return ToothType::Premolar;
}

// The mesiodistal line. Two roots stand mesial and distal (mandibular molars, and the buccal pair
// of a maxillary molar's three), so the line through the two largest root pieces is mesiodistal.
// With one root the crown's cross-section says it for premolars and canines, whose crowns are
// wider buccolingually than mesiodistally [WH]: the minor axis. Incisors and molars with one root
// differ by arch, which the shape does not tell. The sign needs the arch and side: never known.
std::optional<Vec3> mesiodistalLine(const LocalGrid& g, const Slices& s, const ToothHeights& h, const Vec3& crown,
                               ToothType type) {
  auto inPlane = [&](Vec3 v) -> std::optional<Vec3> {
    v = v - crown * dot(v, crown);
    if (norm(v) < 1e-9) return std::nullopt;
    v = normalized(v);
    // A fixed sign so that the same shape gives the same answer: the largest component positive.
    const int a = std::abs(v.x) >= std::abs(v.y) && std::abs(v.x) >= std::abs(v.z) ? 0 : (std::abs(v.y) >= std::abs(v.z) ? 1 : 2);
    return v[a] < 0 ? -v : v;
  };
  if (h.roots >= 2) {
    const int b = std::max(0, h.furcation_bin - int(0.2 * h.furcation_bin));
    std::vector<int32_t> ids = s.bin_pieces[size_t(b)];
    if (ids.size() >= 2) {
      std::sort(ids.begin(), ids.end(), [&](int32_t x, int32_t y) { return s.pieces[size_t(x)].voxels > s.pieces[size_t(y)].voxels; });
      const SlicePiece& p = s.pieces[size_t(ids[0])];
      const SlicePiece& q = s.pieces[size_t(ids[1])];
      return inPlane(p.sum / double(p.voxels) - q.sum / double(q.voxels));
    }
  }
  if (type != ToothType::Premolar && type != ToothType::Canine) return std::nullopt;
  // The minor axis of the widest slice's second moments, in the plane across the crown.
  const Vec3 helper = std::abs(crown.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalized(cross(crown, helper)), e2 = cross(crown, e1);
  double sxx = 0, sxy = 0, syy = 0, mx = 0, my = 0, cnt = 0;
  for (size_t k = 0; k < g.tooth.size(); ++k) {
    if (s.bin_of[k] != h.widest_bin) continue;
    const Vec3 p = g.centre(g.tooth[k]);
    const double x = dot(p, e1), y = dot(p, e2);
    mx += x, my += y, sxx += x * x, sxy += x * y, syy += y * y, cnt += 1;
  }
  if (cnt < 3) return std::nullopt;
  mx /= cnt, my /= cnt;
  sxx = sxx / cnt - mx * mx, sxy = sxy / cnt - mx * my, syy = syy / cnt - my * my;
  const double major = 0.5 * std::atan2(2 * sxy, sxx - syy);  // angle of the major axis
  return inPlane(e1 * std::cos(major + M_PI / 2) + e2 * std::sin(major + M_PI / 2));
}

// ---- 6. the layers ------------------------------------------------------------------------------
// The enamel's thickness at a height above the CEJ: a knife edge at the CEJ growing smoothly to the
// type's full thickness over the cervical part of the crown [TC][SG] [mm].
double enamelThickness(double above_cej_mm, double crown_mm, const TypeProportions& p) {
  if (above_cej_mm <= 0) return 0;
  const double u = std::min(1.0, above_cej_mm / std::max(1e-9, kTaperFraction * crown_mm));
  return p.enamel_full_mm * u * (2.0 - u);  // steep off the CEJ, flat at the cusp tips  // rises steeply off the CEJ, flat at the top
}

}  // namespace

// ---- 7. synthesizeLayers ------------------------------------------------------------------------
Result<LayerSynthReport> synthesizeLayers(BrickVolume& volume, double voxel_mm, const LayerSynthOptions& options,
                                          Interrupter* progress) {
  assert(voxel_mm > 0);
  Interrupter& ui = progress ? *progress : nullInterrupter();
  const Error cancelled{"layer synthesis cancelled"};
  ui.start("synthesizing layers");
  const VoxelBox box = tissueVoxelBoxes(volume)[0];
  if (box.empty()) return Error{"layer synthesis: the volume holds no tooth voxels"};
  LocalGrid g = gatherTooth(volume, box);
  if (g.tooth.empty()) return Error{"layer synthesis: the volume holds no tooth voxels"};
  if (!ui.progress(0.1)) return cancelled;

  // 1. the crown axis, and the tooth's depth
  LayerSynthReport r;
  // A given axis that is zero or not finite tells nothing: the shape's is found instead.
  if (options.crown && norm(*options.crown) > 0 && finite(*options.crown)) {
    r.crown = normalized(*options.crown);
  } else {
    r.crown = crownFromShape(g);
    r.crown_found = true;
  }
  const std::vector<float> depth = depthMm(g.inside, g.dims, voxel_mm);
  if (!ui.progress(0.25)) return cancelled;

  // 2. slices, heights, roots and type
  const Slices s = sliceTooth(g, r.crown, depth);
  if (s.bins < kMinLengthVoxels)
    return Error{formatted("layer synthesis: the tooth is too small for layers at this voxel size: %d voxels long at %.3f mm, "
                     "at least %d needed",
                     s.bins, voxel_mm, kMinLengthVoxels)};
  ToothHeights h = findHeights(s, voxel_mm, options.type);
  r.type = options.type;
  if (r.type == ToothType::Unknown) {
    r.type = guessType(s, h, voxel_mm);
    r.type_guessed = true;
    h = findHeights(s, voxel_mm, r.type);  // the crown/root ratio fallback reads the type
  }
  const TypeProportions& prop = proportions(r.type);
  if (prop.enamel_fissure_mm < voxel_mm)
    return Error{formatted("layer synthesis: a %.3f mm voxel is coarser than the thinnest enamel (%.1f mm); use a finer grid",
                     voxel_mm, prop.enamel_fissure_mm)};
  r.roots = h.roots;
  r.tooth_length_mm = s.bins * voxel_mm;
  r.cej_mm = (h.cej_bin + 0.5) * voxel_mm;
  r.furcation_mm = h.furcation_bin > 0 ? (h.furcation_bin + 0.5) * voxel_mm : 0.0;
  r.mesiodistal = mesiodistalLine(g, s, h, r.crown, r.type);
  if (!ui.progress(0.45)) return cancelled;

  // 3. the enamel cap: under the smoothed shape, so thicker over cusps and thinner in fissures
  const int smooth_r = std::max(1, int(std::lround(kSmoothMm / voxel_mm)));
  const std::vector<float> smooth_depth = depthMm(smoothedShape(g, smooth_r), g.dims, voxel_mm);
  if (!ui.progress(0.75)) return cancelled;
  const double crown_mm = r.tooth_length_mm - r.cej_mm;
  std::vector<Material> made(g.tooth.size(), Material::Dentin);
  for (size_t k = 0; k < g.tooth.size(); ++k) {
    const uint32_t l = g.tooth[k];
    const double above = (s.bin_of[k] - h.cej_bin) * voxel_mm;
    const double full = enamelThickness(above, crown_mm, prop);
    const double fissure = std::min(full, prop.enamel_fissure_mm);
    if (smooth_depth[l] < full || depth[l] < fissure) made[k] = Material::Enamel;
  }

  // 4. the pulp: the chamber from its roof at the CEJ's level down the type's chamber height [DM],
  //    centred and concentric to the outer surface [KR]; below it a canal along each root piece's
  //    middle to 1 mm short of its apex [KU]. Two voxels of dentin at least keep it enclosed.
  const int chamber_floor = h.cej_bin - int(std::lround(prop.chamber_height_mm / voxel_mm));
  const int apex_gap = int(std::lround(kApexGapMm / voxel_mm));
  const float wall_mm = float(2.0 * voxel_mm);
  for (size_t k = 0; k < g.tooth.size(); ++k) {
    if (made[k] != Material::Dentin || s.piece_of[k] < 0) continue;
    const SlicePiece& p = s.pieces[size_t(s.piece_of[k])];
    const int b = s.bin_of[k];
    const float d = depth[g.tooth[k]];
    if (b > h.cej_bin || d < wall_mm) continue;
    if (b < chamber_floor && b - p.apex_bin < apex_gap) continue;
    const double fraction = b >= chamber_floor ? kChamberFraction : kCanalFraction;
    if (d >= (1.0 - fraction) * p.max_depth) made[k] = Material::Pulp;
  }
  if (!ui.progress(0.9)) return cancelled;

  // 5. written back, each voxel keeping its fill
  double fills[DS_MATERIAL_COUNT] = {};
  for (size_t k = 0; k < g.tooth.size(); ++k) {
    const uint32_t l = g.tooth[k];
    const auto c = voxelCoords(l, g.dims);
    volume.setVoxel(uint32_t(g.origin[0] + c[0]), uint32_t(g.origin[1] + c[1]), uint32_t(g.origin[2] + c[2]),
                    makeVoxel(made[k], g.fill[l]));
    fills[size_t(made[k])] += g.fill[l];
  }
  const double voxel_mm3 = voxel_mm * voxel_mm * voxel_mm / DS_FILL_FULL;
  r.enamel_mm3 = fills[DS_MAT_ENAMEL] * voxel_mm3;
  r.dentin_mm3 = fills[DS_MAT_DENTIN] * voxel_mm3;
  r.pulp_mm3 = fills[DS_MAT_PULP] * voxel_mm3;
  r.enamel_cusp_mm = prop.enamel_full_mm;
  r.enamel_fissure_mm = prop.enamel_fissure_mm;
  ui.end();

  // 6. what was found and made
  r.lines.push_back(std::string("layers synthesized, not measured: enamel, dentin and pulp by published proportions for a ") +
                    toothTypeName(r.type) + (r.type_guessed ? " (type guessed from size and roots)" : " (type given)") +
                    "; method and sources in docs/LAYER_SYNTHESIS.md");
  r.lines.push_back(formatted("crown axis (%.3f, %.3f, %.3f) ", r.crown.x, r.crown.y, r.crown.z) +
                    (r.crown_found ? "found from the shape (the wide end)" : "given"));
  if (r.mesiodistal)
    r.lines.push_back(formatted("mesiodistal line (%.3f, %.3f, %.3f) from the ", r.mesiodistal->x, r.mesiodistal->y,
                          r.mesiodistal->z) +
                      (r.roots >= 2 ? std::string("roots") : std::string("crown's cross-section")) +
                      "; which end is mesial the shape does not tell (the arch and side)");
  else
    r.lines.push_back("mesial not known: the shape does not tell the mesiodistal line for this type, nor its sign");
  r.lines.push_back(formatted("%d root(s); tooth %.2f mm long; CEJ %.2f mm above the apex", r.roots, r.tooth_length_mm,
                        r.cej_mm) +
                    (r.furcation_mm > 0 ? formatted(", furcation at %.2f mm", r.furcation_mm) : std::string()));
  r.lines.push_back(formatted("enamel up to %.2f mm at the cusps, at least %.2f mm in fissures, to a knife edge at the CEJ: %.2f mm^3",
                        r.enamel_cusp_mm, r.enamel_fissure_mm, r.enamel_mm3));
  r.lines.push_back(formatted("pulp chamber %.1f mm high below the CEJ's level, canals to %.1f mm short of each apex: %.2f mm^3; dentin %.2f mm^3",
                        prop.chamber_height_mm, kApexGapMm, r.pulp_mm3, r.dentin_mm3));
  return r;
}

}  // namespace dentsim
