// The CPU reference marching-cubes mesher: a generated case table, a sparse walk over brick blocks, welded vertices.
//
// Contents
//   1. The case table, generated once from the per-face rule
//   2. The scalar field: voxel byte -> phi, inside test
//   3. Cell blocks: which 8^3 groups of cells can hold surface, and their voxels with an apron
//   4. Vertices: position, tissue and averaged-gradient normal
//   5. meshVolumeCpu
#include "volume/surface_mesher.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace dentsim {

TriangleMesh SurfaceMesh::geometry() const {
  TriangleMesh m;
  m.positions = positions;
  m.triangles = triangles;
  return m;
}

namespace internal {

// ==== 1. the case table ===========================================================================
// Cube corner c sits at (c & 1, (c >> 1) & 1, (c >> 2) & 1). Edge e joins corner kEdgeCorner[e] to
// that corner plus one step along kEdgeAxis[e]; edges 0..3 run along x, 4..7 along y, 8..11 along z.
constexpr std::array<int, 12> kEdgeCorner{0, 2, 4, 6, 0, 1, 4, 5, 0, 1, 2, 3};
constexpr std::array<int, 12> kEdgeAxis{0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};

constexpr int cornerBit(int c, int axis) { return (c >> axis) & 1; }

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

struct CaseEntry {
  uint8_t triangle_count = 0;
  std::array<std::array<uint8_t, 3>, 12> triangles{};  // cell-edge indices, counter-clockwise from outside
};

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
// phi per voxel byte: the voxel's solid share, counting only `tissue` when one is chosen.
struct FieldTable {
  std::array<float, 256> phi{};
  std::array<bool, 256> inside{};
};

FieldTable makeFieldTable(Material tissue) {
  FieldTable t;
  for (uint32_t b = 0; b < 256; ++b) {
    const Voxel v = Voxel(b);
    const bool counts = tissue == Material::Empty || voxelMaterial(v) == tissue;
    const uint32_t fill = counts ? voxelFill(v) : 0u;
    t.phi[b] = float(fill) / float(DS_FILL_FULL);
    t.inside[b] = 2 * fill > DS_FILL_FULL;  // phi > 0.5 exactly, without float rounding
  }
  return t;
}

// ==== 3. cell blocks =============================================================================
// Cell (i,j,k) has its corners at voxel centres (i..i+1, j..j+1, k..k+1), for i in [-1, dim-1]
// (voxels outside the grid are empty). Cell block (bx,by,bz), bx in [0, brickDim], holds the cells
// with i in [8bx-1, 8bx+6], so its corners lie in bricks bx-1 and bx on each axis.
constexpr int kBlockCells = int(DS_BRICK_DIM);
// The block's voxels are copied with an apron: the normals average gradients over up to 6^3 voxel
// centres around a vertex, and each gradient reads one voxel further out.
constexpr int kApronLo = 5;                                   // voxels below 8bx
constexpr int kLocalDim = kApronLo + kBlockCells + 5;         // 8bx-5 .. 8bx+12
constexpr int kLocalVoxels = kLocalDim * kLocalDim * kLocalDim;

// What a brick holds as far as the surface is concerned.
enum BrickState : uint8_t { kAllOutside = 0, kAllInside = 1, kMixed = 2 };

std::vector<uint8_t> brickStates(const BrickVolume& vol, const FieldTable& field) {
  const size_t bd = vol.brickDim();
  std::vector<uint8_t> states(bd * bd * bd, kAllOutside);
  vol.forEachBrick([&](const BrickView& b) {
    uint8_t s;
    if (b.uniform) {
      s = field.inside[b.value] ? kAllInside : kAllOutside;
    } else {
      const bool first = field.inside[b.voxels[0]];
      s = first ? kAllInside : kAllOutside;
      for (uint32_t i = 1; i < DS_BRICK_VOXELS; ++i)
        if (field.inside[b.voxels[i]] != first) {
          s = kMixed;
          break;
        }
    }
    states[(size_t(b.coord.z) * bd + b.coord.y) * bd + b.coord.x] = s;
  });
  return states;
}

// A cell block can hold surface only if the bricks its corners read are not all on one side.
bool blockActive(const std::vector<uint8_t>& states, int64_t bd, int64_t bx, int64_t by, int64_t bz) {
  int seen = -1;
  for (int64_t z = bz - 1; z <= bz; ++z)
    for (int64_t y = by - 1; y <= by; ++y)
      for (int64_t x = bx - 1; x <= bx; ++x) {
        const bool in_grid = x >= 0 && y >= 0 && z >= 0 && x < bd && y < bd && z < bd;
        const int s = in_grid ? int(states[size_t((z * bd + y) * bd + x)]) : int(kAllOutside);
        if (s == kMixed) return true;
        if (seen >= 0 && s != seen) return true;
        seen = s;
      }
  return false;
}

// The voxels of one cell block and its apron, with phi and central-difference gradients.
struct LocalBlock {
  int64_t base[3] = {0, 0, 0};                // grid voxel of local (0,0,0)
  std::array<Voxel, kLocalVoxels> voxels{};
  std::array<float, kLocalVoxels> phi{};
  std::array<std::array<float, 3>, kLocalVoxels> grad{};  // d(phi)/d(voxel), zero on the outer layer

  static int index(int x, int y, int z) { return (z * kLocalDim + y) * kLocalDim + x; }
};

void loadBlock(const BrickVolume& vol, const FieldTable& field, int64_t bx, int64_t by, int64_t bz,
               LocalBlock& block) {
  const int64_t dim = vol.dim();
  const int64_t b0[3] = {bx * kBlockCells - kApronLo, by * kBlockCells - kApronLo, bz * kBlockCells - kApronLo};
  for (int a = 0; a < 3; ++a) block.base[a] = b0[a];
  // The block spans three bricks per axis; read each brick's view once.
  std::array<BrickView, 27> views{};
  std::array<bool, 27> have{};
  const int64_t brick0[3] = {bx - 1, by - 1, bz - 1};
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) {
        const int64_t c[3] = {brick0[0] + x, brick0[1] + y, brick0[2] + z};
        const int64_t bd = int64_t(vol.brickDim());
        const size_t slot = size_t((z * 3 + y) * 3 + x);
        if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= bd || c[1] >= bd || c[2] >= bd) continue;
        views[slot] = vol.brick(BrickCoord{uint32_t(c[0]), uint32_t(c[1]), uint32_t(c[2])});
        have[slot] = true;
      }
  constexpr int64_t m = DS_BRICK_DIM - 1;
  for (int z = 0; z < kLocalDim; ++z)
    for (int y = 0; y < kLocalDim; ++y)
      for (int x = 0; x < kLocalDim; ++x) {
        const int64_t g[3] = {b0[0] + x, b0[1] + y, b0[2] + z};
        Voxel v = 0;
        if (g[0] >= 0 && g[1] >= 0 && g[2] >= 0 && g[0] < dim && g[1] < dim && g[2] < dim) {
          const size_t slot = size_t((((g[2] >> DS_BRICK_LOG2) - brick0[2]) * 3 + ((g[1] >> DS_BRICK_LOG2) - brick0[1])) * 3 +
                                     ((g[0] >> DS_BRICK_LOG2) - brick0[0]));
          assert(have[slot]);
          const BrickView& view = views[slot];
          v = view.uniform ? view.value
                           : view.voxels[layout::brickCoordToOffset(uint32_t(g[0] & m), uint32_t(g[1] & m),
                                                                    uint32_t(g[2] & m))];
        }
        const int i = LocalBlock::index(x, y, z);
        block.voxels[size_t(i)] = v;
        block.phi[size_t(i)] = field.phi[v];
      }
  for (int z = 1; z + 1 < kLocalDim; ++z)
    for (int y = 1; y + 1 < kLocalDim; ++y)
      for (int x = 1; x + 1 < kLocalDim; ++x) {
        const auto& p = block.phi;
        const auto at = [&](int dx, int dy, int dz) { return p[size_t(LocalBlock::index(x + dx, y + dy, z + dz))]; };
        block.grad[size_t(LocalBlock::index(x, y, z))] = {0.5f * (at(1, 0, 0) - at(-1, 0, 0)),
                                                          0.5f * (at(0, 1, 0) - at(0, -1, 0)),
                                                          0.5f * (at(0, 0, 1) - at(0, 0, -1))};
      }
}

// ==== 4. vertices ================================================================================
// The normal at a vertex on the edge from voxel centre `lo` (local coordinates) along `axis`: the
// mean gradient over the cube of side `side` voxel centres nearest the vertex, negated. Along the
// edge that cube is centred on the edge midpoint for every side. Across the edge the vertex sits on
// a voxel-centre plane, where two cubes tie; both count half, i.e. side+1 centres with the two
// outermost at half weight, so the mean has no half-voxel bias.
Vec3f vertexNormal(const LocalBlock& block, const int lo[3], int axis, int side, const float edge_dir[3]) {
  const int half = side / 2;
  double sum[3] = {0, 0, 0};
  int from[3], to[3];
  for (int a = 0; a < 3; ++a) {
    from[a] = a == axis ? lo[a] - (half - 1) : lo[a] - half;
    to[a] = a == axis ? lo[a] + half : lo[a] + half;
  }
  for (int z = from[2]; z <= to[2]; ++z) {
    const double wz = (axis != 2 && (z == from[2] || z == to[2])) ? 0.5 : 1.0;
    for (int y = from[1]; y <= to[1]; ++y) {
      const double wy = (axis != 1 && (y == from[1] || y == to[1])) ? 0.5 : 1.0;
      for (int x = from[0]; x <= to[0]; ++x) {
        const double wx = (axis != 0 && (x == from[0] || x == to[0])) ? 0.5 : 1.0;
        const auto& g = block.grad[size_t(LocalBlock::index(x, y, z))];
        const double w = wx * wy * wz;
        for (int a = 0; a < 3; ++a) sum[a] -= w * double(g[a]);
      }
    }
  }
  const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
  // A flat field around the vertex (thin features cancelling out) leaves the edge as the best guess.
  if (len < 1e-12) return {edge_dir[0], edge_dir[1], edge_dir[2]};
  return {float(sum[0] / len), float(sum[1] / len), float(sum[2] / len)};
}

}  // namespace internal

// ==== 5. meshVolumeCpu ===========================================================================
Result<SurfaceMesh> meshVolumeCpu(const ToothVolume& tooth, const SurfaceOptions& options, Interrupter& interrupter) {
  using namespace internal;
  int side = 0;
  switch (options.normal_neighbours) {
    case 8: side = 2; break;
    case 64: side = 4; break;
    case 216: side = 6; break;
    default:
      return makeError("surface mesher", "normal_neighbours must be 8, 64 or 216, not " +
                                              std::to_string(options.normal_neighbours));
  }

  const BrickVolume& vol = tooth.voxels;
  const VolumeFrame& frame = tooth.frame;
  const CaseEntry* table = caseTable().data();
  const FieldTable field = makeFieldTable(options.tissue);
  const std::vector<uint8_t> states = brickStates(vol, field);
  const int64_t dim = vol.dim();
  const int64_t bd = vol.brickDim();
  const int64_t edge_stride = dim + 1;  // edge ids count lower voxel coordinates from -1

  SurfaceMesh mesh;
  std::unordered_map<uint64_t, uint32_t> edge_vertex;
  auto block = std::make_unique<LocalBlock>();

  interrupter.start("mesh surface");
  for (int64_t bz = 0; bz <= bd; ++bz) {
    if (!interrupter.progress(double(bz) / double(bd + 1))) {
      interrupter.end();
      return makeError("surface mesher", "cancelled");
    }
    for (int64_t by = 0; by <= bd; ++by)
      for (int64_t bx = 0; bx <= bd; ++bx) {
        if (!blockActive(states, bd, bx, by, bz)) continue;
        loadBlock(vol, field, bx, by, bz, *block);

        // Cells by their lower corner in local coordinates; the last block row stops at dim-1.
        const int64_t cell0[3] = {bx * kBlockCells - 1, by * kBlockCells - 1, bz * kBlockCells - 1};
        const int lo_local = kApronLo - 1;
        const int count[3] = {int(std::min<int64_t>(kBlockCells, dim - cell0[0])),
                              int(std::min<int64_t>(kBlockCells, dim - cell0[1])),
                              int(std::min<int64_t>(kBlockCells, dim - cell0[2]))};
        for (int cz = 0; cz < count[2]; ++cz)
          for (int cy = 0; cy < count[1]; ++cy)
            for (int cx = 0; cx < count[0]; ++cx) {
              const int l[3] = {lo_local + cx, lo_local + cy, lo_local + cz};
              int config = 0;
              for (int c = 0; c < 8; ++c) {
                const Voxel v = block->voxels[size_t(
                    LocalBlock::index(l[0] + cornerBit(c, 0), l[1] + cornerBit(c, 1), l[2] + cornerBit(c, 2)))];
                if (field.inside[v]) config |= 1 << c;
              }
              const CaseEntry& entry = table[config];
              if (entry.triangle_count == 0) continue;

              auto vertexOf = [&](int e) -> uint32_t {
                const int axis = kEdgeAxis[size_t(e)], corner = kEdgeCorner[size_t(e)];
                int a_loc[3] = {l[0] + cornerBit(corner, 0), l[1] + cornerBit(corner, 1), l[2] + cornerBit(corner, 2)};
                int64_t g[3];
                for (int a = 0; a < 3; ++a) g[a] = block->base[a] + a_loc[a];
                const uint64_t id =
                    ((uint64_t(axis) * uint64_t(edge_stride) + uint64_t(g[2] + 1)) * uint64_t(edge_stride) +
                     uint64_t(g[1] + 1)) * uint64_t(edge_stride) + uint64_t(g[0] + 1);
                const auto [it, fresh] = edge_vertex.try_emplace(id, uint32_t(mesh.positions.size()));
                if (!fresh) return it->second;

                int b_loc[3] = {a_loc[0], a_loc[1], a_loc[2]};
                b_loc[axis] += 1;
                const size_t ia = size_t(LocalBlock::index(a_loc[0], a_loc[1], a_loc[2]));
                const size_t ib = size_t(LocalBlock::index(b_loc[0], b_loc[1], b_loc[2]));
                const float pa = block->phi[ia], pb = block->phi[ib];
                const double t = (0.5 - double(pa)) / (double(pb) - double(pa));
                Vec3f pos;
                for (int a = 0; a < 3; ++a) {
                  const double idx = double(g[a]) + 0.5 + (a == axis ? t : 0.0);
                  pos[size_t(a)] = float(frame.origin_mm[size_t(a)] + idx * frame.voxel_mm);
                }
                const bool a_inside = pa > pb;
                const float dir[3] = {axis == 0 ? (a_inside ? 1.f : -1.f) : 0.f,
                                      axis == 1 ? (a_inside ? 1.f : -1.f) : 0.f,
                                      axis == 2 ? (a_inside ? 1.f : -1.f) : 0.f};
                mesh.positions.push_back(pos);
                mesh.normals.push_back(vertexNormal(*block, a_loc, axis, side, dir));
                mesh.tissue.push_back(voxelMaterial(block->voxels[a_inside ? ia : ib]));
                return it->second;
              };
              for (int t = 0; t < entry.triangle_count; ++t) {
                const auto& tri = entry.triangles[size_t(t)];
                mesh.triangles.push_back({vertexOf(tri[0]), vertexOf(tri[1]), vertexOf(tri[2])});
              }
            }
      }
  }
  interrupter.progress(1.0);
  interrupter.end();
  return mesh;
}

}  // namespace dentsim
