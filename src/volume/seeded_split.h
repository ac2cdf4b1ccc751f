// Cutting one object of a mask from the objects it touches, at narrow joins: a seeded flood by depth (dynamics) over the distance transform.
//
// Entry point:
//   keepSeededPart(piece, dims, pitch, seed, h_mm, interrupter)  clears the voxels of `piece` that
//                                                                 do not belong to the seed's part
//
// The rule: every voxel's depth is the radius of the largest ball inscribed at it
// (distance_transform.h). Voxels are flooded from the deepest outwards; a voxel touching no flooded
// region starts one, whose peak is its depth. Where regions meet at a voxel, each region whose peak
// stands less than h above that voxel's depth joins the region with the highest peak; one that
// stands h or more above it stays apart. So two bulges (two teeth, a tooth and the bone) joined
// through a neck narrower than their own radii by h stay apart, and a part's own bumps merge.
// Depths are counted in steps of 1/16 of the smallest pitch, ties in scan order, and of two regions
// with equal peaks the first face neighbour's (forEachFaceNeighbour's order) wins.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/interrupter.h"

namespace dentsim {

// `piece` is a 0/1 grid of dims (i fastest) of at most 2^32 voxels; pitch its voxel edges [mm], each
// > 0; seed an index with piece[seed] == 1; h_mm >= 0 [mm] (0 keeps every peak apart). On return,
// piece holds 1 only where the seed's part lies. interrupter.progress sees fractions 0..1 of this
// job; false from it stops the job: the return is then false and piece is left unspecified.
// Memory: about 10 bytes a voxel while it runs (a float depth, then a 16-bit one, the flood order
// and a region id).
bool keepSeededPart(std::vector<uint8_t>& piece, const std::array<int32_t, 3>& dims, const std::array<double, 3>& pitch,
                    uint64_t seed, double h_mm, Interrupter& interrupter = nullInterrupter());

}  // namespace dentsim
