// Analytic test meshes (sphere, torus, box) whose enclosed volumes are known in closed form.
#pragma once

#include <cmath>
#include <numbers>

#include "core/triangle_mesh.h"

namespace dentsim::test {

// Appends mesh b to a (a second shell of the same surface).
inline void appendMesh(TriangleMesh& a, const TriangleMesh& b) {
  const uint32_t base = uint32_t(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

inline void invertMesh(TriangleMesh& m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
}

// UV sphere: `rings` latitude bands, `segments` longitudes, outward.
inline TriangleMesh uvSphere(Vec3d c, double r, uint32_t segments = 96, uint32_t rings = 48) {
  TriangleMesh m;
  m.positions.push_back({float(c[0]), float(c[1]), float(c[2] - r)});  // south pole
  for (uint32_t i = 1; i < rings; ++i) {
    const double theta = std::numbers::pi * double(i) / rings - std::numbers::pi / 2;
    for (uint32_t j = 0; j < segments; ++j) {
      const double phi = 2 * std::numbers::pi * double(j) / segments;
      m.positions.push_back({float(c[0] + r * std::cos(theta) * std::cos(phi)),
                             float(c[1] + r * std::cos(theta) * std::sin(phi)), float(c[2] + r * std::sin(theta))});
    }
  }
  m.positions.push_back({float(c[0]), float(c[1]), float(c[2] + r)});  // north pole
  const uint32_t north = uint32_t(m.positions.size() - 1);
  auto ring = [&](uint32_t i, uint32_t j) { return 1 + (i - 1) * segments + (j % segments); };
  for (uint32_t j = 0; j < segments; ++j) m.triangles.push_back({0, ring(1, j + 1), ring(1, j)});
  for (uint32_t i = 1; i + 1 < rings; ++i)
    for (uint32_t j = 0; j < segments; ++j) {
      m.triangles.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
  for (uint32_t j = 0; j < segments; ++j) m.triangles.push_back({ring(rings - 1, j), ring(rings - 1, j + 1), north});
  return m;
}

// Torus about the z axis: major radius R, minor radius r, outward.
inline TriangleMesh torus(Vec3d c, double R, double r, uint32_t major = 128, uint32_t minor = 48) {
  TriangleMesh m;
  for (uint32_t i = 0; i < major; ++i) {
    const double u = 2 * std::numbers::pi * double(i) / major;
    for (uint32_t j = 0; j < minor; ++j) {
      const double v = 2 * std::numbers::pi * double(j) / minor;
      const double rho = R + r * std::cos(v);
      m.positions.push_back(
          {float(c[0] + rho * std::cos(u)), float(c[1] + rho * std::sin(u)), float(c[2] + r * std::sin(v))});
    }
  }
  auto at = [&](uint32_t i, uint32_t j) { return (i % major) * minor + (j % minor); };
  for (uint32_t i = 0; i < major; ++i)
    for (uint32_t j = 0; j < minor; ++j) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

// Axis-aligned box, outward, 12 triangles.
inline TriangleMesh box(Vec3d lo, Vec3d hi) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k)
    m.positions.push_back({float(k & 1 ? hi[0] : lo[0]), float(k & 2 ? hi[1] : lo[1]), float(k & 4 ? hi[2] : lo[2])});
  const uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& f : q) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  return m;
}

// A box with a box-shaped cavity: the inner shell turned inward.
inline TriangleMesh hollowBox(Vec3d lo, Vec3d hi, double wall) {
  TriangleMesh m = box(lo, hi);
  TriangleMesh inner = box({lo[0] + wall, lo[1] + wall, lo[2] + wall}, {hi[0] - wall, hi[1] - wall, hi[2] - wall});
  invertMesh(inner);
  appendMesh(m, inner);
  return m;
}

inline double sphereVolume(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }
inline double torusVolume(double R, double r) { return 2 * std::numbers::pi * std::numbers::pi * R * r * r; }

}  // namespace dentsim::test
