// Tests of the generated molar: topology of each layer, the shared DEJ, nesting, caries, dimensions, volumes.
#include "model/molar_generator.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>
#include <set>
#include <string_view>
#include <unordered_map>

#include <gtest/gtest.h>

#include "io/mesh_topology.h"
#include "model/field_distance.h"
#include "volume/tissue_table.h"

namespace dentsim {
namespace {

// A coarser lattice than the assets' keeps the checks quick under the sanitizers; the full
// resolution is compared with the checked-in files once, in builtin_assets_test.
constexpr double kCoarse = 0.35;  // [mm]

const MolarLayers& coarseMolar() {
  static const MolarLayers layers = generateMolar({.grid_mm = kCoarse});
  return layers;
}

// Every tissue of the tissue table is a layer of the molar, in the table's order, each row on its
// own mesh, except the tissues named here with the reason: a tissue added to the table fails here
// until the molar has its layer or a line below says why it has none.
struct NoLayer {
  const char* tissue;
  const char* why;
};
constexpr NoLayer kTissuesWithoutAMolarLayer[] = {
    // An adjacent tooth is a tooth of its own beside the molar, not a layer inside it: the
    // neighbours are separate meshes (model/neighbour_generator.h), voxelized beside the molar.
    {"neighbour", "neighbours are separate teeth (neighbour_generator.h)"},
};

const NoLayer* whyNoLayer(const char* tissue) {
  for (const NoLayer& n : kTissuesWithoutAMolarLayer)
    if (std::string_view(n.tissue) == tissue) return &n;
  return nullptr;
}

TEST(MolarLayers, EveryTissueOfTheTableIsALayer) {
  std::vector<const char*> layered;
  for (const TissueRow& row : kTissueTable)
    if (!whyNoLayer(row.name)) layered.push_back(row.name);
  ASSERT_EQ(std::size(kMolarLayers), layered.size());
  for (size_t t = 0; t < layered.size(); ++t) EXPECT_STREQ(kMolarLayers[t].tissue, layered[t]);
  const MolarLayers& m = coarseMolar();
  std::set<const TriangleMesh*> meshes;
  for (const TissueRow& row : kTissueTable) {
    const TriangleMesh* mesh = m.layer(row.name);
    if (const NoLayer* n = whyNoLayer(row.name)) {
      EXPECT_EQ(mesh, nullptr) << row.name << " has a layer, yet is listed without one: " << n->why;
      continue;
    }
    ASSERT_NE(mesh, nullptr) << row.name;
    EXPECT_GT(mesh->triangleCount(), 0u) << row.name;
    meshes.insert(mesh);
  }
  EXPECT_EQ(meshes.size(), layered.size());
  EXPECT_EQ(m.layer("enamel"), &m.enamel);
  EXPECT_EQ(m.layer("caries"), &m.caries);
  EXPECT_EQ(m.layer("cementum"), nullptr);  // a tissue the molar lacks has no layer
  // Each tissue listed without a layer is a tissue of the table (no stale excuse).
  for (const NoLayer& n : kTissuesWithoutAMolarLayer) {
    bool known = false;
    for (const TissueRow& row : kTissueTable) known = known || std::string_view(row.name) == n.tissue;
    EXPECT_TRUE(known) << n.tissue;
  }
}

Vec3d toD(const Vec3f& p) { return {p[0], p[1], p[2]}; }

// How far p lies outside the tooth [mm], to first order.
double outsideTooth(const Vec3f& p) { return test::fieldDistanceMm(molarToothField, toD(p)); }

// Nearest-point queries over a vertex cloud, bucketed in cubes of `cell` mm.
class PointCloud {
 public:
  PointCloud(const std::vector<Vec3f>& pts, double cell) : cell_(cell) {
    for (const Vec3f& p : pts) buckets_[key(cellOf(p))].push_back(p);
  }
  // Distance to the nearest point, or `reach` cells * cell if none is that close [mm].
  double nearest(const Vec3f& p, int reach) const {
    const auto c = cellOf(p);
    double best = std::pow(reach * cell_, 2);
    for (int a = -reach; a <= reach; ++a)
      for (int b = -reach; b <= reach; ++b)
        for (int d = -reach; d <= reach; ++d) {
          auto it = buckets_.find(key({c[0] + a, c[1] + b, c[2] + d}));
          if (it == buckets_.end()) continue;
          for (const Vec3f& q : it->second) {
            double s = 0;
            for (int k = 0; k < 3; ++k) s += (double(p[k]) - q[k]) * (double(p[k]) - q[k]);
            best = std::min(best, s);
          }
        }
    return std::sqrt(best);
  }

 private:
  std::array<int, 3> cellOf(const Vec3f& p) const {
    return {int(std::floor(p[0] / cell_)), int(std::floor(p[1] / cell_)), int(std::floor(p[2] / cell_))};
  }
  static uint64_t key(const std::array<int, 3>& c) {
    return (uint64_t(uint32_t(c[0] + 1000)) << 40) | (uint64_t(uint32_t(c[1] + 1000)) << 20) | uint64_t(uint32_t(c[2] + 1000));
  }
  double cell_;
  std::unordered_map<uint64_t, std::vector<Vec3f>> buckets_;
};

int componentCount(const TriangleMesh& m) {
  std::vector<uint32_t> parent(m.vertexCount());
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& t : m.triangles) {
    parent[root(t[1])] = root(t[0]);
    parent[root(t[2])] = root(t[0]);
  }
  int n = 0;
  for (uint32_t i = 0; i < parent.size(); ++i) n += root(i) == i ? 1 : 0;
  return n;
}

// The DEJ: dentin vertices that are bit-identical to enamel vertices.
std::vector<Vec3f> sharedVertices(const MolarLayers& l) {
  const std::set<Vec3f> enamel(l.enamel.positions.begin(), l.enamel.positions.end());
  std::vector<Vec3f> shared;
  for (const Vec3f& p : l.dentin.positions)
    if (enamel.count(p)) shared.push_back(p);
  return shared;
}

TEST(MolarGenerator, EveryLayerIsOneClosedOutwardManifold) {
  const MolarLayers& l = coarseMolar();
  for (const TriangleMesh* m : {&l.enamel, &l.dentin, &l.pulp, &l.caries}) {
    const MeshTopology t = analyzeTopology(*m);
    EXPECT_GT(m->triangleCount(), 100u);
    EXPECT_EQ(t.open_edges, 0u);
    EXPECT_EQ(t.nonmanifold_edges, 0u);
    EXPECT_EQ(t.flipped_edges, 0u);
    EXPECT_EQ(t.degenerate_triangles, 0u);
    EXPECT_GT(t.signed_volume_mm3, 0.0);
    // One piece each: no enamel crumbs at the CEJ, and the canals stay joined to the chamber.
    EXPECT_EQ(componentCount(*m), 1);
  }
}

TEST(MolarGenerator, Deterministic) {
  const MolarLayers a = generateMolar({.grid_mm = 0.5}), b = generateMolar({.grid_mm = 0.5});
  EXPECT_EQ(a.enamel.positions, b.enamel.positions);
  EXPECT_EQ(a.enamel.triangles, b.enamel.triangles);
  EXPECT_EQ(a.dentin.positions, b.dentin.positions);
  EXPECT_EQ(a.pulp.triangles, b.pulp.triangles);
  EXPECT_EQ(a.caries.positions, b.caries.positions);
}

TEST(MolarGenerator, DimensionsOfALowerFirstMolar) {
  const MolarLayers& l = coarseMolar();
  Bounds3 tooth = l.enamel.bounds();
  tooth.add(l.dentin.bounds());
  const Vec3d e = tooth.extent();
  EXPECT_NEAR(e[0], 11.0, 0.5) << "mesiodistal";
  EXPECT_NEAR(e[1], 10.0, 0.5) << "buccolingual";
  EXPECT_NEAR(e[2], 21.0, 1.0) << "crown tip to apex";
  EXPECT_NEAR(tooth.hi[2], 7.5, 0.4) << "crown height above the CEJ";
  EXPECT_LE(tooth.lo[2], -13.0) << "roots 13-14 mm";
  EXPECT_GE(tooth.lo[2], -14.0) << "roots 13-14 mm";
  // The enamel ends at the CEJ (z = 0); the dentin alone forms the roots.
  EXPECT_GE(l.enamel.bounds().lo[2], 0.0);
  // Two roots: a horizontal section 6 mm below the CEJ meets dentin in two separate x ranges.
  std::vector<float> xs;
  for (const auto& t : l.dentin.triangles) {
    float zlo = 1e9f, zhi = -1e9f;
    for (uint32_t c : t) zlo = std::min(zlo, l.dentin.positions[c][2]), zhi = std::max(zhi, l.dentin.positions[c][2]);
    if (zlo <= -6.0f && zhi >= -6.0f && std::abs(l.dentin.positions[t[0]][1]) < 0.5f) xs.push_back(l.dentin.positions[t[0]][0]);
  }
  const bool mesial = std::any_of(xs.begin(), xs.end(), [](float x) { return x < -1.0f; });
  const bool distal = std::any_of(xs.begin(), xs.end(), [](float x) { return x > 1.0f; });
  const bool furcation = std::none_of(xs.begin(), xs.end(), [](float x) { return std::abs(x) < 0.5f; });
  EXPECT_TRUE(mesial && distal && furcation);
}

TEST(MolarGenerator, VolumesArePlausible) {
  const MolarLayers& l = coarseMolar();
  const double enamel = l.enamel.signedVolume(), dentin = l.dentin.signedVolume();
  const double pulp = l.pulp.signedVolume(), caries = l.caries.signedVolume();
  EXPECT_GE(enamel + dentin, 600.0);
  EXPECT_LE(enamel + dentin, 900.0);
  EXPECT_GE(enamel, 150.0);
  EXPECT_LE(enamel, 270.0);
  EXPECT_GE(pulp, 20.0);
  EXPECT_LE(pulp, 80.0);
  EXPECT_GT(caries, 1.0);
  EXPECT_LT(caries, 15.0);
}

TEST(MolarGenerator, EnamelAndDentinShareTheDej) {
  const MolarLayers& l = coarseMolar();
  const std::vector<Vec3f> dej = sharedVertices(l);
  EXPECT_GT(dej.size(), 1000u);
  for (const Vec3f& p : dej) EXPECT_GT(p[2], 0.0f) << "the DEJ lies above the CEJ";
  // No dentin vertex outside the tooth. A vertex sits on a lattice edge that has one end inside,
  // and linear interpolation misses the curved surface by a fraction of a cell; half a cell
  // bounds it with room (about 0.2 cells measured, at the CEJ's edge).
  double worst = -1e9;
  for (const Vec3f& p : l.dentin.positions) worst = std::max(worst, outsideTooth(p));
  EXPECT_LE(worst, 0.5 * kCoarse);
}

TEST(MolarGenerator, PulpStaysDeepInsideTheDentin) {
  const MolarLayers& l = coarseMolar();
  const PointCloud dentin(l.dentin.positions, 0.5), dej(sharedVertices(l), 0.5);
  double to_surface = 1e9, to_dej = 1e9, field = -1e9;
  for (const Vec3f& p : l.pulp.positions) {
    to_surface = std::min(to_surface, dentin.nearest(p, 2));
    to_dej = std::min(to_dej, dej.nearest(p, 4));
    field = std::max(field, molarToothField(toD(p)));
  }
  EXPECT_GE(to_surface, 0.3) << "root canal walls";
  EXPECT_GE(to_dej, 1.4) << "pulp horns under the DEJ";
  EXPECT_LT(field, -0.3);
}

TEST(MolarGenerator, CariesCrossesTheDejAndSparesThePulp) {
  const MolarLayers& l = coarseMolar();
  // Where the lesion opens at the fissure it takes the enamel's own outer-surface vertices (they
  // may bridge a fissure narrower than a cell); every other vertex is inside the tooth field.
  const std::set<Vec3f> enamel(l.enamel.positions.begin(), l.enamel.positions.end());
  int in_enamel = 0, in_dentin = 0, on_surface = 0;
  double outside = -1e9;
  for (const Vec3f& p : l.caries.positions) {
    const double d = molarDentinField(toD(p));
    in_enamel += d > 0.05 ? 1 : 0;
    in_dentin += d < -0.05 ? 1 : 0;
    if (enamel.count(p)) ++on_surface;
    else outside = std::max(outside, outsideTooth(p));
  }
  EXPECT_GT(in_enamel, 20);
  EXPECT_GT(in_dentin, 20);
  // Half a cell, as for the dentin (about 0.4 cells measured, at the lesion's rim in the fissure).
  EXPECT_LE(outside, 0.5 * kCoarse) << "the lesion stays inside the outer surface";
  const PointCloud pulp(l.pulp.positions, 0.5);
  double gap = 1e9;
  for (const Vec3f& p : l.caries.positions) gap = std::min(gap, pulp.nearest(p, 3));
  EXPECT_GE(gap, 1.0);
  EXPECT_GT(on_surface, 0) << "it opens at the fissure";
}

}  // namespace
}  // namespace dentsim
