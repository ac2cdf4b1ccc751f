// VolumeFrame: where a voxel grid sits in the world, shared by the file readers and the brick volume.
#pragma once

#include <array>
#include <cstdint>

namespace dentsim {

// Placement of a 2^level voxel grid. It does not change after loading.
// Two frames matter: the simulation frame (axis-aligned with the grid, in mm) and the scanner
// frame of an imported CT (NIfTI world, possibly with flipped or rotated axes), kept so that an
// export overlays on the source in 3D Slicer or ITK-SNAP.
struct VolumeFrame {
  int level = 0;                              // octree level L: grid of 2^L voxels per side
  double voxel_mm = 0.0;                      // voxel edge length [mm]
  std::array<double, 3> origin_mm{0, 0, 0};   // simulation-frame position of voxel (0,0,0)'s corner [mm]
  std::array<int32_t, 3> source_offset{0, 0, 0};  // grid index of the imported source's voxel (0,0,0)
  std::array<int32_t, 3> source_dims{0, 0, 0};    // voxels of the imported source grid; 0 when none
  // Scanner position [mm] of the centre of grid voxel (i,j,k): row r is
  // scanner_from_grid[4r+0]*i + [4r+1]*j + [4r+2]*k + [4r+3]  (3 x 4, row-major).
  std::array<double, 12> scanner_from_grid{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};

  int64_t dim() const { return int64_t{1} << level; }  // voxels per side
  bool hasSource() const { return source_dims[0] > 0 && source_dims[1] > 0 && source_dims[2] > 0; }
  double voxelVolumeMm3() const { return voxel_mm * voxel_mm * voxel_mm; }

  // The frame of a grid with no scanner of its own: scanner = simulation frame.
  static VolumeFrame axisAligned(int level, double voxel_mm, std::array<double, 3> origin_mm) {
    VolumeFrame f;
    f.level = level;
    f.voxel_mm = voxel_mm;
    f.origin_mm = origin_mm;
    for (int r = 0; r < 3; ++r) {
      f.scanner_from_grid[4 * r + r] = voxel_mm;
      f.scanner_from_grid[4 * r + 3] = origin_mm[r] + 0.5 * voxel_mm;
    }
    return f;
  }
};

}  // namespace dentsim
