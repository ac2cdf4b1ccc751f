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
#include <span>
#include <vector>

#include "core/interrupter.h"
#include "core/result.h"
#include "core/triangle_mesh.h"
#include "volume/brick_volume.h"
#include "volume/normal_mode.h"
#include "volume/surface_layout.h"

namespace dentsim {

// A triangle surface with a normal and a tissue per vertex, in the volume's simulation frame [mm].
struct SurfaceMesh {
  std::vector<Vec3f> positions;                   // [mm]
  std::vector<Vec3f> normals;                     // unit, pointing out of the solid
  std::vector<Material> tissue;                   // tissue at the surface, per vertex
  std::vector<Material> across;                   // material on the outer side, per vertex: empty on
                                                  // the outer surface, a tissue at an interface
  std::vector<std::array<uint32_t, 3>> triangles; // counter-clockwise seen from outside

  size_t triangleCount() const { return triangles.size(); }
  TriangleMesh geometry() const;                  // positions and triangles only
};

struct SurfaceOptions {
  // Gradient neighbourhood for the normals: 8 (2^3), 64 (4^3) or 216 (6^3) voxels, the paper's modes.
  NormalMode normals = NormalMode::Box8;
  // Empty: the outer surface of all tissue. A tissue: the surface of that tissue alone (its voxels'
  // fill counts as solid, every other voxel as empty), for per-tissue export and round trips.
  Material tissue = Material::Empty;
};

// Meshes the whole volume. Errors: cancellation.
Result<SurfaceMesh> meshVolumeCpu(const ToothVolume& tooth, const SurfaceOptions& options,
                                  Interrupter& interrupter = nullInterrupter());

// ---- per-block meshing (the GPU kernels' reference; layout in surface_layout.h) -------------------

// A cell block's coordinate, each in [0, brickDim()].
struct MeshBlock {
  uint32_t x = 0, y = 0, z = 0;
  uint32_t packed() const { return layout::meshBlockPack(x, y, z); }
  static MeshBlock unpack(uint32_t b) { return {layout::meshBlockX(b), layout::meshBlockY(b), layout::meshBlockZ(b)}; }
  friend bool operator==(const MeshBlock&, const MeshBlock&) = default;
};

// One block's part of the surface, as the GPU writes it into the block's slot.
struct BlockMesh {
  MeshBlock block;
  std::vector<layout::MeshVertex> vertices;  // in local edge order
  std::vector<uint32_t> indices;             // 3 per triangle, local to `vertices`
};

// Blocks that can hold surface: the bricks their corners read are not all inside or all outside.
// Ordered by packed coordinate (z, then y, then x).
std::vector<MeshBlock> activeMeshBlocks(const BrickVolume& volume, Material tissue);
// Blocks whose cells or normals read a voxel of any of `bricks` (the 3^3 blocks around each),
// sorted and unique.
std::vector<MeshBlock> blocksReadingBricks(const BrickVolume& volume, std::span<const BrickCoord> bricks);
// Whether each of `candidates` can hold surface (the test activeMeshBlocks applies), reading each
// brick once: active[i] for candidates[i].
std::vector<bool> meshBlocksActive(const BrickVolume& volume, Material tissue, std::span<const MeshBlock> candidates);

// Meshes one block exactly as the GPU does: same vertices in the same order, same triangles. The
// positions agree with the GPU's up to the rounding of one division, the normals to their packing.
BlockMesh meshBlockCpu(const BrickVolume& volume, MeshBlock block, Material tissue, uint32_t side);

// The case table as the GPU reads it: DS_MESH_CASE_WORDS words per corner configuration.
std::vector<uint32_t> packedMeshCaseTable();

// The octahedral normal of MeshVertex.packed, unit length.
Vec3f unpackMeshNormal(uint32_t packed);

// Joins blocks into one mesh in millimetres, welding the copies of a vertex that neighbouring blocks
// share (same position bits). Tissue per vertex from the packed word.
SurfaceMesh weldBlockMeshes(std::span<const BlockMesh> blocks, const VolumeFrame& frame);

}  // namespace dentsim
