// Analytic solids: exact distances and normals, and their voxelization by sampled coverage.
#include "bench/analytic_solid.h"

#include <array>
#include <cassert>
#include <cmath>
#include <cstdio>

namespace dentsim::bench {

double AnalyticSolid::distance(const Vec3d& p) const {
  const double dx = p[0] - centre[0], dy = p[1] - centre[1], dz = p[2] - centre[2];
  if (kind == Kind::Sphere) return std::sqrt(dx * dx + dy * dy + dz * dz) - radius;
  // Distance to the tube's axis circle, less the tube radius.
  const double ring = std::sqrt(dx * dx + dy * dy) - radius;
  return std::sqrt(ring * ring + dz * dz) - tube;
}

Vec3d AnalyticSolid::normal(const Vec3d& p) const {
  Vec3d d{p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
  if (kind == Kind::Torus) {
    // From the nearest point of the axis circle, which lies in the plane z = centre.
    const double rho = std::hypot(d[0], d[1]);
    if (rho > 0.0) {
      d[0] -= radius * d[0] / rho;
      d[1] -= radius * d[1] / rho;
    }
  }
  const double len = std::hypot(d[0], d[1], d[2]);
  if (len == 0.0) return {0.0, 0.0, 1.0};
  return {d[0] / len, d[1] / len, d[2] / len};
}

std::string AnalyticSolid::describe() const {
  char buf[64];
  if (kind == Kind::Sphere)
    std::snprintf(buf, sizeof buf, "sphere r %.1f", radius);
  else
    std::snprintf(buf, sizeof buf, "torus R %.1f r %.1f", radius, tube);
  return buf;
}

namespace {

// The off-centre shift [voxels]: irrational-looking, so no plane of symmetry meets voxel centres.
constexpr Vec3d kShift{0.23, 0.17, 0.31};

Vec3d gridCentre(int level) {
  const double c = 0.5 * double(1u << level);
  return {c + kShift[0], c + kShift[1], c + kShift[2]};
}

}  // namespace

AnalyticSolid sphereForLevel(int level) {
  AnalyticSolid s;
  s.kind = AnalyticSolid::Kind::Sphere;
  s.centre = gridCentre(level);
  s.radius = 0.4 * double(1u << level);
  return s;
}

AnalyticSolid torusForLevel(int level) {
  AnalyticSolid s;
  s.kind = AnalyticSolid::Kind::Torus;
  s.centre = gridCentre(level);
  s.radius = 0.3 * double(1u << level);
  s.tube = 0.11 * double(1u << level);
  return s;
}

void fillCoverage(BrickVolume& volume, const AnalyticSolid& solid, Material material, int samples) {
  assert(samples >= 1 && samples <= 16);
  assert(material != Material::Empty);
  // A distance is 1-Lipschitz, so a point this far from the surface decides its whole box.
  const double brick_reach = 0.5 * std::sqrt(3.0) * DS_BRICK_DIM + 1e-9;
  const double voxel_reach = 0.5 * std::sqrt(3.0) + 1e-9;
  const uint32_t bd = volume.brickDim();
  const double step = 1.0 / samples;
  const int total = samples * samples * samples;
  std::array<Voxel, DS_BRICK_VOXELS> voxels{};
  for (uint32_t bz = 0; bz < bd; ++bz)
    for (uint32_t by = 0; by < bd; ++by)
      for (uint32_t bx = 0; bx < bd; ++bx) {
        const double half = 0.5 * DS_BRICK_DIM;
        const double d = solid.distance({DS_BRICK_DIM * bx + half, DS_BRICK_DIM * by + half, DS_BRICK_DIM * bz + half});
        if (d > brick_reach) continue;
        if (d < -brick_reach) {
          volume.setBrickUniform({bx, by, bz}, makeVoxel(material));
          continue;
        }
        for (uint32_t z = 0; z < DS_BRICK_DIM; ++z)
          for (uint32_t y = 0; y < DS_BRICK_DIM; ++y)
            for (uint32_t x = 0; x < DS_BRICK_DIM; ++x) {
              const Vec3d lo{double(DS_BRICK_DIM * bx + x), double(DS_BRICK_DIM * by + y), double(DS_BRICK_DIM * bz + z)};
              const double dc = solid.distance({lo[0] + 0.5, lo[1] + 0.5, lo[2] + 0.5});
              uint32_t fill = 0;
              if (dc < -voxel_reach) {
                fill = DS_FILL_FULL;
              } else if (dc <= voxel_reach) {
                int inside = 0;
                for (int sz = 0; sz < samples; ++sz)
                  for (int sy = 0; sy < samples; ++sy)
                    for (int sx = 0; sx < samples; ++sx)
                      inside += solid.distance({lo[0] + (sx + 0.5) * step, lo[1] + (sy + 0.5) * step,
                                                lo[2] + (sz + 0.5) * step}) < 0.0;
                fill = uint32_t(std::lround(double(inside) * DS_FILL_FULL / total));
              }
              voxels[layout::brickCoordToOffset(x, y, z)] = fill ? makeVoxel(material, fill) : Voxel(0);
            }
        volume.setBrick({bx, by, bz}, voxels.data());
      }
}

ToothVolume analyticTooth(const AnalyticSolid& solid, int level, Material material, int samples, double voxel_mm) {
  ToothVolume tooth{VolumeFrame::axisAligned(level, voxel_mm, {0.0, 0.0, 0.0}), BrickVolume(level)};
  fillCoverage(tooth.voxels, solid, material, samples);
  return tooth;
}

}  // namespace dentsim::bench
