// TriangleMesh: an indexed triangle surface in mm, shared by the STL reader, the generators and the voxelizer.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace dentsim {

using Vec3f = std::array<float, 3>;
using Vec3d = std::array<double, 3>;

// Axis-aligned bounds; empty() until the first point is added.
struct Bounds3 {
  Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3d hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity()};

  bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
  void add(const Vec3d& p) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  void add(const Bounds3& b) {
    if (!b.empty()) {
      add(b.lo);
      add(b.hi);
    }
  }
  Vec3d extent() const {
    if (empty()) return {0, 0, 0};
    return {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
  }
  double maxExtent() const {
    const Vec3d e = extent();
    return std::max(e[0], std::max(e[1], e[2]));
  }
};

// Triangles index `positions`; a triangle's corners run counter-clockwise seen from outside, so
// its right-hand normal points out of the solid.
struct TriangleMesh {
  std::vector<Vec3f> positions;                   // [mm]
  std::vector<std::array<uint32_t, 3>> triangles; // corner indices into positions

  size_t triangleCount() const { return triangles.size(); }
  size_t vertexCount() const { return positions.size(); }

  Bounds3 bounds() const {
    Bounds3 b;
    for (const Vec3f& p : positions) b.add(Vec3d{p[0], p[1], p[2]});
    return b;
  }

  // Enclosed volume by the divergence theorem [mm^3]: the sum of signed tetrahedra from the
  // centroid of the bounds, in double, so that it is exact for a closed mesh and negative for one
  // turned inside out. Taking the tetrahedra from a nearby point keeps the terms small.
  double signedVolume() const {
    const Bounds3 b = bounds();
    if (b.empty()) return 0.0;
    const Vec3d c{0.5 * (b.lo[0] + b.hi[0]), 0.5 * (b.lo[1] + b.hi[1]), 0.5 * (b.lo[2] + b.hi[2])};
    double six_v = 0.0;
    for (const auto& t : triangles) {
      Vec3d p[3];
      for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) p[k][a] = double(positions[t[k]][a]) - c[a];
      six_v += p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
               p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
               p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
    }
    return six_v / 6.0;
  }

  // Scales every position about the origin (unit conversion).
  void scale(double factor) {
    for (Vec3f& p : positions)
      for (float& v : p) v = float(double(v) * factor);
  }
};

}  // namespace dentsim
