// A phantom scan as a clinical CT sees a tooth: a neighbour beside it, a slab of bone around its roots, and voxels a millimetre wide, to test what a head CT does to the segmentation.
//
// Contents
//   1. withNeighbourCopy: the tooth and a shifted copy of it, touching, in one label volume
//   2. addBoneSlab: bone-like grey values around the roots
//   3. averageOntoVoxel: the grey values averaged onto a coarser grid (a clinical scanner's voxels)
//   4. addScanNoise: the noise, added last, on the grid the scanner delivers
//
// `dentsim make-scan` runs them around simulateScan (volume/scan_model.h): neighbour, scan without
// noise, bone, average, noise. Averaging before the noise is what a scanner does: its detector
// integrates a voxel's whole volume, and its noise belongs to the voxel it reports.
#pragma once

#include <cstdint>
#include <string>

#include "core/result.h"
#include "io/grey_image.h"
#include "io/nifti_labels.h"

namespace dentsim {

// ---- 1. withNeighbourCopy ---------------------------------------------------------------------
// The labels widened along i by the tooth's own width (the extent of its non-zero labels), with a
// copy of every non-zero label shifted by that width: the neighbour touches the tooth where the two
// are widest, as adjacent teeth meet at their contact points. Error: no non-zero label.
Result<LabelImage> withNeighbourCopy(const LabelImage& labels, const std::string& where);

// ---- 2. addBoneSlab ---------------------------------------------------------------------------
// Every voxel in the lowest slab_mm of the tooth along k (from the first slice holding a non-zero
// label of `labels`, which share the image's grid) takes at least bone_value, across the whole
// slice: alveolar bone around the roots, fused to them as a clinical CT blurs the periodontal gap.
// The roots are taken to point to -k, as tooth_2's do. The canals in the slab read as bone too; at a
// clinical voxel they are below the resolution anyway. Returns the slab's slices, 0 when none.
int32_t addBoneSlab(GreyImage& image, const LabelImage& labels, double slab_mm, float bone_value);

// ---- 3. averageOntoVoxel ----------------------------------------------------------------------
// The image on a grid of voxel_mm (isotropic) over the same extent: each coarse voxel is the mean of
// the fine voxels whose centres fall in it, and its centre lies at the middle of those it covers. A
// voxel_mm finer than the image's pitch along an axis keeps that axis. Error: voxel_mm not positive.
Result<GreyImage> averageOntoVoxel(const GreyImage& image, double voxel_mm, const std::string& where);

// ---- 4. addScanNoise --------------------------------------------------------------------------
// Independent Gaussian noise of standard deviation sigma on every voxel, from a generator seeded
// with `seed`, in the order simulateScan draws it (so without the steps above the phantom is the
// same as make-scan's always was).
void addScanNoise(GreyImage& image, double sigma, uint32_t seed);

}  // namespace dentsim
