// The known answer for synthesized layers: a layered tooth made one shape, and synthesized layers compared with the real ones (volume/tooth_layer_compare.h).
#include "volume/tooth_layer_compare.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include "volume/crown_estimate.h"
#include "volume/tissue_table.h"
#include "volume/tooth_frame.h"

namespace dentsim {

BrickVolume wholeToothShape(const BrickVolume& layered) {
  BrickVolume shape = layered;
  layered.forEachDenseBrick([&](const BrickView& b) {
    Voxel* out = shape.writableBrick(b.coord);
    for (uint32_t o = 0; o < DS_BRICK_VOXELS; ++o)
      if (isToothTissue(voxelMaterial(b.voxels[o]))) out[o] = makeVoxel(Material::Dentin, voxelFill(b.voxels[o]));
  });
  layered.forEachBrick([&](const BrickView& b) {
    if (b.uniform && isToothTissue(voxelMaterial(b.value)))
      shape.setBrickUniform(b.coord, makeVoxel(Material::Dentin, voxelFill(b.value)));
  });
  return shape;
}

LayerComparison compareLayers(const BrickVolume& real, const BrickVolume& synth, double voxel_mm,
                              const Vec3& synth_crown) {
  assert(real.level() == synth.level());
  const auto as_compared = [](Voxel v) {
    const Material m = voxelMaterial(v);
    if (voxelFill(v) == 0 || !isToothTissue(m)) return Material::Empty;
    return m == Material::Caries ? Material::Dentin : m;
  };
  std::array<uint64_t, DS_MATERIAL_COUNT> in_real{}, in_synth{}, in_both{}, faces_real{}, faces_synth{};
  const uint32_t n = real.dim();
  const auto rb = tissueVoxelBoxes(real)[0], sb = tissueVoxelBoxes(synth)[0];
  if (rb.empty() && sb.empty()) return {};
  std::array<int64_t, 3> lo{}, hi{};
  for (size_t a = 0; a < 3; ++a) {
    lo[a] = std::max<int64_t>(0, std::min(rb.empty() ? sb.lo[a] : rb.lo[a], sb.empty() ? rb.lo[a] : sb.lo[a]) - 1);
    hi[a] = std::min<int64_t>(n - 1, std::max(rb.empty() ? sb.hi[a] : rb.hi[a], sb.empty() ? rb.hi[a] : sb.hi[a]) + 1);
  }
  const auto at = [&](const BrickVolume& v, int64_t x, int64_t y, int64_t z) {
    if (x < 0 || y < 0 || z < 0 || x >= n || y >= n || z >= n) return Material::Empty;
    return as_compared(v.voxel(uint32_t(x), uint32_t(y), uint32_t(z)));
  };
  for (int64_t z = lo[2]; z <= hi[2]; ++z)
    for (int64_t y = lo[1]; y <= hi[1]; ++y)
      for (int64_t x = lo[0]; x <= hi[0]; ++x) {
        const Material a = at(real, x, y, z), b = at(synth, x, y, z);
        ++in_real[size_t(a)];
        ++in_synth[size_t(b)];
        if (a == b) ++in_both[size_t(a)];
        // The enamel's outer area: its faces toward empty, for the mean thickness.
        if (a != Material::Enamel && b != Material::Enamel) continue;
        const int64_t off[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
        for (const auto& o : off) {
          if (a == Material::Enamel) faces_real[DS_MAT_ENAMEL] += at(real, x + o[0], y + o[1], z + o[2]) == Material::Empty;
          if (b == Material::Enamel) faces_synth[DS_MAT_ENAMEL] += at(synth, x + o[0], y + o[1], z + o[2]) == Material::Empty;
        }
      }
  const auto dice = [&](Material m) {
    const double total = double(in_real[size_t(m)] + in_synth[size_t(m)]);
    return total > 0 ? 2.0 * double(in_both[size_t(m)]) / total : 1.0;
  };
  LayerComparison c;
  c.dice_enamel = dice(Material::Enamel);
  c.dice_dentin = dice(Material::Dentin);
  c.dice_pulp = dice(Material::Pulp);
  const auto thickness = [&](uint64_t voxels, uint64_t faces) {
    return faces > 0 ? double(voxels) / double(faces) * voxel_mm : 0.0;
  };
  c.enamel_mm_real = thickness(in_real[DS_MAT_ENAMEL], faces_real[DS_MAT_ENAMEL]);
  c.enamel_mm_synth = thickness(in_synth[DS_MAT_ENAMEL], faces_synth[DS_MAT_ENAMEL]);
  c.enamel_error_mm = std::abs(c.enamel_mm_synth - c.enamel_mm_real);
  c.measured_crown = estimateCrown(real).axis;
  const double cosine = std::clamp(dot(normalized(c.measured_crown), normalized(synth_crown)), -1.0, 1.0);
  c.axis_angle_deg = std::acos(cosine) * 180.0 / M_PI;
  return c;
}

}  // namespace dentsim
