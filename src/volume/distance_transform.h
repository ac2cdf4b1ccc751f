// The exact Euclidean distance transform of a voxel mask, with anisotropic voxels: how deep each voxel lies inside.
//
// Entry point:
//   squaredDistanceToOutside(inside, dims, pitch)  per voxel, the squared distance [mm^2] to the
//                                                  nearest voxel centre outside the mask
//
// Exact, not a chamfer approximation: the transform is separable, so one pass per axis of
// Felzenszwalb & Huttenlocher's lower envelope of parabolas gives the true Euclidean distance in
// O(voxels). seeded_split reads it as the radius of the largest ball inscribed at each voxel.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace dentsim {

// `inside` is a 0/1 grid of dims (i fastest), pitch the voxel edges [mm], each > 0. Returns, per
// voxel, the squared distance [mm^2] between its centre and the nearest centre of a voxel of the
// grid with inside == 0: 0 outside the mask. Voxels beyond the grid do not count as outside, so a
// mask with no 0 voxel is infinitely deep (+inf everywhere). Memory: 4 bytes a voxel for the result.
std::vector<float> squaredDistanceToOutside(const std::vector<uint8_t>& inside, const std::array<int32_t, 3>& dims,
                                            const std::array<double, 3>& pitch);

}  // namespace dentsim
