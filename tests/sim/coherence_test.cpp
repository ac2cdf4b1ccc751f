// Temporal coherence in contact finding: clearances never overstate the distance to tissue, and the finder that skips by them finds exactly what testing every point finds.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "sim/contact.h"
#include "sim/cutter.h"
#include "sim/voxel_field.h"
#include "sim_fixtures.h"

namespace dentsim {
namespace {

using test::Block;
using test::flatBlock;
using test::sphereBur;

// A dentin block whose top layers are ragged: random partial fills and holes, as cutting leaves them.
Block raggedBlock(uint32_t seed) {
  Block b = flatBlock(Material::Dentin);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<uint32_t> fill(0, DS_FILL_FULL);
  for (uint32_t z = 58; z < 66; ++z)
    for (uint32_t y = 0; y < b.volume.dim(); ++y)
      for (uint32_t x = 0; x < b.volume.dim(); ++x) {
        const uint32_t f = z < 64 ? (rng() % 4 == 0 ? fill(rng) : DS_FILL_FULL) : (rng() % 16 == 0 ? fill(rng) : 0);
        b.volume.setVoxel(x, y, z, f == 0 ? Voxel{0} : makeVoxel(Material::Dentin, f));
      }
  return b;
}

TEST(Rigid, RotationMatrixRotatesAsTheQuaternionDoes) {
  // The finder moves its points with the matrix; everything else uses the quaternion.
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> c(-2.0, 2.0);
  for (int n = 0; n < 100; ++n) {
    const Quat q = Quat::fromRotationVector({c(rng), c(rng), c(rng)});
    const std::array<double, 9> m = q.matrix();
    const Vec3 v{c(rng), c(rng), c(rng)};
    const Vec3 a = q.rotate(v);
    const Vec3 b{m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
                 m[6] * v.x + m[7] * v.y + m[8] * v.z};
    EXPECT_LT(norm(a - b), 1e-12 * (1 + norm(v)));
  }
}

TEST(Rigid, FromMatrixInvertsMatrixOnEveryBranch) {
  // Random rotations, plus half turns about each axis and a near half turn, which take each of
  // Shepperd's four branches (trace > 0, then the largest diagonal entry x, y or z).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> c(-3.0, 3.0);
  std::vector<Quat> qs = {Quat::fromAxisAngle({1, 0, 0}, 3.1), Quat::fromAxisAngle({0, 1, 0}, 3.1),
                          Quat::fromAxisAngle({0, 0, 1}, 3.1), Quat::fromAxisAngle({1, 1, 0}, 3.14159), Quat{}};
  for (int n = 0; n < 100; ++n) qs.push_back(Quat::fromRotationVector({c(rng), c(rng), c(rng)}));
  for (const Quat& q : qs) {
    const Quat back = Quat::fromMatrix(q.matrix());
    // q and -q are the same rotation.
    const double dot = q.w * back.w + q.x * back.x + q.y * back.y + q.z * back.z;
    EXPECT_NEAR(std::abs(dot), 1.0, 1e-12);
    // fromAxes takes the matrix's columns: the images of the unit axes.
    const Quat axes = Quat::fromAxes(q.rotate({1, 0, 0}), q.rotate({0, 1, 0}), q.rotate({0, 0, 1}));
    EXPECT_NEAR(std::abs(q.w * axes.w + q.x * axes.x + q.y * axes.y + q.z * axes.z), 1.0, 1e-12);
  }
}

TEST(VoxelField, ClearanceNeverOverstatesTheDistanceToTissue) {
  Block b = raggedBlock(7);
  VoxelField field(b.volume, b.frame);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> xy(4.0, 124.0), z(55.0, 110.0), unit(-1.0, 1.0);
  int checked = 0, far = 0;
  for (int n = 0; n < 3000; ++n) {
    const Vec3 u{xy(rng), xy(rng), z(rng)};
    const double phi = field.sample(u).phi;
    const double c = field.clearance(u, phi);
    if (phi >= 0) {
      EXPECT_EQ(c, 0.0);
      continue;
    }
    ASSERT_GT(c, 0.0);
    // Along rays in every direction, the field stays below the surface for the whole clearance.
    for (int r = 0; r < 12; ++r) {
      Vec3 d{unit(rng), unit(rng), unit(rng)};
      if (norm(d) < 1e-3) continue;
      d = normalized(d);
      for (double t = 0.0; t < c; t += 0.02) ASSERT_LT(field.sample(u + d * t).phi, 0.0) << "u " << u.x << "," << u.y << "," << u.z << " t " << t << " of " << c;
      ASSERT_LT(field.sample(u + d * (c * (1 - 1e-9))).phi, 0.0);
    }
    ++checked;
    // Well above the bricks of the ragged layer (its top brick ends at voxel z = 71), the bound
    // reaches a brick's width: the index tables alone show the box around the point empty.
    if (u.z > 71.0 + 10.0) {
      EXPECT_GE(c, 8.0) << u.z;
      ++far;
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(far, 100);
}

TEST(VoxelField, CachedCopiesFollowWritesOnBrickFacesEdgesAndTiles) {
  // The field reads cells from 9^3 copies: a brick and the first layer of its +x, +y, +z
  // neighbours. Writes through written() must reach every cached copy holding the voxel, including
  // tiles turned dense, so that reads always agree with the volume itself.
  Block b = raggedBlock(5);
  VoxelField field(b.volume, b.frame);
  std::mt19937 rng(23);
  const auto dim = int64_t(b.volume.dim());
  // Writes crowd brick faces and corners, and reach into solid tiles and empty space.
  std::uniform_int_distribution<int64_t> brick(0, dim / DS_BRICK_DIM - 1), z_brick(5, 9), face(0, 2);
  std::uniform_int_distribution<uint32_t> fill(0, DS_FILL_FULL), local(0, DS_BRICK_DIM - 1);
  auto coordinate = [&](int64_t bc) {
    const int64_t pick = face(rng);
    const int64_t l = pick == 0 ? 0 : (pick == 1 ? int64_t(DS_BRICK_DIM) - 1 : int64_t(local(rng)));
    return bc * int64_t(DS_BRICK_DIM) + l;
  };
  // The trilinear field straight from the volume, corners outside the grid empty.
  auto reference = [&](const Vec3& u) {
    const auto x0 = int64_t(std::floor(u.x)), y0 = int64_t(std::floor(u.y)), z0 = int64_t(std::floor(u.z));
    double phi = -0.5;
    for (int i = 0; i < 8; ++i) {
      const int64_t x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + (i >> 2);
      if (x < 0 || y < 0 || z < 0 || x >= dim || y >= dim || z >= dim) continue;
      const double w = ((i & 1) ? u.x - double(x0) : 1 + double(x0) - u.x) *
                       ((i & 2) ? u.y - double(y0) : 1 + double(y0) - u.y) *
                       ((i & 4) ? u.z - double(z0) : 1 + double(z0) - u.z);
      phi += w * double(voxelFill(b.volume.voxel(uint32_t(x), uint32_t(y), uint32_t(z)))) / DS_FILL_FULL;
    }
    return phi;
  };
  std::uniform_real_distribution<double> off(-0.999, 0.999);
  int tiles_opened = 0;
  for (int round = 0; round < 40; ++round) {
    for (int w = 0; w < 60; ++w) {
      const int64_t x = coordinate(brick(rng)), y = coordinate(brick(rng)), z = coordinate(z_brick(rng));
      const uint32_t f = fill(rng);
      const Voxel v = f == 0 ? Voxel{0} : makeVoxel(w % 2 ? Material::Enamel : Material::Dentin, f);
      const auto ux = uint32_t(x), uy = uint32_t(y), uz = uint32_t(z);
      tiles_opened += b.volume.brick({ux / DS_BRICK_DIM, uy / DS_BRICK_DIM, uz / DS_BRICK_DIM}).uniform &&
                      b.volume.voxel(ux, uy, uz) != v;
      b.volume.setVoxel(ux, uy, uz, v);
      field.written(ux, uy, uz, v);
      // A tile opened by the write is no longer answered from the tables as the old tile.
      if (v != 0) {
        ASSERT_FALSE(field.regionEmpty(x, x, y, y, z, z, true)) << x << " " << y << " " << z;
      }
    }
    // Cells around brick corners (where a copy's apron is read) and anywhere, including the grid's edge.
    for (int n = 0; n < 400; ++n) {
      const Vec3 u = n % 4 == 3 ? Vec3{double(dim) - 1 + off(rng) * 0.5, double(brick(rng) * 8) + off(rng),
                                       double(z_brick(rng) * 8) + off(rng)}
                                : Vec3{double(brick(rng) * 8) + off(rng), double(brick(rng) * 8) + off(rng),
                                       double(z_brick(rng) * 8) + off(rng)};
      ASSERT_NEAR(field.sample(u).phi, reference(u), 1e-12) << "round " << round << " at " << u.x << " " << u.y << " " << u.z;
    }
  }
  for (int64_t z = 40; z < 80; ++z)
    for (int64_t y = 0; y < dim; ++y)
      for (int64_t x = 0; x < dim; ++x)
        ASSERT_EQ(field.voxel(x, y, z), b.volume.voxel(uint32_t(x), uint32_t(y), uint32_t(z))) << x << " " << y << " " << z;
  EXPECT_GT(tiles_opened, 20) << "writes must turn cached tiles dense";
}

TEST(VoxelField, BatchPhiAgreesWithTheDoubleFieldToFloatRounding) {
  // The finder classifies points with the four-wide float field; it must be the double field,
  // including cells on brick faces, on the grid's edges and wholly outside it.
  Block b = raggedBlock(3);
  VoxelField field(b.volume, b.frame);
  std::mt19937 rng(31);
  const double dim = double(b.volume.dim());
  std::uniform_real_distribution<double> xy(-2.0, dim + 1.0), z(52.0, 70.0), edge(-1.5, 0.5);
  constexpr uint32_t kN = 4001;  // not a multiple of four: the last group is partial
  std::vector<float> ux(kN + 3), uy(kN + 3), uz(kN + 3), phi(kN + 3);
  for (uint32_t i = 0; i < kN; ++i) {
    ux[i] = float(i % 5 == 0 ? edge(rng) : xy(rng));
    uy[i] = float(i % 7 == 0 ? dim - 1 + edge(rng) : xy(rng));
    uz[i] = float(z(rng));
  }
  field.phiBatch(ux.data(), uy.data(), uz.data(), kN, phi.data());
  int inside = 0, outside_grid = 0;
  for (uint32_t i = 0; i < kN; ++i) {
    const Vec3 u{ux[i], uy[i], uz[i]};
    const double exact = field.sample(u).phi;
    ASSERT_NEAR(phi[i], exact, 1e-5) << i << ": " << u.x << " " << u.y << " " << u.z;
    inside += exact > 0;
    outside_grid += u.x < 0 || u.y < 0 || u.x > dim - 1 || u.y > dim - 1;
  }
  EXPECT_GT(inside, 500);
  EXPECT_GT(outside_grid, 500);
}

TEST(VoxelField, RegionEmptyAgreesWithReadingEveryVoxel) {
  Block b = raggedBlock(3);
  VoxelField field(b.volume, b.frame);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int64_t> at(-4, 131), len(0, 20);
  int empties = 0, tile_answers = 0;
  for (int n = 0; n < 2000; ++n) {
    const int64_t x0 = at(rng), y0 = at(rng), z0 = at(rng) / 2 + 50;
    const int64_t x1 = x0 + len(rng), y1 = y0 + len(rng), z1 = z0 + len(rng);
    bool brute = true;
    for (int64_t z = z0; z <= z1 && brute; ++z)
      for (int64_t y = y0; y <= y1 && brute; ++y)
        for (int64_t x = x0; x <= x1 && brute; ++x) brute = field.voxel(x, y, z) == 0;
    EXPECT_EQ(field.regionEmpty(x0, x1, y0, y1, z0, z1), brute) << x0 << " " << y0 << " " << z0;
    // From the tables alone it may say "not known empty", never "empty" wrongly.
    if (field.regionEmpty(x0, x1, y0, y1, z0, z1, true)) {
      EXPECT_TRUE(brute);
      ++tile_answers;
    }
    empties += brute ? 1 : 0;
  }
  EXPECT_GT(empties, 200);
  EXPECT_GT(tile_answers, 50);
}

TEST(Contact, SkippingByClearanceFindsExactlyTheContactsOfAFullTestWhileCutting) {
  Block b = flatBlock(Material::Dentin);
  b.volume.reserveSpare(256, 4096);
  VoxelField field(b.volume, b.frame);
  const ToolModel bur = sphereBur(0.5, 0.03);
  const SimParams params = defaultSimParams();
  ContactFinder coherent(bur.shell.size()), full(bur.shell.size());
  Cutter cutter(1 << 17);
  uint64_t tested = 0, clear = 0, contacts = 0, changed = 0;
  for (int step = 0; step < 600; ++step) {
    // Down onto the block, then a slow sweep along x with a small wobble: micrometres a step.
    const double t = step * 1e-3;
    const Vec3 tip{0.5 + 2.0 * t, 0.8 + 0.01 * std::sin(40 * t), b.surface_mm + 0.02 - 0.25 * std::min(t, 0.3)};
    const Pose pose{tip, Quat::fromAxisAngle({1, 0, 0}, 0.05 * std::sin(25 * t))};
    ContactStats st;
    const auto found = coherent.find(field, bur.shell, pose, &st);
    std::vector<ContactPoint> a(found.begin(), found.end());
    full.forgetClearances();
    const auto reference = full.find(field, bur.shell, pose);
    ASSERT_EQ(a.size(), reference.size()) << "step " << step;
    for (size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].point, reference[i].point) << "step " << step;
      ASSERT_EQ(a[i].depth_mm, reference[i].depth_mm);
    }
    tested += st.points_tested;
    clear += st.points_clear;
    contacts += a.size();
    changed += cutter.cut(b.volume, field, a, params, 0.8, 0.05, 1e-3, uint64_t(step), nullptr).voxels_changed;
  }
  EXPECT_GT(contacts, 20000u) << "the bur must be cutting for this to test anything";
  EXPECT_GT(changed, 10000u) << "and cutting, so that clearances outlive removed tissue";
  EXPECT_GT(clear, tested) << "most samples are skipped at this speed";
}

}  // namespace
}  // namespace dentsim
