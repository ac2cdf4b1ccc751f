// Analytic solids (sphere, torus) with exact distances and normals, voxelized by sampled coverage: ground truth for surface accuracy.
//
// Coordinates are in voxel units of the grid: voxel (i,j,k) covers [i, i+1) x [j, j+1) x [k, k+1),
// its centre at (i+0.5, j+0.5, k+0.5).
#pragma once

#include <string>

#include "core/triangle_mesh.h"
#include "volume/brick_volume.h"

namespace dentsim::bench {

// A solid known by its exact signed distance.
struct AnalyticSolid {
  enum class Kind { Sphere, Torus };
  Kind kind = Kind::Sphere;
  Vec3d centre{0, 0, 0};  // [voxels]
  double radius = 0.0;    // sphere radius, or the torus' major radius (centre to tube axis) [voxels]
  double tube = 0.0;      // torus tube radius [voxels]; unused by a sphere. The torus' axis is z.

  // Signed Euclidean distance to the surface, negative inside [voxels].
  double distance(const Vec3d& p) const;
  // Unit outward normal of the nearest surface point; +z where the direction is undefined.
  Vec3d normal(const Vec3d& p) const;
  // "sphere r 51.2" or "torus R 38.4 r 14.1" [voxels].
  std::string describe() const;
};

// Solids scaled to a grid of 2^level voxels, their centre a fraction of a voxel off the grid centre
// so that no symmetry plane runs through voxel centres. Sphere: r = 0.4 dim. Torus: R = 0.3 dim and
// r = 0.11 dim, which at level 7 is close to the R 38, r 14 of tests/volume/surface_mesher_test.cpp.
AnalyticSolid sphereForLevel(int level);
AnalyticSolid torusForLevel(int level);

// Writes every brick within reach of the solid's surface or inside it: a voxel's fill is the share
// of `samples`^3 points on a regular sub-grid inside the solid, rounded to 1/31, and its material
// `material`. Voxels whose centre lies more than half a diagonal from the surface are full or empty
// without sampling; bricks wholly outside are left as they are. samples in 1..16.
void fillCoverage(BrickVolume& volume, const AnalyticSolid& solid, Material material, int samples = 8);

// An empty grid of 2^level voxels of `voxel_mm` with its origin at 0, holding `solid` by coverage.
ToothVolume analyticTooth(const AnalyticSolid& solid, int level, Material material, int samples = 8,
                          double voxel_mm = 1.0);

}  // namespace dentsim::bench
