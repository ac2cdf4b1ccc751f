// Marching tetrahedra over a regular lattice (see implicit_mesher.h for the conventions).
#include "model/implicit_mesher.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <unordered_map>

namespace dentsim {
namespace {

// A crossing never sits closer than this fraction of its edge to a node, so vertices on different
// edges of one node stay distinct after rounding to float (and welding cannot merge them).
constexpr double kMinEdgeFraction = 1e-3;
// What an exact zero becomes: positive, far below any field's resolution [field units].
constexpr double kZeroNudge = 1e-12;

// Face of a positively oriented tetrahedron opposite each corner, counter-clockwise from outside.
constexpr int kOppositeFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// The six Kuhn tetrahedra of a cube as corner bitmasks (bit 0 = +x, 1 = +y, 2 = +z): one monotone
// path 0 -> 7 per axis order, reordered once so that every tetrahedron is positively oriented.
struct KuhnTets {
  std::array<std::array<int, 4>, 6> corners{};
  KuhnTets() {
    const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int t = 0; t < 6; ++t) {
      const int a = 1 << orders[t][0], b = 1 << orders[t][1];
      std::array<int, 4> c{0, a, a | b, 7};
      // det(e_a, e_b, e_c) is the sign of the axis permutation; an odd one is turned by a swap.
      const bool even = (orders[t][0] + 1) % 3 == orders[t][1];
      if (!even) std::swap(c[1], c[2]);
      corners[t] = c;
    }
  }
};

int popcount3(int bits) { return (bits & 1) + ((bits >> 1) & 1) + ((bits >> 2) & 1); }

// Parity of a permutation of {0,1,2,3}: true when even.
bool evenPermutation(const std::array<int, 4>& p) {
  int inversions = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) inversions += p[a] > p[b] ? 1 : 0;
  return inversions % 2 == 0;
}

class TetMesher {
 public:
  TetMesher(const SampleGrid& grid, std::span<const double> values) : grid_(grid), values_(values) {}

  TriangleMesh run() {
    const KuhnTets kuhn;
    const int nx = grid_.nodes[0], ny = grid_.nodes[1], nz = grid_.nodes[2];
    for (int k = 0; k + 1 < nz; ++k)
      for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
          cell_ = {i, j, k};
          int inside = 0;
          for (int c = 0; c < 8; ++c) {
            cornerValue_[c] = valueAt(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
            inside += cornerValue_[c] < 0.0 ? 1 : 0;
          }
          if (inside == 0 || inside == 8) continue;
          for (const auto& tet : kuhn.corners) polygonizeTet(tet);
        }
    return std::move(mesh_);
  }

 private:
  // Outer-layer nodes count as outside whatever their value, so that the surface closes.
  double valueAt(int i, int j, int k) const {
    const double v = values_[grid_.index(i, j, k)];
    const bool border = i == 0 || j == 0 || k == 0 || i == grid_.nodes[0] - 1 || j == grid_.nodes[1] - 1 ||
                        k == grid_.nodes[2] - 1;
    return border ? std::max(v, kZeroNudge) : v;
  }

  // The vertex where the field crosses the edge between cube corners ca and cb (one a subset of the other).
  uint32_t edgeVertex(int ca, int cb) {
    const int lo = popcount3(ca) < popcount3(cb) ? ca : cb;
    const int hi = lo == ca ? cb : ca;
    const int dir = lo ^ hi;
    assert((lo & hi) == lo && dir != 0);
    const int i = cell_[0] + (lo & 1), j = cell_[1] + ((lo >> 1) & 1), k = cell_[2] + ((lo >> 2) & 1);
    const uint64_t key = uint64_t(grid_.index(i, j, k)) * 8u + uint64_t(dir);
    auto [it, inserted] = vertexOfEdge_.try_emplace(key, uint32_t(mesh_.positions.size()));
    if (inserted) {
      const double va = cornerValue_[lo], vb = cornerValue_[hi];
      double t = va / (va - vb);
      t = std::clamp(t, kMinEdgeFraction, 1.0 - kMinEdgeFraction);
      const Vec3d pa = grid_.position(i, j, k);
      const double step = t * grid_.spacing;
      mesh_.positions.push_back({float(pa[0] + ((dir & 1) ? step : 0.0)), float(pa[1] + ((dir & 2) ? step : 0.0)),
                                 float(pa[2] + ((dir & 4) ? step : 0.0))});
      keyOfVertex_.push_back(key);
    }
    return it->second;
  }

  void polygonizeTet(const std::array<int, 4>& c) {
    std::array<int, 4> in{}, out{};
    int n_in = 0, n_out = 0;
    for (int v = 0; v < 4; ++v) {
      if (cornerValue_[c[v]] < 0.0) in[n_in++] = v;
      else out[n_out++] = v;
    }
    if (n_in == 0 || n_out == 0) return;
    if (n_in == 1 || n_out == 1) {
      // One corner cut off: the triangle faces away from a lone inside corner, toward a lone outside one.
      const int a = n_in == 1 ? in[0] : out[0];
      const int* f = kOppositeFace[a];
      uint32_t v0 = edgeVertex(c[a], c[f[0]]), v1 = edgeVertex(c[a], c[f[1]]), v2 = edgeVertex(c[a], c[f[2]]);
      if (n_in == 3) std::swap(v1, v2);
      mesh_.triangles.push_back({v0, v1, v2});
      return;
    }
    // Two in (i, j), two out (k, l): the quad ik, il, jl, jk faces outward when (i, j, k, l) is an
    // even permutation of the positively oriented corners.
    const int i = in[0], j = in[1], k = out[0], l = out[1];
    std::array<uint32_t, 4> q{edgeVertex(c[i], c[k]), edgeVertex(c[i], c[l]), edgeVertex(c[j], c[l]),
                              edgeVertex(c[j], c[k])};
    if (!evenPermutation({i, j, k, l})) std::swap(q[1], q[3]);
    // The diagonal through the vertex of the smallest edge key depends only on the four edges, so
    // a field and its negation split the quad the same way.
    int m = 0;
    for (int v = 1; v < 4; ++v)
      if (keyOfVertex_[q[v]] < keyOfVertex_[q[m]]) m = v;
    const int s = m % 2;
    mesh_.triangles.push_back({q[s], q[s + 1], q[(s + 2) % 4]});
    mesh_.triangles.push_back({q[s], q[(s + 2) % 4], q[(s + 3) % 4]});
  }

  const SampleGrid& grid_;
  std::span<const double> values_;
  std::array<int, 3> cell_{};
  std::array<double, 8> cornerValue_{};
  // Only looked up, never iterated, so its order cannot reach the output.
  std::unordered_map<uint64_t, uint32_t> vertexOfEdge_;
  std::vector<uint64_t> keyOfVertex_;
  TriangleMesh mesh_;
};

}  // namespace

SampleGrid gridAround(const Bounds3& box, double spacing, int pad_cells) {
  assert(!box.empty() && spacing > 0.0 && pad_cells >= 1);
  SampleGrid g;
  g.spacing = spacing;
  for (int a = 0; a < 3; ++a) {
    g.origin[a] = box.lo[a] - spacing * pad_cells;
    g.nodes[a] = int(std::ceil((box.hi[a] - box.lo[a]) / spacing)) + 2 * pad_cells + 1;
  }
  return g;
}

std::vector<double> sampleField(const SampleGrid& grid, const std::function<double(const Vec3d&)>& field) {
  std::vector<double> values(grid.nodeCount());
  for (int k = 0; k < grid.nodes[2]; ++k)
    for (int j = 0; j < grid.nodes[1]; ++j)
      for (int i = 0; i < grid.nodes[0]; ++i) {
        const double v = field(grid.position(i, j, k));
        values[grid.index(i, j, k)] = v == 0.0 ? kZeroNudge : v;
      }
  return values;
}

TriangleMesh meshZeroSet(const SampleGrid& grid, std::span<const double> values) {
  assert(values.size() == grid.nodeCount());
  assert(grid.nodes[0] >= 2 && grid.nodes[1] >= 2 && grid.nodes[2] >= 2 && grid.spacing > 0.0);
  return TetMesher(grid, values).run();
}

}  // namespace dentsim
