// Tests of the molar's neighbours: each one closed outward piece of a plausible size, on its side of the molar, at a contact gap of about 0.1 mm.
#include "model/neighbour_generator.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <gtest/gtest.h>

#include "io/mesh_topology.h"
#include "model/field_distance.h"
#include "model/molar_generator.h"

namespace dentsim {
namespace {

// Coarser than the assets' 0.45 mm: the shapes show, and the suite stays quick under the sanitizers.
const NeighbourTeeth& coarseNeighbours() {
  static const NeighbourTeeth teeth = generateNeighbours({.grid_mm = 0.6});
  return teeth;
}

using Field = double (*)(const Vec3d&);

// The first x along a row (y, z), from x0 in direction dir (+1 or -1), where `f` turns inside,
// bisected to 1e-9 mm; NaN when the row stays outside for `reach` mm.
double firstInside(Field f, double x0, double dir, double y, double z, double reach) {
  double prev = x0;
  for (double t = 0.0; t <= reach; t += 0.05) {
    const double x = x0 + dir * t;
    if (f({x, y, z}) < 0.0) {
      double out = prev, in = x;
      for (int i = 0; i < 40; ++i) {
        const double m = 0.5 * (out + in);
        (f({m, y, z}) < 0.0 ? in : out) = m;
      }
      return in;
    }
    prev = x;
  }
  return NAN;
}

// The narrowest gap along x between the molar and a neighbour, over rows 0.1 mm apart across the
// crowns' proximal faces: for each row, the molar's face seen from the neighbour's side less the
// neighbour's face seen from the molar's. It bounds the true (closest) distance from above, and
// equals it where the two faces stand square to x, as they do at a contact.
struct Gap {
  double mm = HUGE_VAL;  // [mm]; negative: the solids overlap
  double y = 0, z = 0;   // the row where it is narrowest [mm]
};
Gap proximalGap(Field neighbour, double side) {
  Gap g;
  for (int j = -20; j <= 20; ++j)
    for (int k = 10; k <= 70; ++k) {
      const double y = 0.1 * j, z = 0.1 * k;
      // The molar's face from 7.5 mm out; the neighbour's from 4 mm out of the molar's centre, inside
      // the molar, toward the neighbour.
      const double molar_face = firstInside(molarToothField, side * 7.5, -side, y, z, 3.5);
      const double neighbour_face = firstInside(neighbour, side * 4.0, side, y, z, 4.5);
      if (std::isnan(molar_face) || std::isnan(neighbour_face)) continue;
      const double gap = side * (neighbour_face - molar_face);
      if (gap < g.mm) g = {gap, y, z};
    }
  return g;
}

TEST(NeighbourGenerator, EachIsOneClosedOutwardManifold) {
  const NeighbourTeeth& n = coarseNeighbours();
  for (const NeighbourRow& row : kNeighbourTeeth) {
    const TriangleMesh& m = n.*row.mesh;
    const MeshTopology t = analyzeTopology(m);
    EXPECT_GT(m.triangleCount(), 1000u) << row.name;
    EXPECT_TRUE(t.closed()) << row.name;
    EXPECT_EQ(t.orientation(), "outward") << row.name;
    EXPECT_EQ(t.nonmanifold_edges, 0u) << row.name;
    EXPECT_EQ(t.degenerate_triangles, 0u) << row.name;
  }
}

TEST(NeighbourGenerator, DimensionsOfASecondPremolarAndASecondMolar) {
  const NeighbourTeeth& n = coarseNeighbours();
  const Vec3d pm = n.premolar.bounds().extent(), m2 = n.second_molar.bounds().extent();
  // Lower second premolar: crown about 7 x 8 mm, about 7.5 mm tall; one root of about 14 mm.
  EXPECT_NEAR(pm[0], 7.0, 0.5) << "premolar mesiodistal";
  EXPECT_NEAR(pm[1], 8.0, 0.5) << "premolar buccolingual";
  EXPECT_NEAR(n.premolar.bounds().hi[2], 7.6, 0.4) << "premolar crown height above the CEJ";
  EXPECT_NEAR(n.premolar.bounds().lo[2], -14.8, 0.5) << "premolar root";
  // Lower second molar: a little smaller than the first (11 x 10 mm, 21 mm long).
  EXPECT_NEAR(m2[0], 10.4, 0.5) << "second molar mesiodistal";
  EXPECT_LT(m2[0], 11.0);
  EXPECT_LT(m2[2], 21.0);
  // Volumes: the premolar about half the first molar's 600-900 mm^3, the second molar about 0.94^3 of it.
  EXPECT_GT(n.premolar.signedVolume(), 300.0);
  EXPECT_LT(n.premolar.signedVolume(), 550.0);
  EXPECT_GT(n.second_molar.signedVolume(), 550.0);
  EXPECT_LT(n.second_molar.signedVolume(), 800.0);
}

TEST(NeighbourGenerator, EachStandsOnItsSideOfTheMolar) {
  const NeighbourTeeth& n = coarseNeighbours();
  const Bounds3 molar = molarBounds();
  // The premolar wholly mesial (-x) of the molar's middle, the second molar wholly distal; both
  // on the molar's buccolingual line and CEJ level.
  EXPECT_LT(n.premolar.bounds().hi[0], -5.0);
  EXPECT_GT(n.second_molar.bounds().lo[0], 5.0);
  for (const TriangleMesh* m : {&n.premolar, &n.second_molar}) {
    EXPECT_GT(m->bounds().lo[1], molar.lo[1]);
    EXPECT_LT(m->bounds().hi[1], molar.hi[1]);
  }
}

// The gap at each contact, measured on the fields: 0.05 to 0.2 mm (a contact that floss passes),
// nowhere an overlap, at the contact area: the proximal height of contour in the upper middle third
// of the crown, about on the molar's buccolingual centre.
TEST(NeighbourGenerator, EachTouchesTheMolarAtItsContactArea) {
  for (const auto& [field, side, name] : {std::tuple{&premolarToothField, -1.0, "premolar"},
                                          std::tuple{&secondMolarToothField, 1.0, "second molar"}}) {
    const Gap g = proximalGap(field, side);
    EXPECT_GE(g.mm, 0.05) << name;
    EXPECT_LE(g.mm, 0.2) << name;
    EXPECT_NEAR(g.mm, kContactGapMm, 0.01) << name << ": the placement's own figure";
    EXPECT_GT(g.z, 3.0) << name << ": above the cervical third";
    EXPECT_LT(g.z, 5.5) << name << ": below the cusps";
    EXPECT_LT(std::abs(g.y), 1.0) << name;
  }
}

// The meshes as shipped keep the gap: no vertex of a neighbour lies inside the molar, and the
// nearest is within the lattice's error of the fields' gap.
TEST(NeighbourGenerator, MeshesKeepTheGap) {
  const NeighbourTeeth& n = coarseNeighbours();
  for (const TriangleMesh* m : {&n.premolar, &n.second_molar}) {
    double nearest = HUGE_VAL;
    for (const Vec3f& p : m->positions) {
      // The distance to the molar's surface, to first order.
      nearest = std::min(nearest, test::fieldDistanceMm(molarToothField, Vec3d{p[0], p[1], p[2]}));
    }
    // A vertex lies on a lattice edge, off the curved surface by a fraction of a 0.6 mm cell.
    EXPECT_GT(nearest, 0.0);
    EXPECT_LT(nearest, kContactGapMm + 0.15);
  }
}

TEST(NeighbourGenerator, Deterministic) {
  const NeighbourTeeth a = generateNeighbours({.grid_mm = 0.8}), b = generateNeighbours({.grid_mm = 0.8});
  EXPECT_EQ(a.premolar.positions, b.premolar.positions);
  EXPECT_EQ(a.premolar.triangles, b.premolar.triangles);
  EXPECT_EQ(a.second_molar.positions, b.second_molar.positions);
}

}  // namespace
}  // namespace dentsim
