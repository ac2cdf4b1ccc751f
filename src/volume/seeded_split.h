// Cutting one object of a mask from the objects it touches, at narrow joins: a seeded flood by depth (dynamics) over the distance transform.
//
// Entry point:
//   keepSeededPart(piece, dims, pitch, seed, h_mm, seal_mm, interrupter)  clears the voxels of
//                                                 `piece` that do not belong to the seed's part
//
// The pulp first: a tooth's hard mask is hollow, and its walls around the pulp chamber and canals
// are thin, so in a transform of the mask itself the tooth's own parts meet at necks far below
// their cores and the cut parts them (a seed in a 1 mm phantom of a real molar kept 13 % of it).
// So the depth is taken of the piece with its enclosed holes filled: the empty space the piece
// encloses, after a closing of seal_mm seals openings narrower than about twice that (apical
// foramina). A closing also fills the narrow wedge beside a contact between two teeth, which would
// thicken the join; so a hole is filled only where it reaches a cavity that the seal's dilation
// leaves open (a chamber a ball of seal_mm fits in), and the wedge, thin everywhere, stays empty.
// The fill only shapes the depth and the flood: the filled voxels are never set in `piece`.
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
// > 0; seed an index with piece[seed] == 1; h_mm >= 0 [mm] (0 keeps every peak apart); seal_mm >= 0
// [mm], the closing radius for the fill, rounded to voxels of the smallest pitch (a cube of that
// half-side; 0 voxels: only holes enclosed as they are get filled). The outside is what a flood from
// the grid's border voxels reaches, so a hole open to the grid's edge is not filled. On return, piece holds 1 only where the
// seed's part lies. interrupter.progress sees fractions 0..1 of this job; false from it stops the
// job: the return is then false and piece is left unspecified.
// Memory: about 12 bytes a voxel while it runs (the filled grid and one scratch byte, a float depth,
// then a 16-bit one, the flood order and a region id).
bool keepSeededPart(std::vector<uint8_t>& piece, const std::array<int32_t, 3>& dims, const std::array<double, 3>& pitch,
                    uint64_t seed, double h_mm, double seal_mm, Interrupter& interrupter = nullInterrupter());

}  // namespace dentsim
