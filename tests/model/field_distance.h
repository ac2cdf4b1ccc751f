// The distance from a point to an implicit field's surface, to first order, for the model tests that compare generated meshes with their fields.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/rigid.h"

namespace dentsim::test {

// The field's value over its gradient's length (central differences) [mm]: positive outside. A
// field steep in the fissures (the molar's occlusal height field) overstates the distance raw.
template <typename Field>
double fieldDistanceMm(const Field& field, const Vec3d& c) {
  const double f = field(c), e = 1e-4;
  double g2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    Vec3d lo = c, hi = c;
    lo[a] -= e;
    hi[a] += e;
    g2 += std::pow((field(hi) - field(lo)) / (2 * e), 2);
  }
  return f / std::sqrt(std::max(g2, 1e-12));
}

}  // namespace dentsim::test
