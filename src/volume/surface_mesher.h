// Surface extraction from the brick volume by marching cubes over the fill fraction: the CPU reference mesher.
//
// The scalar field is each voxel's solid share (fill / 31) at the voxel centre; the surface is its
// 0.5 level set, so it lies below the scale of one voxel. Cells span eight voxel centres and cross
// brick borders freely, so the surface has no cracks. The case table is generated in code from one
// rule per cube face, which both cells sharing the face apply alike: closed solids give closed,
// 2-manifold meshes.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/interrupter.h"
#include "core/result.h"
#include "core/triangle_mesh.h"
#include "volume/brick_volume.h"

namespace dentsim {

// A triangle surface with a normal and a tissue per vertex, in the volume's simulation frame [mm].
struct SurfaceMesh {
  std::vector<Vec3f> positions;                   // [mm]
  std::vector<Vec3f> normals;                     // unit, pointing out of the solid
  std::vector<Material> tissue;                   // tissue at the surface, per vertex
  std::vector<std::array<uint32_t, 3>> triangles; // counter-clockwise seen from outside

  size_t triangleCount() const { return triangles.size(); }
  TriangleMesh geometry() const;                  // positions and triangles only
};

struct SurfaceOptions {
  // Gradient neighbourhood for the normals: 8 (2^3), 64 (4^3) or 216 (6^3) voxels, the paper's modes.
  int normal_neighbours = 8;
  // Empty: the outer surface of all tissue. A tissue: the surface of that tissue alone (its voxels'
  // fill counts as solid, every other voxel as empty), for per-tissue export and round trips.
  Material tissue = Material::Empty;
};

// Meshes the whole volume. Errors: an unsupported normal mode, cancellation.
Result<SurfaceMesh> meshVolumeCpu(const ToothVolume& tooth, const SurfaceOptions& options,
                                  Interrupter& interrupter = nullInterrupter());

}  // namespace dentsim
