// Mesh voxelization shared by the CPU reference and the GPU kernels: grid fitting, ray set-up and the CPU reference voxelizer.
//
// The rule both implementations follow (docs/VOXELIZE.md states it in full):
//   - Rays run along +z through S x S sub-sample points of every voxel column.
//   - A triangle covers a ray when the ray's (x,y) lies inside its projection, decided by edge
//     functions evaluated the same way by both triangles of a shared edge, with a tie rule that
//     gives a point on an edge or a vertex to exactly one triangle. Closed meshes are watertight.
//   - Each covering gives a hit: the depth z and whether the ray enters (+1) or leaves (-1).
//   - Along a ray a layer is inside where its winding number is not zero, so nested shells,
//     overlapping shells and inside-out meshes all fill. The material is that of the
//     highest-priority layer inside: pulp > caries > dentin > enamel.
//   - A ray whose hits on a layer do not balance passed through a hole in that layer; it borrows
//     that layer's hits from the nearest balanced ray within `hole_radius` sub-samples.
//   - A voxel's fill is the covered length along its rays over S^2 rays of one voxel each,
//     rounded to 1/31; its material is the one with the longest covered length.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/interrupter.h"
#include "core/result.h"
#include "core/triangle_mesh.h"
#include "core/volume_frame.h"
#include "volume/brick_volume.h"

namespace dentsim {

// One tissue layer: a closed (or nearly closed) surface and the material inside it.
struct MeshLayer {
  Material material = Material::Dentin;
  const TriangleMesh* mesh = nullptr;
  std::string name;  // for messages, e.g. the file name
};

struct VoxelizeOptions {
  int subsamples = 2;    // S: rays per voxel column side (1..4); S^2 rays per column
  int hole_radius = 8;   // how far, in sub-samples, a leaky ray looks for a balanced one
  // GPU only; 0 = automatic. Tests set them to force the band split and the pool regrowth that
  // large grids need.
  uint32_t max_band_chunk_rows = 0;  // chunk rows per band at most
  uint32_t initial_brick_capacity = 0;  // dense bricks the pool starts with
};

// Priority of a material when layers overlap: a higher value wins.
int materialPriority(Material m);

// The grid for a set of layers: a cube of 2^level voxels fitted to the union of their bounds with
// a margin of `margin_voxels` empty voxels on every side, centred. Errors if the bounds are empty.
Result<VolumeFrame> fitGridToLevel(const Bounds3& bounds, int level, int margin_voxels = 2);
// The smallest level whose voxel is at most voxel_mm with the same margin; the voxel is then
// exactly voxel_mm. Errors if that needs more than DS_MAX_LEVEL.
Result<VolumeFrame> fitGridToVoxelSize(const Bounds3& bounds, double voxel_mm, int margin_voxels = 2);

// Triangles of every layer moved into grid space, as both voxelizers consume them:
// x and y in sub-sample units (a voxel is S units wide, ray centres at half-integers) and z in
// voxels. Layers are sorted by priority, lowest first; the layer index is the priority rank.
struct RaySetup {
  int level = 0;
  int subsamples = 1;
  std::vector<Material> layer_material;      // per layer, lowest priority first
  std::vector<float> corners;                // 9 floats per triangle: x0 y0 z0 x1 y1 z1 x2 y2 z2
  std::vector<uint32_t> triangle_layer;      // layer index per triangle
  // Footprint rectangle of all triangles in sub-sample rays, half-open, clamped to the grid.
  uint32_t ray_x0 = 0, ray_y0 = 0, ray_x1 = 0, ray_y1 = 0;
};
Result<RaySetup> makeRaySetup(const std::vector<MeshLayer>& layers, const VolumeFrame& frame,
                              const VoxelizeOptions& options);

// Material code of each layer packed 4 bits a layer, lowest priority first (voxelize_layout.h).
uint32_t layerMaterialWord(const RaySetup& setup);

// The CPU reference voxelizer: exactly the rule above, one thread, no GPU.
Result<BrickVolume> voxelizeCpu(const RaySetup& setup, const VoxelizeOptions& options,
                                Interrupter& interrupter = nullInterrupter());

// The layers in a 2^level grid fitted to their bounds (fitGridToLevel), voxelized by the CPU
// reference and compacted: a whole tooth, the same bytes on every machine.
Result<ToothVolume> voxelizeLayersCpu(const std::vector<MeshLayer>& layers, int level, const VoxelizeOptions& options = {});

}  // namespace dentsim
