// Welding and topology checks of triangle meshes.
#include "io/mesh_topology.h"

#include <algorithm>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace dentsim {

namespace {

struct PositionKey {
  uint32_t bits[3];
  bool operator==(const PositionKey& o) const {
    return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
  }
};

struct PositionHash {
  size_t operator()(const PositionKey& k) const {
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (uint32_t b : k.bits) h = (h ^ b) * 0x100000001b3ull;
    return size_t(h ^ (h >> 29));
  }
};

PositionKey keyOf(const Vec3f& p) {
  PositionKey k{};
  for (int a = 0; a < 3; ++a) {
    const float v = p[a] == 0.0f ? 0.0f : p[a];  // one key for +0 and -0
    std::memcpy(&k.bits[a], &v, sizeof v);
  }
  return k;
}

}  // namespace

std::string MeshTopology::orientation() const {
  if (!consistent()) return "inconsistent";
  return signed_volume_mm3 < 0.0 ? "inward" : "outward";
}

uint64_t weldVertices(TriangleMesh& mesh) {
  std::unordered_map<PositionKey, uint32_t, PositionHash> first;
  first.reserve(mesh.positions.size());
  std::vector<uint32_t> remap(mesh.positions.size());
  std::vector<Vec3f> welded;
  welded.reserve(mesh.positions.size() / 4 + 8);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    auto [it, inserted] = first.try_emplace(keyOf(mesh.positions[i]), uint32_t(welded.size()));
    if (inserted) welded.push_back(mesh.positions[i]);
    remap[i] = it->second;
  }
  uint64_t dropped = 0;
  size_t out = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    std::array<uint32_t, 3> tri = mesh.triangles[t];
    for (uint32_t& c : tri) c = remap[c];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      ++dropped;
      continue;
    }
    mesh.triangles[out++] = tri;
  }
  mesh.triangles.resize(out);
  mesh.positions = std::move(welded);
  return dropped;
}

MeshTopology analyzeTopology(const TriangleMesh& mesh) {
  MeshTopology topo;
  // Each directed half-edge as (min, max, direction); sorting groups the uses of an edge.
  struct HalfEdge {
    uint64_t key;   // min << 32 | max
    int8_t forward; // +1 when the triangle runs min -> max
  };
  std::vector<HalfEdge> half;
  half.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      ++topo.degenerate_triangles;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[k], b = t[(k + 1) % 3];
      const uint32_t lo = std::min(a, b), hi = std::max(a, b);
      half.push_back({(uint64_t(lo) << 32) | hi, int8_t(a < b ? 1 : -1)});
    }
  }
  std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) { return x.key < y.key; });
  for (size_t i = 0; i < half.size();) {
    size_t j = i;
    int net = 0;
    while (j < half.size() && half[j].key == half[i].key) net += half[j++].forward;
    const size_t uses = j - i;
    ++topo.edges;
    if (uses == 1) ++topo.open_edges;
    else if (uses > 2) ++topo.nonmanifold_edges;
    else if (net != 0) ++topo.flipped_edges;
    i = j;
  }
  topo.signed_volume_mm3 = mesh.signedVolume();
  return topo;
}

}  // namespace dentsim
