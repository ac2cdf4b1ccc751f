// The field algebra and primitive shapes the tooth generators share: smooth min/max, height profiles, ellipsoids, capsules, contours, cusp cones and root sweeps.
//
// Every function returns a field that is negative inside its solid and about a distance [mm] near
// its surface. Only + - * / and sqrt appear (IEEE 754 rounds them exactly), so a generator built
// from them gives bit-identical meshes on every conforming build (dentsim_model builds with
// -ffp-contract=off).
#pragma once

#include <algorithm>
#include <cmath>
#include <span>

#include "core/triangle_mesh.h"

namespace dentsim::shapes {

// Polynomial smooth minimum: equals min(a, b) once they differ by more than k [mm].
inline double smin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * k * h * h;
}
inline double smax(double a, double b, double k) { return -smin(-a, -b, k); }

inline double clamp01(double t) { return std::clamp(t, 0.0, 1.0); }
inline double smoothstep(double e0, double e1, double x) {
  const double t = clamp01((x - e0) / (e1 - e0));
  return t * t * (3.0 - 2.0 * t);
}
inline double lerp(double a, double b, double t) { return a + (b - a) * t; }
inline double sq(double v) { return v * v; }

// A profile v(z) through knots: cubic Hermite with centred-difference slopes, flat beyond the ends.
struct Knot {
  double z, v;
};
inline double profile(std::span<const Knot> k, double z) {
  if (z <= k.front().z) return k.front().v;
  if (z >= k.back().z) return k.back().v;
  size_t i = 0;
  while (k[i + 1].z < z) ++i;
  auto slope = [&](size_t n) {
    if (n == 0 || n + 1 == k.size()) return 0.0;
    return (k[n + 1].v - k[n - 1].v) / (k[n + 1].z - k[n - 1].z);
  };
  const double h = k[i + 1].z - k[i].z, t = (z - k[i].z) / h;
  const double t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * k[i].v + (t3 - 2 * t2 + t) * h * slope(i) + (-2 * t3 + 3 * t2) * k[i + 1].v +
         (t3 - t2) * h * slope(i + 1);
}

// Ellipsoid about c with semi-axes s, scaled to about a distance near its surface [mm].
inline double ellipsoid(const Vec3d& p, const Vec3d& c, const Vec3d& s) {
  const double n = std::sqrt(sq((p[0] - c[0]) / s[0]) + sq((p[1] - c[1]) / s[1]) + sq((p[2] - c[2]) / s[2]));
  return (n - 1.0) * std::min(s[0], std::min(s[1], s[2]));
}

// A capsule whose radius runs linearly from ra at a to rb at b.
inline double taperedCapsule(const Vec3d& p, const Vec3d& a, const Vec3d& b, double ra, double rb) {
  const Vec3d ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ap{p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double t = clamp01((ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / (sq(ab[0]) + sq(ab[1]) + sq(ab[2])));
  const double d = std::sqrt(sq(ap[0] - t * ab[0]) + sq(ap[1] - t * ab[1]) + sq(ap[2] - t * ab[2]));
  return d - lerp(ra, rb, t);
}

// Box of half-extents h about c with edges rounded by r.
inline double roundedBox(const Vec3d& p, const Vec3d& c, const Vec3d& h, double r) {
  double outside = 0.0, inside = -1e30;
  for (int a = 0; a < 3; ++a) {
    const double q = std::abs(p[a] - c[a]) - (h[a] - r);
    outside += sq(std::max(q, 0.0));
    inside = std::max(inside, q);
  }
  return std::sqrt(outside) + std::min(inside, 0.0) - r;
}

// A rounded-rectangle-like horizontal contour of half-widths a (x) and b (y): the mean of an
// ellipse and a 4-norm superellipse, as about a distance [mm].
inline double contour(double x, double y, double a, double b) {
  const double u = x / a, v = y / b;
  const double n = 0.5 * (std::sqrt(u * u + v * v) + std::sqrt(std::sqrt(u * u * u * u + v * v * v * v)));
  return (n - 1.0) * std::min(a, b);
}

// The height of a cusp's cone at (x, y): `tip` at (cx, cy), falling at `slope` (rise over run),
// the tip rounded over `round` [mm].
inline double cone(double x, double y, double cx, double cy, double tip, double slope, double round) {
  return tip - slope * (std::sqrt(sq(x - cx) + sq(y - cy) + sq(round)) - round);
}

// A root (or canal) swept from `top` to `apex`: elliptic sections of half-widths ax (mesiodistal)
// and by (buccolingual) tapering linearly, closed at the apex by a half-ellipsoid `cap` [mm] deep.
struct Sweep {
  Vec3d top, apex;
  double ax0, by0, ax1, by1, cap;
};

inline double sweepField(const Vec3d& p, const Sweep& s) {
  Vec3d w{s.apex[0] - s.top[0], s.apex[1] - s.top[1], s.apex[2] - s.top[2]};
  const double len = std::sqrt(sq(w[0]) + sq(w[1]) + sq(w[2]));
  for (double& v : w) v /= len;
  // e1: +x made perpendicular to the axis; e2 = w x e1.
  Vec3d e1{1.0 - w[0] * w[0], -w[0] * w[1], -w[0] * w[2]};
  const double n1 = std::sqrt(sq(e1[0]) + sq(e1[1]) + sq(e1[2]));
  for (double& v : e1) v /= n1;
  const Vec3d e2{w[1] * e1[2] - w[2] * e1[1], w[2] * e1[0] - w[0] * e1[2], w[0] * e1[1] - w[1] * e1[0]};
  const Vec3d q{p[0] - s.top[0], p[1] - s.top[1], p[2] - s.top[2]};
  const double along = q[0] * w[0] + q[1] * w[1] + q[2] * w[2];
  const double q1 = q[0] * e1[0] + q[1] * e1[1] + q[2] * e1[2];
  const double q2 = q[0] * e2[0] + q[1] * e2[1] + q[2] * e2[2];
  const double t = along / len;
  if (t > 1.0) {
    const double n = std::sqrt(sq(q1 / s.ax1) + sq(q2 / s.by1) + sq((along - len) / s.cap));
    return (n - 1.0) * std::min(s.cap, std::min(s.ax1, s.by1));
  }
  const double tc = std::max(t, 0.0);
  const double ax = lerp(s.ax0, s.ax1, tc), by = lerp(s.by0, s.by1, tc);
  const double d = (std::sqrt(sq(q1 / ax) + sq(q2 / by)) - 1.0) * std::min(ax, by);
  return t < 0.0 ? std::max(d, -along) : d;
}

}  // namespace dentsim::shapes
