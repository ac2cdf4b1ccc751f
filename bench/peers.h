// Peer libraries measured beside dentsim in the same run (OpenVDB, VTK); each is compiled in only when installed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/triangle_mesh.h"
#include "volume/brick_volume.h"

namespace dentsim::bench {

// Memory of an OpenVDB tree holding the same voxels' labels (uint8, 5-4-3 tree, pruned to tiles).
struct PeerMemory {
  bool available = false;   // false when dentsim was built without OpenVDB
  std::string name;         // "OpenVDB 10.0.1 uint8 label tree"
  uint64_t bytes = 0;       // Tree::memUsage() [B]
  uint64_t leaf_nodes = 0;  // leaves after pruning
  double build_s = 0.0;     // time to fill and prune [s]
};

PeerMemory openvdbLabelTreeMemory(const BrickVolume& volume);

// How OpenVDB is asked to voxelize: the solid filled with stored distances (what a voxelizer
// delivers, and the paper's comparison) or its usual narrow-band level set, where the inside is
// known by sign only (tiles and inactive values).
enum class VdbInterior { Filled, NarrowBand };

// One closed surface turned into an OpenVDB level set by meshToVolume.
struct PeerVoxelize {
  bool available = false;        // false when dentsim was built without OpenVDB
  std::string name;              // "OpenVDB 10.0.1 meshToVolume<FloatGrid>, interior filled"
  int threads = 0;               // TBB worker threads it could use
  double ms = 0.0;               // wall time of meshToVolume alone [ms]
  uint64_t interior_voxels = 0;  // voxels whose centre has a negative distance (inside)
  uint64_t active_voxels = 0;    // stored distance values
  uint64_t leaf_nodes = 0;       // 8^3 leaves of the result
  double interior_mm3 = 0.0;     // interior_voxels x voxel volume [mm^3]
};

// Voxelizes `mesh` into a grid of `voxel_mm` whose voxel (0,0,0) has its lower corner at
// `origin_mm`, so its voxel centres coincide with those of dentsim's grid in the same frame.
// Filled: exterior band 1 voxel (the least that classifies the surface), interior unbounded.
// NarrowBand: OpenVDB's default half-width of 3 voxels on both sides.
PeerVoxelize openvdbMeshToVolume(const TriangleMesh& mesh, double voxel_mm, const Vec3d& origin_mm,
                                 VdbInterior interior = VdbInterior::Filled);

// ---- VTK ----------------------------------------------------------------------------------------

// One marching-cubes surface of the same voxels by VTK's vtkFlyingEdges3D.
struct PeerMesh {
  bool available = false;      // it ran
  std::string name;            // "VTK 9.1.0 vtkFlyingEdges3D (TBB)"
  std::string skipped;         // why it did not run (not built in, not enough memory); empty when it ran
  int threads = 0;             // threads vtkSMPTools estimates it uses
  uint64_t image_bytes = 0;    // bytes of the dense image (one per voxel) [B]
  double image_ms = 0.0;       // time to copy the bricks into the dense image [ms]
  std::vector<double> runs_ms; // (repeats) time of the filter's Update() alone [ms]
  double ms = 0.0;             // median of runs_ms [ms]
  uint64_t triangles = 0;      // triangles of the result
  uint64_t points = 0;         // points of the result: one per crossed lattice edge
};

// Copies the voxels into a dense vtkImageData (one unsigned char per voxel, the fill 0..31, a voxel
// of another tissue than `tissue` counting as 0; Material::Empty counts every tissue), one point per
// voxel centre in voxel units, and runs vtkFlyingEdges3D at 15.5, which is phi = 0.5, with gradient
// normals on: `repeats` times on the same image, a new filter each time. Voxels outside the grid are
// not seen, so a solid touching the grid border stays open there where dentsim's surface closes.
// Skips, saying so, when the image and the filter's per-voxel edge cases would not fit in the memory
// available now. Touches no dentsim data.
PeerMesh vtkFlyingEdges(const BrickVolume& volume, Material tissue = Material::Empty, int repeats = 1);

}  // namespace dentsim::bench
