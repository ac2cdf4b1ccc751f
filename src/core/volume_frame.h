// VolumeFrame: where a voxel grid sits in the world, shared by the file readers and the brick volume.
#pragma once

#include <array>
#include <cstdint>

namespace dentsim {

// How an axis of the tooth's frame was known.
enum class AxisSource : uint8_t {
  Assumed = 0,  // not known: the convention (crown +z, mesial -x, buccal -y) stands in
  Found = 1,    // estimated from the tissues (the crown axis: where the enamel sits against the roots)
  Given = 2,    // given by whoever made the volume (voxelize --crown-axis, the built-in molar's generator)
};

// The tooth's own frame inside the simulation frame (docs/VOLUME.md, "The tooth's frame").
// `voxelize` turns the grid by quarter turns so that the crown axis lies nearest +z; what is left
// (a tooth standing a little tilted) stays in `crown`, unresampled. Distal is -mesial, lingual -buccal.
struct ToothAxes {
  std::array<double, 3> crown{0, 0, 1};     // unit: from the roots toward the crown
  std::array<double, 3> mesial{-1, 0, 0};   // unit, perpendicular to crown
  std::array<double, 3> buccal{0, -1, 0};   // unit, perpendicular to both
  AxisSource crown_source = AxisSource::Assumed;
  AxisSource mesial_source = AxisSource::Assumed;
  AxisSource buccal_source = AxisSource::Assumed;
  bool has_occlusal_centre = false;
  std::array<double, 3> occlusal_centre_mm{0, 0, 0};  // the middle of the occlusal surface, simulation frame [mm]
  // The quarter turn voxelize applied: simulation axis r = sum over c of turn[3r+c] * source axis c
  // (a signed permutation with determinant +1; identity when the tooth was not turned).
  std::array<int8_t, 9> turn{1, 0, 0, 0, 1, 0, 0, 0, 1};

  bool turned() const { return turn != std::array<int8_t, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1}; }
};

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
  ToothAxes tooth;  // the tooth's frame; files written before it existed load with the default

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
