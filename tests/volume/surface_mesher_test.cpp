// CPU marching cubes: every corner case closed, random volumes closed, sphere area, volume and normals, tissues.
#include "volume/surface_mesher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <random>

#include "io/mesh_topology.h"

namespace dentsim {
namespace {

// Sanitizer and unoptimised builds draw fewer random blocks.
#if defined(__SANITIZE_ADDRESS__) || !defined(NDEBUG)
constexpr bool kSlowBuild = true;
#else
constexpr bool kSlowBuild = false;
#endif

ToothVolume makeTooth(int level, double voxel_mm = 0.1) {
  return ToothVolume{VolumeFrame::axisAligned(level, voxel_mm, {-1.0, 2.0, 0.5}), BrickVolume(level)};
}

SurfaceMesh meshOf(const ToothVolume& tooth, SurfaceOptions options = {}) {
  auto r = meshVolumeCpu(tooth, options);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.message());
  return r.ok() ? std::move(r).value() : SurfaceMesh{};
}

// Euler characteristic V - E + F of a closed triangle mesh (E = 3F/2): 2 per sphere-like shell.
int64_t eulerCharacteristic(const SurfaceMesh& m) {
  return int64_t(m.positions.size()) - int64_t(m.triangles.size()) / 2;
}

// Closed, 2-manifold, consistently wound and enclosing positive volume; returns the topology.
MeshTopology expectWatertight(const SurfaceMesh& m, const std::string& what) {
  EXPECT_EQ(m.normals.size(), m.positions.size()) << what;
  EXPECT_EQ(m.tissue.size(), m.positions.size()) << what;
  const MeshTopology t = analyzeTopology(m.geometry());
  EXPECT_EQ(t.open_edges, 0u) << what;
  EXPECT_EQ(t.nonmanifold_edges, 0u) << what;
  EXPECT_EQ(t.flipped_edges, 0u) << what;
  EXPECT_EQ(t.degenerate_triangles, 0u) << what;
  EXPECT_EQ(m.triangles.size() % 2, 0u) << what;  // a closed triangle mesh has 3F/2 edges
  if (!m.triangles.empty()) {
    EXPECT_GT(t.signed_volume_mm3, 0.0) << what;
  }
  return t;
}

// ---- analytic solids, voxelized by exact coverage ----------------------------------------------
// Signed distance in voxel units (negative inside); voxel (i,j,k) covers [i, i+1) etc.
using Sdf = std::function<double(double, double, double)>;

// Sets each voxel to `m` with fill = its covered share (8^3 point samples) rounded to 1/31; binary:
// full where that share is over one half, else empty (the paper's binary octree).
void fillCoverage(BrickVolume& vol, const Sdf& sdf, Material m, bool binary = false) {
  const uint32_t bd = vol.brickDim();
  const double brick_reach = 4.0 * std::sqrt(3.0) + 1e-9;  // half-diagonal of a brick [voxels]
  const double voxel_reach = 0.5 * std::sqrt(3.0) + 1e-9;
  std::array<Voxel, DS_BRICK_VOXELS> buf{};
  for (uint32_t bz = 0; bz < bd; ++bz)
    for (uint32_t by = 0; by < bd; ++by)
      for (uint32_t bx = 0; bx < bd; ++bx) {
        const double d = sdf(8.0 * bx + 4, 8.0 * by + 4, 8.0 * bz + 4);
        if (d > brick_reach) continue;
        if (d < -brick_reach) {
          vol.setBrickUniform({bx, by, bz}, makeVoxel(m));
          continue;
        }
        for (uint32_t z = 0; z < 8; ++z)
          for (uint32_t y = 0; y < 8; ++y)
            for (uint32_t x = 0; x < 8; ++x) {
              const double cx = 8.0 * bx + x + 0.5, cy = 8.0 * by + y + 0.5, cz = 8.0 * bz + z + 0.5;
              const double dc = sdf(cx, cy, cz);
              uint32_t fill = 0;
              if (dc < -voxel_reach) {
                fill = DS_FILL_FULL;
              } else if (dc <= voxel_reach) {
                int count = 0;
                for (int sz = 0; sz < 8; ++sz)
                  for (int sy = 0; sy < 8; ++sy)
                    for (int sx = 0; sx < 8; ++sx)
                      count += sdf(cx - 0.5 + (sx + 0.5) / 8, cy - 0.5 + (sy + 0.5) / 8, cz - 0.5 + (sz + 0.5) / 8) < 0;
                fill = uint32_t(std::lround(double(count) * DS_FILL_FULL / 512.0));
                if (binary) fill = 2 * fill > DS_FILL_FULL ? DS_FILL_FULL : 0u;
              }
              buf[layout::brickCoordToOffset(x, y, z)] = fill ? makeVoxel(m, fill) : Voxel(0);
            }
        vol.setBrick({bx, by, bz}, buf.data());
      }
}

Sdf sphereSdf(double cx, double cy, double cz, double r) {
  // sqrt rather than std::hypot: the sub-sampling calls this a hundred million times at level 8.
  return [=](double x, double y, double z) {
    return std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz)) - r;
  };
}

Sdf torusSdf(double cx, double cy, double cz, double R, double r) {
  return [=](double x, double y, double z) {
    const double rho = std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy)) - R;
    return std::sqrt(rho * rho + (z - cz) * (z - cz)) - r;
  };
}

// Mesh position [mm] to voxel coordinates, where voxel i covers [i, i+1).
std::array<double, 3> toVoxel(const ToothVolume& t, const Vec3f& p) {
  std::array<double, 3> v;
  for (size_t a = 0; a < 3; ++a) v[a] = (double(p[a]) - t.frame.origin_mm[a]) / t.frame.voxel_mm;
  return v;
}

double surfaceArea(const SurfaceMesh& m) {
  double area = 0;
  for (const auto& t : m.triangles) {
    const Vec3f &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    area += 0.5 * std::hypot(u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]);
  }
  return area;
}

// Mean angle [deg] between the mesh normals and an analytic normal field (voxel coordinates).
double meanNormalErrorDeg(const ToothVolume& t, const SurfaceMesh& m,
                          const std::function<std::array<double, 3>(std::array<double, 3>)>& truth) {
  double sum = 0;
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const auto n = truth(toVoxel(t, m.positions[i]));
    const double len = std::hypot(n[0], n[1], n[2]);
    double dot = 0;
    for (size_t a = 0; a < 3; ++a) dot += n[a] / len * double(m.normals[i][a]);
    sum += std::acos(std::clamp(dot, -1.0, 1.0));
  }
  return sum / double(m.positions.size()) * 180.0 / std::numbers::pi;
}

// ---- 1. the case table ---------------------------------------------------------------------------

TEST(SurfaceMesher, OneFullVoxelIsAnOctahedron) {
  // The voxel's six neighbours along the axes are empty, so each of its six edges to them carries a
  // vertex half-way; the eight cells around the voxel centre each cut one corner: eight triangles.
  ToothVolume t = makeTooth(3, 1.0);
  t.voxels.setVoxel(3, 4, 5, makeVoxel(Material::Enamel));
  const SurfaceMesh m = meshOf(t);
  EXPECT_EQ(m.positions.size(), 6u);
  EXPECT_EQ(m.triangles.size(), 8u);
  const MeshTopology topo = expectWatertight(m, "octahedron");
  EXPECT_NEAR(topo.signed_volume_mm3, 4.0 / 3.0 * 0.125, 1e-6);  // octahedron of half-diagonal 0.5
  for (Material mat : m.tissue) EXPECT_EQ(mat, Material::Enamel);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    // Each normal points from the voxel centre to its vertex.
    const auto v = toVoxel(t, m.positions[i]);
    const double d[3] = {v[0] - 3.5, v[1] - 4.5, v[2] - 5.5};
    const double len = std::hypot(d[0], d[1], d[2]);
    for (size_t a = 0; a < 3; ++a) EXPECT_NEAR(double(m.normals[i][a]), d[a] / len, 1e-6);
  }
}

TEST(SurfaceMesher, EveryCornerConfigurationIsClosedAndOutward) {
  // All 256 inside/outside patterns of one cell's eight voxels, with full and partial fills, alone
  // in an empty grid and touching the grid's corner (where the cells outside see empty).
  std::mt19937 rng(7);
  for (int partial = 0; partial < 2; ++partial)
    for (uint32_t offset : {0u, 3u, 6u})
      for (int config = 0; config < 256; ++config) {
        ToothVolume t = makeTooth(3);
        for (int c = 0; c < 8; ++c) {
          const bool in = (config >> c) & 1;
          uint32_t fill = in ? DS_FILL_FULL : 0u;
          if (partial) fill = in ? 16 + rng() % 16 : rng() % 16;
          if (fill) t.voxels.setVoxel(offset + (c & 1), offset + ((c >> 1) & 1), offset + ((c >> 2) & 1),
                                      makeVoxel(Material::Dentin, fill));
        }
        const SurfaceMesh m = meshOf(t);
        const std::string what = "config " + std::to_string(config) + " offset " + std::to_string(offset);
        EXPECT_EQ(m.triangles.empty(), config == 0) << what;
        expectWatertight(m, what);
      }
}

TEST(SurfaceMesher, RandomSmallVolumesAreClosedAndOutward) {
  // Random 3^3 and 4^3 blocks exercise every pairing of ambiguous faces between neighbour cells.
  std::mt19937 rng(2024);
  const int trials = kSlowBuild ? 600 : 3000;  // each trial meshes up to five times
  for (int trial = 0; trial < trials; ++trial) {
    ToothVolume t = makeTooth(3);
    const uint32_t n = 3 + trial % 2;
    const uint32_t offset = rng() % (9 - n);
    const int mode = trial % 3;  // 0 binary, 1 partial fills, 2 partial fills and mixed tissues
    for (uint32_t z = 0; z < n; ++z)
      for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
          const uint32_t fill = mode == 0 ? (rng() % 2) * DS_FILL_FULL : rng() % 32;
          const Material mat = mode == 2 ? Material(1 + rng() % 4) : Material::Enamel;
          if (fill) t.voxels.setVoxel(offset + x, offset + y, offset + z, makeVoxel(mat, fill));
        }
    const std::string what = "trial " + std::to_string(trial);
    expectWatertight(meshOf(t), what);
    if (mode == 2)
      for (Material tissue : {Material::Enamel, Material::Dentin, Material::Pulp, Material::Caries}) {
        SurfaceOptions o;
        o.tissue = tissue;
        expectWatertight(meshOf(t, o), what + " tissue " + materialName(tissue));
      }
  }
}

// ---- 2. tiles and brick borders ------------------------------------------------------------------

TEST(SurfaceMesher, TilesGiveExactBoxes) {
  // A solid grid meets the empty outside half-way between the last voxel centre and the next, i.e.
  // on the grid's faces; a half-full grid is cut at the middle plane. Only border blocks are walked.
  // Along each box edge the cells with one inside corner (of four across the edge) cut a prism of
  // cross-section h^2/8 off, and each box corner's cell puts back h^3/12 of it.
  const double h = 0.5;
  auto boxVolume = [&](double a, double b, double c) {
    return a * b * c - 4 * (a + b + c) * h * h / 8 + 8 * h * h * h / 12;
  };
  ToothVolume t = makeTooth(6, h);
  for (uint32_t z = 0; z < 8; ++z)
    for (uint32_t y = 0; y < 8; ++y)
      for (uint32_t x = 0; x < 8; ++x) t.voxels.setBrickUniform({x, y, z}, makeVoxel(Material::Dentin));
  t.voxels.compact();
  const double side = 64 * h;
  SurfaceMesh full = meshOf(t);
  MeshTopology topo = expectWatertight(full, "full grid");
  EXPECT_NEAR(topo.signed_volume_mm3, boxVolume(side, side, side), 1e-9 * side * side * side);
  EXPECT_EQ(eulerCharacteristic(full), 2);

  for (uint32_t z = 4; z < 8; ++z)
    for (uint32_t y = 0; y < 8; ++y)
      for (uint32_t x = 0; x < 8; ++x) t.voxels.setBrickUniform({x, y, z}, 0);
  SurfaceMesh half = meshOf(t);
  topo = expectWatertight(half, "half grid");
  EXPECT_NEAR(topo.signed_volume_mm3, boxVolume(side, side, side / 2), 1e-9 * side * side * side);
  EXPECT_EQ(eulerCharacteristic(half), 2);
}

TEST(SurfaceMesher, SphereOnABrickCornerHasNoCracks) {
  // Centred where eight bricks meet, so every brick border crosses the surface.
  ToothVolume t = makeTooth(6);
  fillCoverage(t.voxels, sphereSdf(32, 32, 32, 13.0), Material::Enamel);
  const SurfaceMesh m = meshOf(t);
  expectWatertight(m, "sphere on a brick corner");
  EXPECT_EQ(eulerCharacteristic(m), 2);  // one shell, no handles
}

// ---- 3. accuracy on analytic solids --------------------------------------------------------------

TEST(SurfaceMesher, SphereAreaAndVolume) {
  for (int level : {6, 7}) {
    const double r = level == 6 ? 23.3 : 50.7;  // [voxels]
    const double h = 0.05;                      // [mm]
    ToothVolume t = makeTooth(level, h);
    const double c = 0.5 * double(t.voxels.dim());
    fillCoverage(t.voxels, sphereSdf(c + 0.31, c - 0.17, c + 0.05, r), Material::Enamel);
    const SurfaceMesh m = meshOf(t);
    const MeshTopology topo = expectWatertight(m, "sphere");
    EXPECT_EQ(eulerCharacteristic(m), 2);
    const double rm = r * h;
    const double area = surfaceArea(m), area_ref = 4 * std::numbers::pi * rm * rm;
    const double vol = m.geometry().signedVolume(), vol_ref = 4.0 / 3.0 * std::numbers::pi * rm * rm * rm;
    std::printf("sphere level %d r=%.1f voxels: %zu triangles, area error %+.3f%%, volume error %+.3f%%\n", level,
                r, m.triangles.size(), 100 * (area / area_ref - 1), 100 * (vol / vol_ref - 1));
    EXPECT_NEAR(area / area_ref, 1.0, 0.02);
    EXPECT_NEAR(vol / vol_ref, 1.0, 0.01);
    EXPECT_NEAR(topo.signed_volume_mm3, vol, 1e-9 * vol_ref);
  }
}

// Mean normal errors [deg] for 8, 64 and 216 neighbours.
std::array<double, 3> normalErrors(const ToothVolume& t,
                                   const std::function<std::array<double, 3>(std::array<double, 3>)>& truth) {
  std::array<double, 3> e{};
  for (size_t i = 0; i < 3; ++i) {
    SurfaceOptions o;
    o.normals = kNormalModes[i];
    e[i] = meanNormalErrorDeg(t, meshOf(t, o), truth);
  }
  return e;
}

// The paper's claim: averaging the gradient over more voxels lowers the normal error. Checked on
// exact-coverage fills and on binary fills; prints the mean errors for the record.
void expectNormalErrorFallsOnSphere(int level) {
  for (bool binary : {false, true}) {
    ToothVolume t = makeTooth(level);
    const double c = 0.5 * double(t.voxels.dim()) + 0.23, r = 0.4 * double(t.voxels.dim());
    fillCoverage(t.voxels, sphereSdf(c, c, c, r), Material::Enamel, binary);
    const auto e = normalErrors(t, [&](std::array<double, 3> p) {
      return std::array<double, 3>{p[0] - c, p[1] - c, p[2] - c};
    });
    const char* fill = binary ? "binary" : "coverage";
    std::printf("sphere level %d r=%.1f %s: mean normal error 8: %.3f deg, 64: %.3f deg, 216: %.3f deg\n", level, r,
                fill, e[0], e[1], e[2]);
    EXPECT_LT(e[1], e[0]) << "level " << level << " " << fill;
    EXPECT_LT(e[2], e[1]) << "level " << level << " " << fill;
  }
}

TEST(SurfaceMesher, WiderNormalNeighbourhoodsAreMoreAccurateOnASphereLevel7) { expectNormalErrorFallsOnSphere(7); }

TEST(SurfaceMesher, WiderNormalNeighbourhoodsAreMoreAccurateOnASphereLevel8) {
  expectNormalErrorFallsOnSphere(8);
}

TEST(SurfaceMesher, TorusNormals) {
  // A torus bends both ways, so the widest neighbourhood also averages across curvature; the numbers
  // are printed for the record, and only closedness and genus are asserted.
  ToothVolume t = makeTooth(7);
  const double c = 64.17, R = 38.0, r = 14.0;
  fillCoverage(t.voxels, torusSdf(c, c, c, R, r), Material::Dentin);
  const SurfaceMesh m = meshOf(t);
  expectWatertight(m, "torus");
  EXPECT_EQ(eulerCharacteristic(m), 0);  // one handle
  const auto e = normalErrors(t, [&](std::array<double, 3> p) {
    const double dx = p[0] - c, dy = p[1] - c, rho = std::hypot(dx, dy);
    return std::array<double, 3>{dx - R * dx / rho, dy - R * dy / rho, p[2] - c};
  });
  std::printf("torus level 7 R=%.0f r=%.0f: mean normal error 8: %.3f deg, 64: %.3f deg, 216: %.3f deg\n", R, r,
              e[0], e[1], e[2]);
}

// ---- 4. tissues, options, determinism, cancellation ----------------------------------------------

TEST(SurfaceMesher, EachTissueOfNestedSpheresIsClosed) {
  // Dentin ball with a pulp core: the outer surface is all dentin; the pulp alone is one shell; the
  // dentin alone is two shells (outside and the pulp chamber).
  ToothVolume t = makeTooth(6, 0.1);
  const double c = 32.4, r_out = 22.0, r_in = 10.0;
  fillCoverage(t.voxels, sphereSdf(c, c, c, r_out), Material::Dentin);
  ToothVolume pulp = makeTooth(6, 0.1);
  fillCoverage(pulp.voxels, sphereSdf(c, c, c, r_in), Material::Pulp);
  for (uint32_t z = 0; z < 64; ++z)
    for (uint32_t y = 0; y < 64; ++y)
      for (uint32_t x = 0; x < 64; ++x)
        if (2 * voxelFill(pulp.voxels.voxel(x, y, z)) > DS_FILL_FULL) t.voxels.setVoxel(x, y, z, makeVoxel(Material::Pulp));

  const SurfaceMesh whole = meshOf(t);
  expectWatertight(whole, "whole");
  EXPECT_EQ(eulerCharacteristic(whole), 2);
  for (Material m : whole.tissue) EXPECT_EQ(m, Material::Dentin);

  const double h3 = 0.001;  // voxel volume [mm^3]
  SurfaceOptions o;
  o.tissue = Material::Pulp;
  const SurfaceMesh p = meshOf(t, o);
  const MeshTopology tp = expectWatertight(p, "pulp");
  EXPECT_EQ(eulerCharacteristic(p), 2);
  for (Material m : p.tissue) EXPECT_EQ(m, Material::Pulp);
  EXPECT_NEAR(tp.signed_volume_mm3 / (4.0 / 3.0 * std::numbers::pi * r_in * r_in * r_in * h3), 1.0, 0.03);

  o.tissue = Material::Dentin;
  const SurfaceMesh d = meshOf(t, o);
  const MeshTopology td = expectWatertight(d, "dentin");
  EXPECT_EQ(eulerCharacteristic(d), 4);
  for (Material m : d.tissue) EXPECT_EQ(m, Material::Dentin);
  const double shell = 4.0 / 3.0 * std::numbers::pi * (std::pow(r_out, 3) - std::pow(r_in, 3)) * h3;
  EXPECT_NEAR(td.signed_volume_mm3 / shell, 1.0, 0.02);

  o.tissue = Material::Enamel;
  EXPECT_TRUE(meshOf(t, o).triangles.empty());
}

TEST(SurfaceMesher, SameVolumeSameMesh) {
  ToothVolume t = makeTooth(6);
  fillCoverage(t.voxels, torusSdf(31.7, 33.2, 32.9, 18.0, 7.0), Material::Enamel);
  const SurfaceMesh a = meshOf(t), b = meshOf(t);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_FALSE(a.triangles.empty());
}

TEST(SurfaceMesher, ReportsProgressAndStopsWhenCancelled) {
  struct Recorder : Interrupter {
    int starts = 0, ends = 0, calls = 0, stop_at = -1;
    double last = -1;
    bool monotone = true;
    void start(std::string_view) override { ++starts; }
    bool progress(double f) override {
      monotone = monotone && f >= last;
      last = f;
      return ++calls != stop_at;
    }
    void end() override { ++ends; }
  };
  ToothVolume t = makeTooth(6);
  fillCoverage(t.voxels, sphereSdf(30, 30, 30, 12), Material::Enamel);
  Recorder full;
  ASSERT_TRUE(meshVolumeCpu(t, {}, full).ok());
  EXPECT_EQ(full.starts, 1);
  EXPECT_EQ(full.ends, 1);
  EXPECT_TRUE(full.monotone);
  EXPECT_DOUBLE_EQ(full.last, 1.0);

  Recorder cancel;
  cancel.stop_at = 3;
  auto r = meshVolumeCpu(t, {}, cancel);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("cancel"), std::string::npos);
  EXPECT_EQ(cancel.ends, 1);
}

}  // namespace
}  // namespace dentsim
