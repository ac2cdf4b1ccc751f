// Per-corner creased normals for tool meshes, and the mirror's glass disc.
#include "render/tool_mesh.h"

#include <cassert>
#include <cmath>
#include <numbers>

namespace dentsim::render {

namespace {

using D3 = std::array<double, 3>;

D3 sub(const Vec3f& a, const Vec3f& b) { return {double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]}; }
D3 crossD(const D3& a, const D3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dotD(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
D3 unit(const D3& a) {
  const double n = std::sqrt(dotD(a, a));
  return n > 0 ? D3{a[0] / n, a[1] / n, a[2] / n} : D3{0, 0, 0};
}

}  // namespace

std::vector<ToolVertex> creasedVertices(const TriangleMesh& mesh, double crease_deg) {
  const size_t nt = mesh.triangles.size();
  // Face normals with length twice the area (the weights), and each vertex's faces.
  std::vector<D3> area_normal(nt);
  std::vector<std::vector<uint32_t>> faces_of(mesh.positions.size());
  for (size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    area_normal[t] = crossD(sub(mesh.positions[tri[1]], mesh.positions[tri[0]]),
                            sub(mesh.positions[tri[2]], mesh.positions[tri[0]]));
    for (uint32_t v : tri) faces_of[v].push_back(uint32_t(t));
  }
  const double cos_crease = std::cos(crease_deg * std::numbers::pi / 180.0);

  std::vector<ToolVertex> out;
  out.reserve(nt * 3);
  for (size_t t = 0; t < nt; ++t) {
    const D3 own = unit(area_normal[t]);
    for (uint32_t v : mesh.triangles[t]) {
      D3 sum{0, 0, 0};
      for (uint32_t f : faces_of[v]) {
        const D3 other = unit(area_normal[f]);
        // A degenerate face (own = 0) takes every neighbour.
        if (dotD(own, own) == 0.0 || dotD(own, other) >= cos_crease)
          for (int a = 0; a < 3; ++a) sum[size_t(a)] += area_normal[f][size_t(a)];
      }
      const D3 n = unit(sum);
      const Vec3f& p = mesh.positions[v];
      out.push_back({p[0], p[1], p[2], float(n[0]), float(n[1]), float(n[2])});
    }
  }
  return out;
}

std::vector<ToolVertex> discVertices(double radius_mm, double z_mm, int segments) {
  assert(segments >= 3);
  std::vector<ToolVertex> out;
  out.reserve(size_t(segments) * 3);
  const float z = float(z_mm);
  for (int i = 0; i < segments; ++i) {
    const double a0 = 2.0 * std::numbers::pi * i / segments, a1 = 2.0 * std::numbers::pi * (i + 1) / segments;
    out.push_back({0.0f, 0.0f, z, 0.0f, 0.0f, 1.0f});
    out.push_back({float(radius_mm * std::cos(a0)), float(radius_mm * std::sin(a0)), z, 0.0f, 0.0f, 1.0f});
    out.push_back({float(radius_mm * std::cos(a1)), float(radius_mm * std::sin(a1)), z, 0.0f, 0.0f, 1.0f});
  }
  return out;
}

}  // namespace dentsim::render
