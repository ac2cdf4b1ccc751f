// The clinical CT's additions to a phantom: neighbour, bone slab, coarse voxels, noise (volume/clinical_phantom.h).
#include "volume/clinical_phantom.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace dentsim {

Result<LabelImage> withNeighbourCopy(const LabelImage& labels, const std::string& where) {
  int64_t lo = labels.dims[0], hi = -1;
  for (int64_t k = 0; k < labels.dims[2]; ++k)
    for (int64_t j = 0; j < labels.dims[1]; ++j)
      for (int64_t i = 0; i < labels.dims[0]; ++i)
        if (labels.labels[labels.index(i, j, k)] != 0) lo = std::min(lo, i), hi = std::max(hi, i);
  if (hi < 0) return makeError(where, "no tissue to copy as a neighbour");
  const int64_t width = hi - lo + 1;
  LabelImage out;
  out.dims = {int32_t(labels.dims[0] + width), labels.dims[1], labels.dims[2]};
  out.pitch_mm = labels.pitch_mm;
  out.scanner_from_voxel = labels.scanner_from_voxel;
  out.labels.assign(size_t(out.voxelCount()), 0);
  for (int64_t k = 0; k < labels.dims[2]; ++k)
    for (int64_t j = 0; j < labels.dims[1]; ++j)
      for (int64_t i = 0; i < labels.dims[0]; ++i) {
        const Label l = labels.labels[labels.index(i, j, k)];
        if (l == 0) continue;
        out.labels[out.index(i, j, k)] = l;
        // The tooth keeps its own voxels where the two overlap.
        Label& copy = out.labels[out.index(i + width, j, k)];
        if (i + width >= labels.dims[0] || labels.labels[labels.index(i + width, j, k)] == 0) copy = l;
      }
  return out;
}

int32_t addBoneSlab(GreyImage& image, const LabelImage& labels, double slab_mm, float bone_value) {
  if (!(slab_mm > 0) || labels.voxelCount() != image.voxelCount()) return 0;
  int64_t first = -1;
  for (int64_t v = 0; v < labels.voxelCount() && first < 0; ++v)
    if (labels.labels[size_t(v)] != 0) first = v / (int64_t{labels.dims[0]} * labels.dims[1]);
  if (first < 0) return 0;
  const int64_t slices = std::min<int64_t>(int64_t(std::lround(slab_mm / image.pitch_mm[2])), image.dims[2] - first);
  const size_t plane = size_t(image.dims[0]) * size_t(image.dims[1]);
  for (size_t v = size_t(first) * plane; v < size_t(first + slices) * plane; ++v)
    image.values[v] = std::max(image.values[v], bone_value);
  return int32_t(slices);
}

Result<GreyImage> averageOntoVoxel(const GreyImage& image, double voxel_mm, const std::string& where) {
  if (!(voxel_mm > 0) || !std::isfinite(voxel_mm)) return makeError(where, "the scan's voxel must be a positive size");
  GreyImage out = image;
  out.values.clear();
  std::array<double, 3> ratio{};  // fine voxels a coarse one spans, along each axis
  for (size_t a = 0; a < 3; ++a) {
    ratio[a] = std::max(1.0, voxel_mm / image.pitch_mm[a]);
    // Every coarse voxel takes at least one fine one; the last may take fewer than ratio.
    out.dims[a] = int32_t(double(image.dims[a] - 1) / ratio[a]) + 1;
    out.pitch_mm[a] = image.pitch_mm[a] * ratio[a];
  }
  // A coarse centre sits at fine coordinate (q + 0.5) * ratio - 0.5: the columns scale and the
  // origin moves by half a coarse voxel less half a fine one.
  for (size_t r = 0; r < 3; ++r) {
    for (size_t a = 0; a < 3; ++a) {
      out.scanner_from_voxel[4 * r + a] = image.scanner_from_voxel[4 * r + a] * ratio[a];
      out.scanner_from_voxel[4 * r + 3] += image.scanner_from_voxel[4 * r + a] * (0.5 * ratio[a] - 0.5);
    }
  }
  std::vector<double> sum(size_t(out.voxelCount()), 0.0);
  std::vector<uint32_t> count(sum.size(), 0);
  const auto coarse = [&](int64_t i, size_t a) {
    return std::min<int64_t>(int64_t(double(i) / ratio[a]), out.dims[a] - 1);
  };
  for (int64_t k = 0; k < image.dims[2]; ++k)
    for (int64_t j = 0; j < image.dims[1]; ++j)
      for (int64_t i = 0; i < image.dims[0]; ++i) {
        const size_t q = out.index(coarse(i, 0), coarse(j, 1), coarse(k, 2));
        sum[q] += image.values[image.index(i, j, k)];
        ++count[q];
      }
  out.values.resize(sum.size());
  for (size_t q = 0; q < sum.size(); ++q) out.values[q] = count[q] ? float(sum[q] / count[q]) : 0.0f;
  return out;
}

void addScanNoise(GreyImage& image, double sigma, uint32_t seed) {
  if (!(sigma > 0)) return;
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, float(sigma));
  for (float& v : image.values) v += noise(rng);
}

}  // namespace dentsim
