// PointShell: a tool's surface as points with inward normals and area, grouped in clusters, for voxel/point-shell contact.
//
// Entry points
//   buildPointShell(mesh, options)   any closed tool mesh (a bur STL, the mirror) -> its point shell
//
// How it is built (VPS, McNeely et al. 1999; the paper converts the tool through an octree): the
// surface is sampled densely, and the samples are binned into cubes of the chosen spacing; each
// occupied cube gives one point at the area-weighted centroid of its samples, with their averaged
// inward normal and their total area. The areas sum to the mesh's area, so a force summed as
// area x pressure does not depend on the spacing. The cutting head (the part of a bur within
// `cutting_length_mm` of its tip, along +Z) is sampled at its own, finer spacing and flagged; the
// neck and shank collide but never cut. Points are stored cluster by cluster: a cluster is the
// points of one coarse cube, with a bounding sphere, so that a whole cluster can skip a step when
// it lies in empty space.
#pragma once

#include <cstdint>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "core/triangle_mesh.h"

namespace dentsim {

struct PointShellOptions {
  double head_spacing_mm = 0.03;    // point spacing on the cutting head [mm], > 0
  double shank_spacing_mm = 0.08;   // point spacing elsewhere [mm], > 0
  double cutting_length_mm = 0.0;   // the head: points with z - z_min <= this cut; 0: nothing cuts
  double cluster_mm = 0.4;          // edge of the cubes that group points into clusters [mm]
};

// A group of points that are tested, or skipped, together.
struct ShellCluster {
  uint32_t first = 0;     // index of its first point
  uint32_t count = 0;     // its points: first .. first+count-1
  Vec3 centre;            // bounding sphere centre, tool frame [mm]
  double radius = 0.0;    // bounding sphere radius [mm]
};

struct PointShell {
  std::vector<Vec3> positions;     // (n) points on the surface, tool frame [mm]
  std::vector<Vec3> inward;        // (n) unit normals into the tool
  std::vector<double> area_mm2;    // (n) surface area each point stands for [mm^2]
  std::vector<uint8_t> cutting;    // (n) 1 where the point belongs to the cutting head
  std::vector<ShellCluster> clusters;  // in point order; they partition the points
  double head_spacing_mm = 0.0;    // spacing the head was sampled at [mm]
  double shank_spacing_mm = 0.0;   // spacing elsewhere [mm]
  double total_area_mm2 = 0.0;     // sum of area_mm2 [mm^2]
  double tip_z_mm = 0.0;           // lowest z of the mesh, tool frame [mm]

  size_t size() const { return positions.size(); }
  size_t cuttingCount() const;
};

// Errors: an empty mesh, a spacing out of (0, 10] mm, a non-finite vertex, a mesh so large for its
// spacing that the shell would exceed 2 million points.
Result<PointShell> buildPointShell(const TriangleMesh& mesh, const PointShellOptions& options);

}  // namespace dentsim
