// The CPU reference marching-cubes mesher: a generated case table, a sparse walk over brick blocks, welded vertices.
//
// Contents
//   1. The case table, generated once from the per-face rule
//   2. The scalar field: voxel byte -> F (fill counted as solid), inside test
//   3. Cell blocks: which blocks can hold surface, their voxels with an apron and box sums
//   4. Vertices: averaged-gradient normals from box sums, octahedral packing
//   5. Per-block meshing (the GPU's reference) and welding
//   6. meshVolumeCpu
#include "volume/surface_mesher.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "volume/surface_mesher_internal.h"

namespace dentsim {

TriangleMesh SurfaceMesh::geometry() const {
  TriangleMesh m;
  m.positions = positions;
  m.triangles = triangles;
  return m;
}

namespace internal {

// ==== 1. the case table ===========================================================================
// Corners and edges are numbered as surface_mesher_internal.h says.
int edgeBetween(int a, int b) {
  for (int e = 0; e < 12; ++e) {
    const int lo = kEdgeCorner[e], hi = lo | (1 << kEdgeAxis[e]);
    if ((lo == a && hi == b) || (lo == b && hi == a)) return e;
  }
  assert(false && "corners are not adjacent");
  return -1;
}

// Face f = 2 * axis + side holds the corners whose bit `axis` equals `side`; its outward normal is
// +axis for side 1 and -axis for side 0.
bool edgeOnFace(int e, int f) {
  const int axis = f / 2, side = f % 2;
  return kEdgeAxis[e] != axis && cornerBit(kEdgeCorner[e], axis) == side;
}

bool edgesShareFace(int a, int b) {
  for (int f = 0; f < 6; ++f)
    if (edgeOnFace(a, f) && edgeOnFace(b, f)) return true;
  return false;
}

struct Vec3i {
  int v[3];
};

Vec3i cornerPos2(int c) { return {{2 * cornerBit(c, 0), 2 * cornerBit(c, 1), 2 * cornerBit(c, 2)}}; }
// Edge midpoint in doubled cube coordinates, so it stays integral.
Vec3i edgeMid2(int e) {
  Vec3i p = cornerPos2(kEdgeCorner[e]);
  p.v[kEdgeAxis[e]] += 1;
  return p;
}

// Fans a loop from a start vertex whose diagonals do not lie on a cube face. A diagonal on a face
// would also be drawn by the neighbour cell when its loop holds the same two vertices, giving an
// edge of four triangles; a diagonal through the cube interior belongs to this cell alone.
bool fanLoop(const std::vector<int>& loop, CaseEntry& entry) {
  const size_t n = loop.size();
  for (size_t start = 0; start < n; ++start) {
    bool clean = true;
    for (size_t k = 2; k + 1 < n && clean; ++k)
      clean = !edgesShareFace(loop[start], loop[(start + k) % n]);
    if (!clean) continue;
    for (size_t k = 1; k + 1 < n; ++k) {
      entry.triangles[entry.triangle_count++] = {uint8_t(loop[start]), uint8_t(loop[(start + k) % n]),
                                                 uint8_t(loop[(start + k + 1) % n])};
    }
    return true;
  }
  return false;
}

// Builds the case for one corner configuration (bit c set: corner c inside).
CaseEntry buildCase(int config) {
  auto inside = [&](int c) { return ((config >> c) & 1) != 0; };
  std::array<int, 12> next;
  next.fill(-1);

  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2, side = f % 2, u = (axis + 1) % 3, w = (axis + 2) % 3;
    // The face's corners in cyclic order.
    std::array<int, 4> q{};
    const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; ++k) q[size_t(k)] = (side << axis) | (uv[k][0] << u) | (uv[k][1] << w);

    // Segments as (edge, edge, inside corner beside the segment).
    std::vector<std::array<int, 3>> segments;
    std::vector<int> crossing;
    for (int k = 0; k < 4; ++k)
      if (inside(q[size_t(k)]) != inside(q[size_t((k + 1) % 4)]))
        crossing.push_back(edgeBetween(q[size_t(k)], q[size_t((k + 1) % 4)]));
    if (crossing.empty()) continue;
    if (crossing.size() == 2) {
      int in_corner = -1;
      for (int c : q)
        if (inside(c)) in_corner = c;
      segments.push_back({crossing[0], crossing[1], in_corner});
    } else {
      // Ambiguous face: cut each inside corner off by itself, so the inside corners stay apart.
      // The choice reads only this face's corners, so the cell across the face makes the same one.
      assert(crossing.size() == 4);
      for (int k = 0; k < 4; ++k) {
        const int c = q[size_t(k)];
        if (!inside(c)) continue;
        segments.push_back({edgeBetween(q[size_t((k + 3) % 4)], c), edgeBetween(c, q[size_t((k + 1) % 4)]), c});
      }
    }

    // Orient each segment so that, seen from outside the cube, the inside corner lies to its right:
    // the loops then run counter-clockwise seen from the empty side.
    for (auto& s : segments) {
      const Vec3i p = edgeMid2(s[0]), qq = edgeMid2(s[1]), c = cornerPos2(s[2]);
      const int d[3] = {qq.v[0] - p.v[0], qq.v[1] - p.v[1], qq.v[2] - p.v[2]};
      const int r[3] = {c.v[0] - p.v[0], c.v[1] - p.v[1], c.v[2] - p.v[2]};
      const int cross[3] = {d[1] * r[2] - d[2] * r[1], d[2] * r[0] - d[0] * r[2], d[0] * r[1] - d[1] * r[0]};
      const int along_normal = (side ? 1 : -1) * cross[axis];
      assert(along_normal != 0);
      int from = s[0], to = s[1];
      if (along_normal > 0) std::swap(from, to);
      assert(next[size_t(from)] == -1);
      next[size_t(from)] = to;
    }
  }

  // Each crossing edge lies on two faces, so it starts one segment and ends another: the segments
  // close into disjoint loops.
  CaseEntry entry;
  std::array<bool, 12> used{};
  for (int e = 0; e < 12; ++e) {
    if (next[size_t(e)] < 0 || used[size_t(e)]) continue;
    std::vector<int> loop;
    for (int v = e; !used[size_t(v)]; v = next[size_t(v)]) {
      used[size_t(v)] = true;
      loop.push_back(v);
    }
    const bool fanned = fanLoop(loop, entry);
    assert(fanned && "no fan of this loop avoids face diagonals");
    (void)fanned;
  }
  return entry;
}

const std::array<CaseEntry, 256>& caseTable() {
  static const std::array<CaseEntry, 256> table = [] {
    std::array<CaseEntry, 256> t{};
    for (int config = 0; config < 256; ++config) t[size_t(config)] = buildCase(config);
    return t;
  }();
  return table;
}

// ==== 2. the scalar field ========================================================================
FieldTable makeFieldTable(Material tissue) {
  FieldTable t;
  for (uint32_t b = 0; b < 256; ++b) {
    const Voxel v = Voxel(b);
    const bool counts = tissue == Material::Empty || voxelMaterial(v) == tissue;
    const uint32_t fill = counts ? voxelFill(v) : 0u;
    t.fill[b] = fill;
    t.inside[b] = 2 * fill > DS_FILL_FULL;  // phi > 0.5 exactly, without float rounding
  }
  return t;
}

// ==== 3. cell blocks =============================================================================
// Block b's cells have their lower corners at lo + (0..7), lo = 8b - 1 per axis, so its corners lie
// in bricks b-1 and b. It reads voxels 8b-5 .. 8b+12 (local 0..17): the normals average gradients
// over up to 6^3 voxel centres around a vertex, and each gradient reads one voxel further out.
constexpr int kBlockCells = int(DS_MESH_BLOCK_CELLS);
constexpr int kCornerDim = int(DS_MESH_CORNER_DIM);
constexpr int kLocalDim = int(DS_MESH_LOCAL_DIM);
constexpr int kCornerLocal0 = int(DS_MESH_APRON) - 1;  // local index of corner 0 (voxel lo)
constexpr int kLocalVoxels = kLocalDim * kLocalDim * kLocalDim;

// What a brick holds as far as the surface is concerned.
enum BrickState : uint8_t { kAllOutside = 0, kAllInside = 1, kMixed = 2 };

uint8_t brickState(const BrickView& b, const FieldTable& field) {
  if (b.uniform) return field.inside[b.value] ? kAllInside : kAllOutside;
  const bool first = field.inside[b.voxels[0]];
  for (uint32_t i = 1; i < DS_BRICK_VOXELS; ++i)
    if (field.inside[b.voxels[i]] != first) return kMixed;
  return first ? kAllInside : kAllOutside;
}

// A block can hold surface only if the bricks its corners read are not all on one side. `state`
// answers for brick coordinates that may lie outside the grid (outside is empty).
template <class StateOf>
bool blockActiveBy(int64_t bx, int64_t by, int64_t bz, const StateOf& state) {
  int seen = -1;
  for (int64_t z = bz - 1; z <= bz; ++z)
    for (int64_t y = by - 1; y <= by; ++y)
      for (int64_t x = bx - 1; x <= bx; ++x) {
        const int s = state(x, y, z);
        if (s == kMixed) return true;
        if (seen >= 0 && s != seen) return true;
        seen = s;
      }
  return false;
}

// The fill that counts as solid (F), per local voxel, and the raw bytes for the tissue labels.
struct LocalBlock {
  std::array<Voxel, kLocalVoxels> voxels{};
  std::array<uint32_t, kLocalVoxels> sat{};  // inclusive 3-D prefix sums of F
  std::array<uint8_t, kLocalVoxels> fill{};  // F

  static int index(int x, int y, int z) { return (z * kLocalDim + y) * kLocalDim + x; }
  bool inside(int x, int y, int z) const { return 2u * fill[size_t(index(x, y, z))] > DS_FILL_FULL; }
  // Sum of F over the inclusive box [lo, hi] (local coordinates, lo - 1 may be -1).
  int64_t box(const int lo[3], const int hi[3]) const {
    int64_t sum = 0;
    for (int k = 0; k < 8; ++k) {
      const int x = (k & 1) ? hi[0] : lo[0] - 1;
      const int y = (k & 2) ? hi[1] : lo[1] - 1;
      const int z = (k & 4) ? hi[2] : lo[2] - 1;
      if (x < 0 || y < 0 || z < 0) continue;
      const int sign = (((k & 1) ? 0 : 1) + ((k & 2) ? 0 : 1) + ((k & 4) ? 0 : 1)) % 2 ? -1 : 1;
      sum += sign * int64_t(sat[size_t(index(x, y, z))]);
    }
    return sum;
  }
};

void loadBlock(const BrickVolume& vol, const FieldTable& field, const MeshBlock& b, LocalBlock& block) {
  const int64_t dim = vol.dim(), bd = vol.brickDim();
  const int64_t base[3] = {int64_t(b.x) * kBlockCells - int64_t(DS_MESH_APRON),
                           int64_t(b.y) * kBlockCells - int64_t(DS_MESH_APRON),
                           int64_t(b.z) * kBlockCells - int64_t(DS_MESH_APRON)};
  // The block reads bricks b-1 .. b+1 on each axis; read each brick's view once.
  std::array<BrickView, 27> views{};
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) {
        const int64_t c[3] = {int64_t(b.x) - 1 + x, int64_t(b.y) - 1 + y, int64_t(b.z) - 1 + z};
        if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= bd || c[1] >= bd || c[2] >= bd) continue;
        views[size_t((z * 3 + y) * 3 + x)] = vol.brick(BrickCoord{uint32_t(c[0]), uint32_t(c[1]), uint32_t(c[2])});
      }
  constexpr int64_t m = DS_BRICK_DIM - 1;
  for (int z = 0; z < kLocalDim; ++z)
    for (int y = 0; y < kLocalDim; ++y)
      for (int x = 0; x < kLocalDim; ++x) {
        const int64_t g[3] = {base[0] + x, base[1] + y, base[2] + z};
        Voxel v = 0;
        if (g[0] >= 0 && g[1] >= 0 && g[2] >= 0 && g[0] < dim && g[1] < dim && g[2] < dim) {
          const int64_t s[3] = {(g[0] >> DS_BRICK_LOG2) - int64_t(b.x) + 1, (g[1] >> DS_BRICK_LOG2) - int64_t(b.y) + 1,
                                (g[2] >> DS_BRICK_LOG2) - int64_t(b.z) + 1};
          const BrickView& view = views[size_t((s[2] * 3 + s[1]) * 3 + s[0])];
          v = view.uniform ? view.value
                           : view.voxels[layout::brickCoordToOffset(uint32_t(g[0] & m), uint32_t(g[1] & m),
                                                                    uint32_t(g[2] & m))];
        }
        const size_t i = size_t(LocalBlock::index(x, y, z));
        block.voxels[i] = v;
        block.fill[i] = uint8_t(field.fill[v]);
        block.sat[i] = field.fill[v];
      }
  // Prefix sums along x, then y, then z, as the GPU kernel does (exact in integers either way).
  for (int axis = 0; axis < 3; ++axis) {
    const int step = axis == 0 ? 1 : axis == 1 ? kLocalDim : kLocalDim * kLocalDim;
    for (int i = 0; i < kLocalVoxels; ++i) {
      const int coord = axis == 0 ? i % kLocalDim : axis == 1 ? (i / kLocalDim) % kLocalDim : i / (kLocalDim * kLocalDim);
      if (coord > 0) block.sat[size_t(i)] += block.sat[size_t(i - step)];
    }
  }
}

// ==== 4. vertices ================================================================================
// The normal at a vertex on the edge from local voxel p along `axis` is minus the mean gradient over
// the cube of side voxel centres nearest the vertex. Along the edge that cube is centred on the edge
// midpoint; across it the vertex sits on a voxel-centre plane where two cubes tie, and both count
// half (side+1 centres, the outer two at half weight), so the mean has no half-voxel bias. With
// central differences the sum telescopes into box sums of F, computed exactly in integers:
//   N_c = sum over weighted ranges of [Box(range_c + 1) - Box(range_c - 1)].
// Weights are doubled to stay integral: across axes the full range plus the inner one, along the
// edge its one range (counted twice; every component has the same factor 2, which drops out).
std::array<int64_t, 3> normalSums(const LocalBlock& block, const int p[3], int axis, int side) {
  const int h = side / 2;
  int ranges[3][2][2];  // [axis][which][lo,hi]
  int counts[3];
  for (int d = 0; d < 3; ++d) {
    if (d == axis) {
      ranges[d][0][0] = p[d] - h + 1;
      ranges[d][0][1] = p[d] + h;
      counts[d] = 1;
    } else {
      ranges[d][0][0] = p[d] - h;
      ranges[d][0][1] = p[d] + h;
      ranges[d][1][0] = p[d] - h + 1;
      ranges[d][1][1] = p[d] + h - 1;
      counts[d] = 2;
    }
  }
  std::array<int64_t, 3> n{0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    const int u = (c + 1) % 3, w = (c + 2) % 3;
    int64_t sum = 0;
    for (int rc = 0; rc < counts[c]; ++rc)
      for (int ru = 0; ru < counts[u]; ++ru)
        for (int rw = 0; rw < counts[w]; ++rw) {
          int lo[3], hi[3];
          lo[u] = ranges[u][ru][0];
          hi[u] = ranges[u][ru][1];
          lo[w] = ranges[w][rw][0];
          hi[w] = ranges[w][rw][1];
          lo[c] = ranges[c][rc][0] + 1;
          hi[c] = ranges[c][rc][1] + 1;
          const int64_t plus = block.box(lo, hi);
          lo[c] -= 2;
          hi[c] -= 2;
          sum += plus - block.box(lo, hi);
        }
    n[size_t(c)] = sum;
  }
  return n;
}

// Octahedral mapping of a unit vector to two 12-bit fractions.
uint32_t packOctahedral(Vec3f n) {
  const float l1 = std::fabs(n[0]) + std::fabs(n[1]) + std::fabs(n[2]);
  float u = n[0] / l1, v = n[1] / l1;
  if (n[2] < 0.f) {
    const float uu = (1.f - std::fabs(v)) * (u >= 0.f ? 1.f : -1.f);
    const float vv = (1.f - std::fabs(u)) * (v >= 0.f ? 1.f : -1.f);
    u = uu;
    v = vv;
  }
  const auto q = [](float x) { return uint32_t(std::lround(std::clamp(x * 0.5f + 0.5f, 0.f, 1.f) * 4095.f)); };
  return q(u) | (q(v) << 12);
}

layout::MeshVertex meshVertex(const int64_t g[3], int axis, int fa, int fb, const std::array<int64_t, 3>& n, Voxel in,
                              Voxel out, Material tissue, Vec3f* float_normal) {
  // t in [1/32, 31/32]: fill is integral, so the level 15.5 never sits on a voxel centre.
  const float t = float(int(DS_FILL_FULL) - 2 * fa) / float(2 * (fb - fa));
  float pos[3];
  for (int a = 0; a < 3; ++a) pos[a] = float(g[a]) + 0.5f;
  pos[axis] = pos[axis] + t;
  layout::MeshVertex v{};
  v.x = pos[0];
  v.y = pos[1];
  v.z = pos[2];

  // N grows inwards (fill rises into the solid); the normal points out.
  const double len = std::sqrt(double(n[0]) * double(n[0]) + double(n[1]) * double(n[1]) + double(n[2]) * double(n[2]));
  Vec3f normal;
  if (len == 0.0) {  // a flat field (thin features cancelling): the edge is the best guess
    normal = {0.f, 0.f, 0.f};
    normal[size_t(axis)] = 2 * fa > int(DS_FILL_FULL) ? 1.f : -1.f;
  } else {
    normal = {float(-double(n[0]) / len), float(-double(n[1]) / len), float(-double(n[2]) / len)};
  }
  // Across: the other tissue at an interface of one tissue's surface; the outer surface (and every
  // vertex of the all-tissue surface) has empty space across.
  const Material out_material = voxelMaterial(out);
  const Material across = tissue != Material::Empty && out_material != tissue ? out_material : Material::Empty;
  v.packed = packOctahedral(normal) | uint32_t(voxelMaterial(in)) << 24 | uint32_t(across) << 28;
  if (float_normal) *float_normal = normal;
  return v;
}

}  // namespace internal

// ==== 5. per-block meshing =======================================================================
Vec3f unpackMeshNormal(uint32_t packed) {
  float u = float(packed & 4095u) / 4095.f * 2.f - 1.f;
  float v = float((packed >> 12) & 4095u) / 4095.f * 2.f - 1.f;
  const float z = 1.f - std::fabs(u) - std::fabs(v);
  if (z < 0.f) {
    const float uu = (1.f - std::fabs(v)) * (u >= 0.f ? 1.f : -1.f);
    const float vv = (1.f - std::fabs(u)) * (v >= 0.f ? 1.f : -1.f);
    u = uu;
    v = vv;
  }
  const float len = std::sqrt(u * u + v * v + z * z);
  return {u / len, v / len, z / len};
}

std::vector<uint32_t> packedMeshCaseTable() {
  const auto& table = internal::caseTable();
  std::vector<uint32_t> words(256 * DS_MESH_CASE_WORDS, 0u);
  for (size_t c = 0; c < 256; ++c) {
    const auto& e = table[c];
    uint32_t* w = &words[c * DS_MESH_CASE_WORDS];
    w[0] = e.triangle_count;
    for (uint32_t t = 0; t < e.triangle_count; ++t) {
      const uint32_t tri = uint32_t(e.triangles[t][0]) | uint32_t(e.triangles[t][1]) << 4 | uint32_t(e.triangles[t][2]) << 8;
      w[1 + t / 2] |= tri << (12 * (t % 2));
    }
  }
  return words;
}

std::vector<MeshBlock> activeMeshBlocks(const BrickVolume& vol, Material tissue) {
  using namespace internal;
  const FieldTable field = makeFieldTable(tissue);
  const int64_t bd = vol.brickDim();
  std::vector<uint8_t> states(size_t(bd * bd * bd), kAllOutside);
  vol.forEachBrick([&](const BrickView& b) {
    states[(size_t(b.coord.z) * size_t(bd) + b.coord.y) * size_t(bd) + b.coord.x] = brickState(b, field);
  });
  const auto state = [&](int64_t x, int64_t y, int64_t z) -> int {
    if (x < 0 || y < 0 || z < 0 || x >= bd || y >= bd || z >= bd) return kAllOutside;
    return states[size_t((z * bd + y) * bd + x)];
  };
  std::vector<MeshBlock> blocks;
  for (int64_t z = 0; z <= bd; ++z)
    for (int64_t y = 0; y <= bd; ++y)
      for (int64_t x = 0; x <= bd; ++x)
        if (blockActiveBy(x, y, z, state)) blocks.push_back({uint32_t(x), uint32_t(y), uint32_t(z)});
  return blocks;
}

std::vector<bool> meshBlocksActive(const BrickVolume& vol, Material tissue, std::span<const MeshBlock> candidates) {
  using namespace internal;
  const FieldTable field = makeFieldTable(tissue);
  const int64_t bd = vol.brickDim();
  std::unordered_map<uint64_t, uint8_t> cache;
  const auto state = [&](int64_t x, int64_t y, int64_t z) -> int {
    if (x < 0 || y < 0 || z < 0 || x >= bd || y >= bd || z >= bd) return kAllOutside;
    const uint64_t key = (uint64_t(z) * uint64_t(bd) + uint64_t(y)) * uint64_t(bd) + uint64_t(x);
    auto [it, fresh] = cache.try_emplace(key, uint8_t(0));
    if (fresh) it->second = brickState(vol.brick(BrickCoord{uint32_t(x), uint32_t(y), uint32_t(z)}), field);
    return it->second;
  };
  std::vector<bool> active(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i)
    active[i] = blockActiveBy(candidates[i].x, candidates[i].y, candidates[i].z, state);
  return active;
}

std::vector<MeshBlock> blocksReadingBricks(const BrickVolume& vol, std::span<const BrickCoord> bricks) {
  const int64_t last = vol.brickDim();  // blocks run 0..brickDim
  std::vector<uint32_t> packed;
  packed.reserve(bricks.size() * 27);
  for (const BrickCoord& c : bricks)
    for (int64_t dz = -1; dz <= 1; ++dz)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          const int64_t x = int64_t(c.x) + dx, y = int64_t(c.y) + dy, z = int64_t(c.z) + dz;
          if (x < 0 || y < 0 || z < 0 || x > last || y > last || z > last) continue;
          packed.push_back(layout::meshBlockPack(uint32_t(x), uint32_t(y), uint32_t(z)));
        }
  // Packed order is z, then y, then x: the same order as activeMeshBlocks.
  std::sort(packed.begin(), packed.end());
  packed.erase(std::unique(packed.begin(), packed.end()), packed.end());
  std::vector<MeshBlock> out;
  out.reserve(packed.size());
  for (uint32_t p : packed) out.push_back(MeshBlock::unpack(p));
  return out;
}

namespace {

BlockMesh meshBlockWith(const BrickVolume& vol, const internal::FieldTable& field, Material tissue, MeshBlock b,
                        uint32_t side, internal::LocalBlock& block, std::vector<Vec3f>* float_normals) {
  using namespace internal;
  loadBlock(vol, field, b, block);
  BlockMesh out;
  out.block = b;
  const int64_t lo[3] = {int64_t(b.x) * kBlockCells - 1, int64_t(b.y) * kBlockCells - 1, int64_t(b.z) * kBlockCells - 1};
  std::array<uint16_t, DS_MESH_EDGES> vertex_of{};
  constexpr int c0 = kCornerLocal0;
  for (int cz = 0; cz < kCornerDim; ++cz)
    for (int cy = 0; cy < kCornerDim; ++cy)
      for (int cx = 0; cx < kCornerDim; ++cx)
        for (int axis = 0; axis < 3; ++axis) {
          const int c[3] = {cx, cy, cz};
          if (c[axis] >= kBlockCells) continue;
          const int p[3] = {c0 + cx, c0 + cy, c0 + cz};
          int q[3] = {p[0], p[1], p[2]};
          ++q[axis];
          const bool a_in = block.inside(p[0], p[1], p[2]);
          if (a_in == block.inside(q[0], q[1], q[2])) continue;
          vertex_of[size_t(((cz * kCornerDim + cy) * kCornerDim + cx) * 3 + axis)] = uint16_t(out.vertices.size());

          const int ip = LocalBlock::index(p[0], p[1], p[2]), iq = LocalBlock::index(q[0], q[1], q[2]);
          const int64_t g[3] = {lo[0] + c[0], lo[1] + c[1], lo[2] + c[2]};
          const std::array<int64_t, 3> n = normalSums(block, p, axis, int(side));
          Vec3f normal;
          out.vertices.push_back(meshVertex(g, axis, block.fill[size_t(ip)], block.fill[size_t(iq)], n,
                                            block.voxels[size_t(a_in ? ip : iq)], block.voxels[size_t(a_in ? iq : ip)],
                                            tissue, &normal));
          if (float_normals) float_normals->push_back(normal);
        }

  const CaseEntry* table = caseTable().data();
  for (int cz = 0; cz < kBlockCells; ++cz)
    for (int cy = 0; cy < kBlockCells; ++cy)
      for (int cx = 0; cx < kBlockCells; ++cx) {
        int config = 0;
        for (int k = 0; k < 8; ++k)
          if (block.inside(c0 + cx + cornerBit(k, 0), c0 + cy + cornerBit(k, 1), c0 + cz + cornerBit(k, 2)))
            config |= 1 << k;
        const CaseEntry& entry = table[config];
        for (int t = 0; t < entry.triangle_count; ++t)
          for (int k = 0; k < 3; ++k) {
            const int e = entry.triangles[size_t(t)][size_t(k)];
            const int corner = kEdgeCorner[size_t(e)];
            const int x = cx + cornerBit(corner, 0), y = cy + cornerBit(corner, 1), z = cz + cornerBit(corner, 2);
            out.indices.push_back(vertex_of[size_t(((z * kCornerDim + y) * kCornerDim + x) * 3 + kEdgeAxis[size_t(e)])]);
          }
      }
  return out;
}

}  // namespace

BlockMesh meshBlockCpu(const BrickVolume& vol, MeshBlock b, Material tissue, uint32_t side) {
  auto block = std::make_unique<internal::LocalBlock>();
  return meshBlockWith(vol, internal::makeFieldTable(tissue), tissue, b, side, *block, nullptr);
}

namespace {

// Welds one block into `mesh`. A vertex lies strictly inside its lattice edge (t in [1/32, 31/32]),
// so its position names the edge: the axis is the coordinate off the voxel-centre lattice and the
// lower corner its floor. Copies of a face vertex in two blocks map to the same edge.
class BlockWelder {
 public:
  BlockWelder(SurfaceMesh& mesh, const VolumeFrame& frame) : mesh_(mesh), frame_(frame) {}

  void add(const BlockMesh& b, const std::vector<Vec3f>* float_normals) {
    ids_.resize(b.vertices.size());
    for (size_t k = 0; k < b.vertices.size(); ++k) {
      const layout::MeshVertex& v = b.vertices[k];
      const double c[3] = {double(v.x) - 0.5, double(v.y) - 0.5, double(v.z) - 0.5};
      int axis = 0;
      for (int a = 0; a < 3; ++a)
        if (std::fabs(c[a] - std::round(c[a])) > 1.0 / 64.0) axis = a;
      const uint64_t stride = uint64_t(frame_.dim()) + 2;
      uint64_t g[3];
      for (int a = 0; a < 3; ++a) g[a] = uint64_t(int64_t(a == axis ? std::floor(c[a]) : std::round(c[a])) + 1);
      const uint64_t id = ((uint64_t(axis) * stride + g[2]) * stride + g[1]) * stride + g[0];
      auto [it, fresh] = edge_vertex_.try_emplace(id, uint32_t(mesh_.positions.size()));
      if (fresh) {
        mesh_.positions.push_back({float(frame_.origin_mm[0] + double(v.x) * frame_.voxel_mm),
                                   float(frame_.origin_mm[1] + double(v.y) * frame_.voxel_mm),
                                   float(frame_.origin_mm[2] + double(v.z) * frame_.voxel_mm)});
        mesh_.normals.push_back(float_normals ? (*float_normals)[k] : unpackMeshNormal(v.packed));
        mesh_.tissue.push_back(Material(layout::meshVertexTissue(v.packed)));
        mesh_.across.push_back(Material(layout::meshVertexAcross(v.packed)));
      }
      ids_[k] = it->second;
    }
    for (size_t t = 0; t + 2 < b.indices.size(); t += 3)
      mesh_.triangles.push_back({ids_[b.indices[t]], ids_[b.indices[t + 1]], ids_[b.indices[t + 2]]});
  }

 private:
  SurfaceMesh& mesh_;
  const VolumeFrame& frame_;
  std::unordered_map<uint64_t, uint32_t> edge_vertex_;
  std::vector<uint32_t> ids_;
};

}  // namespace

SurfaceMesh weldBlockMeshes(std::span<const BlockMesh> blocks, const VolumeFrame& frame) {
  SurfaceMesh mesh;
  BlockWelder welder(mesh, frame);
  for (const BlockMesh& b : blocks) welder.add(b, nullptr);
  return mesh;
}

// ==== 6. meshVolumeCpu ===========================================================================
Result<SurfaceMesh> meshVolumeCpu(const ToothVolume& tooth, const SurfaceOptions& options, Interrupter& interrupter) {
  const uint32_t side = normalBoxSide(options.normals);
  const internal::FieldTable field = internal::makeFieldTable(options.tissue);
  const std::vector<MeshBlock> blocks = activeMeshBlocks(tooth.voxels, options.tissue);
  auto local = std::make_unique<internal::LocalBlock>();
  const VolumeFrame& frame = tooth.frame;

  SurfaceMesh mesh;
  BlockWelder welder(mesh, frame);
  std::vector<Vec3f> normals;  // full precision, not the packed ones the GPU stores
  interrupter.start("mesh surface");
  for (size_t i = 0; i < blocks.size(); ++i) {
    if (!interrupter.progress(double(i) / double(blocks.size()))) {
      interrupter.end();
      return makeError("surface mesher", "cancelled");
    }
    normals.clear();
    welder.add(meshBlockWith(tooth.voxels, field, options.tissue, blocks[i], side, *local, &normals), &normals);
  }
  interrupter.progress(1.0);
  interrupter.end();
  return mesh;
}

}  // namespace dentsim
