// The phantom scanner: tissue values, a separable Gaussian blur and seeded Gaussian noise over a label grid.
#include "volume/scan_model.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "volume/tissue_table.h"

namespace dentsim {
namespace {

// Normalised Gaussian taps out to 3 sigma, in voxels of `pitch`.
std::vector<float> gaussianTaps(double sigma_mm, double pitch_mm) {
  const double sigma = sigma_mm / pitch_mm;
  const int radius = std::max(1, int(std::ceil(3.0 * sigma)));
  std::vector<float> taps(size_t(2 * radius + 1));
  double sum = 0;
  for (int t = -radius; t <= radius; ++t) {
    const double w = std::exp(-0.5 * double(t * t) / (sigma * sigma));
    taps[size_t(t + radius)] = float(w);
    sum += w;
  }
  for (float& w : taps) w = float(w / sum);
  return taps;
}

// Blurs every line along `axis` in place (line buffer, border value repeated).
void blurAxis(GreyImage& g, int axis, const std::vector<float>& taps) {
  const int64_t n[3] = {g.dims[0], g.dims[1], g.dims[2]};
  const int64_t stride[3] = {1, n[0], n[0] * n[1]};
  const int radius = int(taps.size() / 2);
  const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
  std::vector<float> line(size_t(n[axis] + 2 * radius));
  for (int64_t v = 0; v < n[a2]; ++v)
    for (int64_t u = 0; u < n[a1]; ++u) {
      float* base = g.values.data() + u * stride[a1] + v * stride[a2];
      for (int64_t t = -radius; t < n[axis] + radius; ++t)
        line[size_t(t + radius)] = base[std::clamp<int64_t>(t, 0, n[axis] - 1) * stride[axis]];
      for (int64_t t = 0; t < n[axis]; ++t) {
        float sum = 0;
        const float* src = &line[size_t(t)];
        for (size_t q = 0; q < taps.size(); ++q) sum += taps[q] * src[q];
        base[t * stride[axis]] = sum;
      }
    }
}

}  // namespace

Result<GreyImage> simulateScan(const LabelImage& labels, const std::map<int32_t, Material>& map, const ScanModel& model,
                               double pitch_mm, const std::string& where, Interrupter& interrupter) {
  if (labels.labels.size() != size_t(labels.voxelCount()) || labels.voxelCount() == 0)
    return makeError(where, "the label image has no voxels");
  if (!(model.blur_mm >= 0) || !(model.noise >= 0)) return makeError(where, "blur and noise must be 0 or more");
  // Label -> value through a table over the int16 range.
  std::vector<float> value_of(65536, model.value[0]);
  std::vector<bool> known(65536, false);
  known[32768] = true;  // label 0: empty
  for (const auto& [label, tissue] : map) {
    if (label < -32768 || label > 32767) return makeError(where, "label " + std::to_string(label) + " is out of range");
    value_of[size_t(label + 32768)] = model.value[size_t(tissue)];
    known[size_t(label + 32768)] = true;
  }
  interrupter.start("scanning the phantom");
  GreyImage g;
  g.dims = labels.dims;
  g.pitch_mm = labels.pitch_mm;
  g.scanner_from_voxel = labels.scanner_from_voxel;
  if (pitch_mm > 0) {
    g.pitch_mm = {pitch_mm, pitch_mm, pitch_mm};
    g.scanner_from_voxel = scannerWithPitch(g.scanner_from_voxel, g.pitch_mm);
  }
  g.unit = model.unit;
  g.modality = "CT";
  g.description = "dentsim phantom";
  g.values.resize(labels.labels.size());
  for (size_t v = 0; v < labels.labels.size(); ++v) {
    const size_t slot = size_t(int32_t(labels.labels[v]) + 32768);
    if (!known[slot])
      return makeError(where, "label " + std::to_string(labels.labels[v]) + " is not in the label map");
    g.values[v] = value_of[slot];
  }
  if (!interrupter.progress(0.1)) return makeError(where, "cancelled");
  if (model.blur_mm > 0)
    for (int axis = 0; axis < 3; ++axis) {
      blurAxis(g, axis, gaussianTaps(model.blur_mm, g.pitch_mm[size_t(axis)]));
      if (!interrupter.progress(0.1 + 0.25 * (axis + 1))) return makeError(where, "cancelled");
    }
  if (model.noise > 0) {
    std::mt19937 rng(model.seed);
    std::normal_distribution<float> noise(0.0f, float(model.noise));
    for (float& v : g.values) v += noise(rng);
  }
  interrupter.end();
  return g;
}

}  // namespace dentsim
