// The molar's neighbours: a lower second premolar of its own fields, a lower second molar scaled from the first, each placed at its contact.
//
// Contents:
//   1. premolar      lateral contour, two cusps and the marginal ridges, one root
//   2. second molar  the first molar's field, scaled
//   3. placement     where each stands beside the molar
//   4. meshes        generateNeighbours()
//
// The premolar follows textbook dimensions of a mandibular second premolar: crown 7 mm
// mesiodistal, 8 mm buccolingual, about 7.6 mm from CEJ to the buccal cusp tip; one root of 14 mm.
#include "model/neighbour_generator.h"

#include <vector>

#include "model/implicit_mesher.h"
#include "model/implicit_shapes.h"
#include "model/molar_generator.h"

namespace dentsim {
namespace {

using namespace shapes;

// ---- 1. premolar (its own frame: CEJ at z = 0, centred on the long axis) ------------------------------

// Half-widths against height [mm], shaped as the molar's (molar_generator.cpp): the proximal heights
// of contour at z 3.5, where the molar's are, so that the two meet at one contact.
constexpr Knot kPremolarMesiodistal[] = {{-4.0, 2.35}, {-2.0, 2.5}, {0.0, 2.6}, {1.5, 3.1}, {3.5, 3.5},
                                         {5.0, 3.4},   {6.5, 2.9},  {8.0, 2.3}};
constexpr Knot kPremolarBuccal[] = {{-4.0, 3.0}, {-2.0, 3.2}, {0.0, 3.4}, {1.2, 3.95}, {2.2, 4.1},
                                    {4.0, 3.9},  {5.5, 3.3},  {7.0, 2.4}, {8.5, 1.6}};
constexpr Knot kPremolarLingual[] = {{-4.0, 2.8}, {-2.0, 3.0}, {0.0, 3.2}, {1.5, 3.6}, {3.5, 3.85},
                                     {5.0, 3.5},  {6.5, 2.8},  {8.0, 2.1}};

struct PremolarCusp {
  double y, tip, slope, round;  // buccolingual place, height [mm], ridge steepness, tip rounding [mm]
};
// The buccal cusp taller and blunter, the lingual one lower, as on a two-cusp lower second premolar.
constexpr PremolarCusp kPremolarBuccalCusp{-1.5, 7.6, 0.8, 1.0};
constexpr PremolarCusp kPremolarLingualCusp{1.9, 6.8, 0.9, 0.8};

// Marginal ridges at the crown's mesial and distal ends.
double premolarRidges(double x) {
  return 5.9 - 0.9 * (std::sqrt(sq(std::abs(x) - 2.45) + 0.25) - 0.5);
}

// The occlusal surface [mm]: the two cusps' cones, the central groove where they meet (a notch on
// |buccal - lingual|, as the molar's fissures), and the marginal ridges that close it into pits.
double premolarOcclusal(double x, double y) {
  const double b = cone(x, y, 0.0, kPremolarBuccalCusp.y, kPremolarBuccalCusp.tip, kPremolarBuccalCusp.slope,
                        kPremolarBuccalCusp.round);
  const double l = cone(x, y, 0.0, kPremolarLingualCusp.y, kPremolarLingualCusp.tip, kPremolarLingualCusp.slope,
                        kPremolarLingualCusp.round);
  const double cusps = smax(b, l, 0.5);
  const double s = std::abs(b - l) / 0.45;
  const double notch = s < 1.0 ? 0.7 * sq(1.0 - s * s) : 0.0;
  const double ridges = premolarRidges(x);
  const double fade = smoothstep(-0.1, 0.4, cusps - ridges);
  return smax(cusps - notch * fade, ridges, 0.4);
}

constexpr Sweep kPremolarRoot{{0.0, 0.0, -0.5}, {0.0, 0.2, -14.0}, 2.35, 3.1, 0.7, 0.8, 0.8};

double premolarLocal(const Vec3d& p) {
  const double z = p[2];
  const double a = profile(kPremolarMesiodistal, z);
  const double b = p[1] < 0.0 ? profile(kPremolarBuccal, z) : profile(kPremolarLingual, z);
  const double crown = smax(contour(p[0], p[1], a, b), z - premolarOcclusal(p[0], p[1]), 0.8);
  const double body = smax(crown, -(z + 2.0), 1.0);
  return smin(body, sweepField(p, kPremolarRoot), 1.0);
}

// ---- 2. second molar -------------------------------------------------------------------------------

// A lower second molar is a little smaller than the first (crown about 10.5 mm mesiodistal against
// 11); the first's field at this scale stands for it.
constexpr double kSecondMolarScale = 0.94;

// ---- 3. placement -------------------------------------------------------------------------------------

// Each neighbour's CEJ centre in the molar's frame [mm]: found by bisection on the offset until the
// closest surfaces lie kContactGapMm apart (tests/model/neighbour_generator_test.cpp checks it).
constexpr Vec3d kPremolarAt{-9.146, 0.0, 0.0};
constexpr Vec3d kSecondMolarAt{10.828, 0.0, 0.0};

}  // namespace

double premolarToothField(const Vec3d& p) {
  return premolarLocal({p[0] - kPremolarAt[0], p[1] - kPremolarAt[1], p[2] - kPremolarAt[2]});
}

double secondMolarToothField(const Vec3d& p) {
  const double s = kSecondMolarScale;
  return s * molarToothField({(p[0] - kSecondMolarAt[0]) / s, (p[1] - kSecondMolarAt[1]) / s,
                              (p[2] - kSecondMolarAt[2]) / s});
}

Bounds3 premolarBounds() {
  Bounds3 b;
  b.add(Vec3d{kPremolarAt[0] - 4.2, kPremolarAt[1] - 4.8, kPremolarAt[2] - 15.2});
  b.add(Vec3d{kPremolarAt[0] + 4.2, kPremolarAt[1] + 4.8, kPremolarAt[2] + 8.6});
  return b;
}

Bounds3 secondMolarBounds() {
  const Bounds3 m = molarBounds();
  Bounds3 b;
  for (const Vec3d& c : {m.lo, m.hi})
    b.add(Vec3d{kSecondMolarAt[0] + kSecondMolarScale * c[0], kSecondMolarAt[1] + kSecondMolarScale * c[1],
                kSecondMolarAt[2] + kSecondMolarScale * c[2]});
  return b;
}

// ---- 4. meshes ------------------------------------------------------------------------------------------

NeighbourTeeth generateNeighbours(const NeighbourOptions& options) {
  NeighbourTeeth teeth;
  const SampleGrid pm = gridAround(premolarBounds(), options.grid_mm, 2);
  teeth.premolar = meshZeroSet(pm, sampleField(pm, premolarToothField));
  const SampleGrid m2 = gridAround(secondMolarBounds(), options.grid_mm, 2);
  teeth.second_molar = meshZeroSet(m2, sampleField(m2, secondMolarToothField));
  return teeth;
}

}  // namespace dentsim
