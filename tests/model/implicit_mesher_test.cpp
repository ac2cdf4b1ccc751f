// Tests of marching tetrahedra: exact counts on a one-node blob, a sphere's volume and its convergence.
#include "model/implicit_mesher.h"

#include <cmath>
#include <algorithm>
#include <map>
#include <numbers>
#include <set>

#include <gtest/gtest.h>

#include "io/mesh_topology.h"

namespace dentsim {
namespace {

void expectClosedOutward(const TriangleMesh& m) {
  const MeshTopology t = analyzeTopology(m);
  EXPECT_EQ(t.open_edges, 0u);
  EXPECT_EQ(t.nonmanifold_edges, 0u);
  EXPECT_EQ(t.flipped_edges, 0u);
  EXPECT_EQ(t.degenerate_triangles, 0u);
  EXPECT_GT(t.signed_volume_mm3, 0.0);
}

TEST(ImplicitMesher, OneInsideNodeGivesItsLink) {
  // 3x3x3 nodes, only the centre inside. In the Kuhn triangulation an interior node has 14 edge
  // neighbours (6 along the axes, 6 face diagonals, 2 body diagonals) and lies in 24 tetrahedra,
  // so the surface is its link: 14 vertices, one triangle per tetrahedron, each vertex at the
  // middle of its edge because the values are -1 and +1.
  SampleGrid g;
  g.origin = {0, 0, 0};
  g.spacing = 1.0;
  g.nodes = {3, 3, 3};
  std::vector<double> v(g.nodeCount(), 1.0);
  v[g.index(1, 1, 1)] = -1.0;
  const TriangleMesh m = meshZeroSet(g, v);
  EXPECT_EQ(m.vertexCount(), 14u);
  EXPECT_EQ(m.triangleCount(), 24u);
  for (const Vec3f& p : m.positions)
    for (float c : p) EXPECT_TRUE(c == 0.5f || c == 1.0f || c == 1.5f) << c;
  expectClosedOutward(m);
}

TEST(ImplicitMesher, BorderNodesCountAsOutside) {
  // Everything inside: only the interior node survives as inside, so the surface still closes.
  SampleGrid g;
  g.spacing = 1.0;
  g.nodes = {3, 3, 3};
  const std::vector<double> v(g.nodeCount(), -1.0);
  const TriangleMesh m = meshZeroSet(g, v);
  EXPECT_EQ(m.triangleCount(), 24u);
  expectClosedOutward(m);
}

// Volume of the mesh of a sphere of radius r sampled at spacing h.
double sphereVolume(double r, double h) {
  const Vec3d c{0.013, 0.021, -0.017};  // off the lattice, so no symmetry helps
  Bounds3 box;
  box.add(Vec3d{c[0] - r, c[1] - r, c[2] - r});
  box.add(Vec3d{c[0] + r, c[1] + r, c[2] + r});
  const SampleGrid g = gridAround(box, h, 2);
  const auto v = sampleField(g, [&](const Vec3d& p) {
    return std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) + (p[2] - c[2]) * (p[2] - c[2])) - r;
  });
  const TriangleMesh m = meshZeroSet(g, v);
  expectClosedOutward(m);
  return m.signedVolume();
}

TEST(ImplicitMesher, SphereVolumeWithinChordErrorAndConverges) {
  // Tetrahedron edges are at most sqrt(3) h long. A chord of length L lies at most L^2 / (8 r)
  // inside the sphere, and the linear interpolation of the distance along an edge misplaces a
  // vertex by less than that again, so the surface stays within 2 * 3 h^2 / (8 r) = 3 h^2 / (4 r)
  // of the sphere: |V - 4/3 pi r^3| <= 4 pi r^2 * 3 h^2 / (4 r) = 3 pi r h^2.
  const double r = 1.0, exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  double last_error = 0.0;
  for (double h : {0.2, 0.1, 0.05}) {
    const double error = std::abs(sphereVolume(r, h) - exact);
    EXPECT_LE(error, 3.0 * std::numbers::pi * r * h * h) << "h = " << h;
    // Second order: halving h should cut the error to about a quarter; ask for under a half.
    if (last_error > 0.0) {
      EXPECT_LT(error, 0.5 * last_error) << "h = " << h;
    }
    last_error = error;
  }
}

TEST(ImplicitMesher, NegatedFieldGivesTheSameVerticesReversed) {
  // Two shells cut from one lattice share their interface exactly: an inner ball and the shell
  // around it, the second from max(outer, -inner) as the molar's enamel is made.
  SampleGrid g = gridAround(Bounds3{{-2, -2, -2}, {2, 2, 2}}, 0.15, 2);
  const auto inner = sampleField(g, [](const Vec3d& p) { return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1.0; });
  const auto outer = sampleField(g, [](const Vec3d& p) { return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1.7; });
  std::vector<double> shell(g.nodeCount());
  for (size_t n = 0; n < shell.size(); ++n) shell[n] = std::max(outer[n], -inner[n]);
  const TriangleMesh ball = meshZeroSet(g, inner), ring = meshZeroSet(g, shell);
  expectClosedOutward(ball);
  expectClosedOutward(ring);
  // Every vertex and triangle of the ball reappears in the shell, reversed.
  std::map<std::array<float, 3>, uint32_t> ring_index;
  for (uint32_t i = 0; i < ring.positions.size(); ++i) ring_index[ring.positions[i]] = i;
  std::set<std::array<uint32_t, 3>> ring_tris;
  for (auto t : ring.triangles) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    ring_tris.insert(t);
  }
  size_t matched = 0;
  for (const auto& t : ball.triangles) {
    std::array<uint32_t, 3> r{};
    bool all = true;
    for (int k = 0; k < 3; ++k) {
      auto it = ring_index.find(ball.positions[t[k]]);
      all = all && it != ring_index.end();
      if (it != ring_index.end()) r[2 - k] = it->second;
    }
    if (!all) continue;
    std::rotate(r.begin(), std::min_element(r.begin(), r.end()), r.end());
    matched += ring_tris.count(r);
  }
  EXPECT_EQ(matched, ball.triangleCount());
  EXPECT_NEAR(ring.signedVolume() + ball.signedVolume(),
              4.0 / 3.0 * std::numbers::pi * 1.7 * 1.7 * 1.7, 0.05 * 4.0 / 3.0 * std::numbers::pi * 1.7 * 1.7 * 1.7);
}

TEST(ImplicitMesher, Deterministic) {
  SampleGrid g = gridAround(Bounds3{{-1, -1, -1}, {1, 1, 1}}, 0.1, 2);
  const auto v = sampleField(g, [](const Vec3d& p) { return p[0] * p[0] + 2 * p[1] * p[1] + 3 * p[2] * p[2] - 0.8; });
  const TriangleMesh a = meshZeroSet(g, v), b = meshZeroSet(g, v);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
}

}  // namespace
}  // namespace dentsim
