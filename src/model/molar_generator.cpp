// The built-in lower first molar: implicit fields for tooth, dentin core, pulp and caries, and their layers.
//
// Contents:
//   1. field algebra      from model/implicit_shapes.h
//   2. crown              lateral contour, occlusal height field (cusps, ridges, fissures), DEJ
//   3. roots and pulp     tapered elliptic roots, chamber with horns, canals
//   4. fields and layers  the four public fields and generateMolar()
//
// The shapes follow textbook dimensions of a mandibular first molar: crown 11 mm mesiodistal,
// 10 mm buccolingual, 7.5 mm from CEJ to cusp tips; roots 13-14 mm. Only + - * / and sqrt appear,
// which IEEE 754 rounds exactly, so the output is bit-identical on every conforming build.
#include "model/molar_generator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "model/implicit_mesher.h"
#include "model/implicit_shapes.h"

namespace dentsim {
namespace {

// ---- 1. field algebra ---------------------------------------------------------------------------

// model/implicit_shapes.h: smin, smax, profile, contour, cone, the root sweep and the rest.
using namespace shapes;

// ---- 2. crown -----------------------------------------------------------------------------------

// Half-widths of the crown and root trunk against height [mm]: the cervical constriction at the
// CEJ (z = 0), the buccal height of contour in the cervical third, the lingual one in the middle
// third, and the occlusal convergence above.
constexpr Knot kMesiodistal[] = {{-4.0, 4.05}, {-2.0, 4.2}, {0.0, 4.45}, {1.5, 5.05}, {3.5, 5.5},
                                 {5.0, 5.45}, {6.5, 5.0}, {8.0, 4.5}};
constexpr Knot kBuccal[] = {{-4.0, 3.55}, {-2.0, 3.75}, {0.0, 4.0}, {1.2, 4.75}, {2.2, 5.0},
                            {4.0, 4.8}, {5.5, 4.3}, {7.0, 3.6}, {8.5, 3.0}};
constexpr Knot kLingual[] = {{-4.0, 3.45}, {-2.0, 3.6}, {0.0, 3.85}, {1.5, 4.4}, {3.5, 4.95},
                             {5.0, 4.8}, {6.5, 4.2}, {8.0, 3.5}};

// Enamel thickness on the axial walls [mm]: zero at the CEJ, growing over the cervical third.
// Below the CEJ it turns negative, which pushes the dentin contour outside the tooth so that the
// root takes its surface from the tooth field.
double wallEnamel(double z) {
  if (z < 0.0) return 3.0 * z;
  const double t = 1.0 - std::min(z / 2.4, 1.0);
  return 0.9 * (1.0 - t * t);
}

struct Cusp {
  double x, y;      // tip position [mm]
  double tip;       // tip height above the CEJ [mm]
  double slope;     // steepness of the cusp ridges (rise over run)
  double round;     // tip rounding radius [mm]
  double enamel;    // enamel thickness over the tip [mm]: the dentin horn is this much lower
};
// Buccal cusps blunter and lower, lingual cusps taller and more pointed.
constexpr Cusp kCusps[] = {
    {-2.8, -2.5, 7.0, 0.62, 1.3, 2.3},  // mesiobuccal
    {0.7, -2.8, 6.8, 0.62, 1.2, 2.3},   // distobuccal
    {3.6, -1.4, 6.3, 0.70, 1.0, 2.0},   // distal
    {-2.4, 2.6, 7.6, 0.85, 0.7, 2.0},   // mesiolingual
    {1.9, 2.6, 7.4, 0.85, 0.7, 2.0},    // distolingual
};
constexpr int kCuspCount = int(sizeof(kCusps) / sizeof(kCusps[0]));

// Mesial and distal marginal ridges: crests across the crown at the proximal ends of the table.
double marginalRidges(double x, double drop, double slope) {
  const double mesial = 5.9 - drop - slope * (std::sqrt(sq(x + 4.25) + 0.25) - 0.5);
  const double distal = 5.6 - drop - slope * (std::sqrt(sq(x - 4.45) + 0.25) - 0.5);
  return std::max(mesial, distal);
}

// Height of the occlusal surface [mm]. Where two cusps' slopes meet, their heights are equal, so
// a narrow notch on |h1 - h2| cuts the fissures (central, buccal, distobuccal, lingual grooves)
// exactly along the valleys; the notch fades out where the marginal ridges rise above the cusps,
// leaving the mesial and distal pits.
double occlusalHeight(double x, double y) {
  double h1 = -1e30, h2 = -1e30, cusps = 0.0;
  for (int c = 0; c < kCuspCount; ++c) {
    const Cusp& k = kCusps[c];
    const double h = cone(x, y, k.x, k.y, k.tip, k.slope, k.round);
    cusps = c == 0 ? h : smax(cusps, h, 0.5);
    if (h > h1) {
      h2 = h1;
      h1 = h;
    } else if (h > h2) {
      h2 = h;
    }
  }
  constexpr double kFissureDepth = 0.85;  // [mm]
  constexpr double kFissureWidth = 0.45;  // in |h1 - h2| [mm]
  const double s = (h1 - h2) / kFissureWidth;
  const double notch = s < 1.0 ? kFissureDepth * sq(1.0 - s * s) : 0.0;
  const double ridges = marginalRidges(x, 0.0, 0.9);
  const double fade = smoothstep(-0.1, 0.4, cusps - ridges);
  return smax(cusps - notch * fade, ridges, 0.4);
}

// Height of the DEJ under the occlusal surface [mm]: blunter dentin horns under each cusp and a
// bowl under the central fossa that keeps the enamel there about 2 mm thick.
double dejHeight(double x, double y) {
  double horns = 0.0;
  for (int c = 0; c < kCuspCount; ++c) {
    const Cusp& k = kCusps[c];
    const double h = cone(x, y, k.x * 0.92, k.y * 0.92, k.tip - k.enamel, 0.75, 1.0);
    horns = c == 0 ? h : smax(horns, h, 0.8);
  }
  horns = smax(horns, marginalRidges(x, 1.7, 0.7), 0.8);
  const double bowl = 3.5 + 0.22 * sq(x + 0.2) + 0.35 * sq(y - 0.2);
  return smin(horns, bowl, 0.8);
}

double crownLateral(const Vec3d& p, double inset) {
  const double z = p[2];
  const double a = profile(kMesiodistal, z) - inset;
  const double b = (p[1] < 0.0 ? profile(kBuccal, z) : profile(kLingual, z)) - inset;
  return contour(p[0], p[1], a, b);
}

// ---- 3. roots and pulp --------------------------------------------------------------------------

// Mesial and distal roots, flattened mesiodistally and diverging slightly toward the apices.
constexpr Sweep kMesialRoot{{-2.35, 0.0, -1.0}, {-3.0, 0.0, -12.6}, 1.9, 3.9, 0.75, 1.05, 0.9};
constexpr Sweep kDistalRoot{{2.45, 0.1, -1.0}, {3.1, 0.2, -12.2}, 1.85, 3.4, 0.8, 1.0, 0.9};

// A canal along a root's axis, from the chamber to about 1 mm short of the apex, ribbon-shaped at
// the top and round (0.44 mm across) near its end.
Sweep canalOf(const Sweep& root, double ax0, double by0) {
  const double reach = 0.97;
  const Vec3d end{lerp(root.top[0], root.apex[0], reach), lerp(root.top[1], root.apex[1], reach),
                  lerp(root.top[2], root.apex[2], reach)};
  return {{root.top[0], root.top[1], root.top[2] + 0.2}, end, ax0, by0, 0.22, 0.22, 0.22};
}

double pulpChamber(const Vec3d& p) {
  double f = roundedBox(p, {0.1, 0.0, -0.4}, {2.2, 1.6, 1.2}, 0.9);
  // One horn toward each cusp, the lingual ones reaching higher under the taller cusps.
  constexpr double kHornTip[kCuspCount] = {1.8, 1.7, 1.3, 2.0, 1.9};  // [mm] above the CEJ
  for (int c = 0; c < kCuspCount; ++c) {
    const Cusp& k = kCusps[c];
    const double horn =
        taperedCapsule(p, {0.55 * k.x, 0.45 * k.y, 0.4}, {0.65 * k.x, 0.55 * k.y, kHornTip[c]}, 0.7, 0.3);
    f = smin(f, horn, 0.5);
  }
  return f;
}

}  // namespace

// ---- 4. fields and layers -----------------------------------------------------------------------

double molarToothField(const Vec3d& p) {
  const double crown = smax(crownLateral(p, 0.0), p[2] - occlusalHeight(p[0], p[1]), 0.8);
  // The root trunk ends in the furcation roof about 3.6 mm below the CEJ.
  const double body = smax(crown, -(p[2] + 3.6), 1.2);
  const double roots = smin(sweepField(p, kMesialRoot), sweepField(p, kDistalRoot), 0.6);
  return smin(body, roots, 1.0);
}

double molarDentinField(const Vec3d& p) {
  return smax(crownLateral(p, wallEnamel(p[2])), p[2] - dejHeight(p[0], p[1]), 0.8);
}

double molarPulpField(const Vec3d& p) {
  const double canals =
      std::min(sweepField(p, canalOf(kMesialRoot, 0.4, 0.9)), sweepField(p, canalOf(kDistalRoot, 0.4, 0.8)));
  return smin(pulpChamber(p), canals, 0.6);
}

double molarCariesField(const Vec3d& p) {
  // A narrow cone along the fissure in the enamel, spreading along the DEJ in the dentin.
  const double in_enamel = ellipsoid(p, {-0.1, 0.3, 4.3}, {1.3, 0.45, 1.0});
  const double in_dentin = ellipsoid(p, {-0.1, 0.3, 3.2}, {1.0, 0.8, 0.45});
  return smin(in_enamel, in_dentin, 0.5);
}

Bounds3 molarBounds() {
  Bounds3 b;
  b.add(Vec3d{-6.2, -5.8, -14.2});
  b.add(Vec3d{6.2, 5.8, 8.4});
  return b;
}

MolarLayers generateMolar(const MolarOptions& options) {
  const SampleGrid grid = gridAround(molarBounds(), options.grid_mm, 2);
  const std::vector<double> tooth = sampleField(grid, molarToothField);
  const std::vector<double> dentin = sampleField(grid, molarDentinField);
  const std::vector<double> pulp = sampleField(grid, molarPulpField);
  const std::vector<double> caries = sampleField(grid, molarCariesField);

  // Enamel is tooth minus dentin core, dentin is tooth and core: on the DEJ the two values are
  // exact negations of each other, so both meshes get the same crossings there.
  std::vector<double> g(grid.nodeCount());
  MolarLayers layers;
  for (size_t n = 0; n < g.size(); ++n) g[n] = std::max(tooth[n], -dentin[n]);
  layers.enamel = meshZeroSet(grid, g);
  for (size_t n = 0; n < g.size(); ++n) g[n] = std::max(tooth[n], dentin[n]);
  layers.dentin = meshZeroSet(grid, g);
  layers.pulp = meshZeroSet(grid, pulp);
  for (size_t n = 0; n < g.size(); ++n) g[n] = std::max(tooth[n], caries[n]);
  layers.caries = meshZeroSet(grid, g);
  return layers;
}

}  // namespace dentsim
