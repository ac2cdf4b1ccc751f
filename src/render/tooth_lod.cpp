// The per-region choice of copy: frustum, nearest depth, half a coarse voxel on screen, and the regions kept at full detail.
#include "render/tooth_lod.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace dentsim::render {

namespace {

constexpr double kRegionVoxels = double(kLodRegionBricks * DS_BRICK_DIM);  // 32
constexpr double kOverlapVoxels = 1.0;  // how far a copy's blocks reach past its regions [full voxels]
constexpr double kShadingShare = 0.25;  // the least error a coarse copy counts, in its own voxels

// Whether the box of eight clip-space corners lies wholly outside one plane of the view volume
// (Vulkan: -w <= x, y <= w and 0 <= z <= w).
bool outsideFrustum(const std::array<glm::vec4, 8>& c) {
  const auto all = [&](auto outside) {
    return std::all_of(c.begin(), c.end(), outside);
  };
  return all([](const glm::vec4& p) { return p.x < -p.w; }) || all([](const glm::vec4& p) { return p.x > p.w; }) ||
         all([](const glm::vec4& p) { return p.y < -p.w; }) || all([](const glm::vec4& p) { return p.y > p.w; }) ||
         all([](const glm::vec4& p) { return p.z < 0.0f; }) || all([](const glm::vec4& p) { return p.z > p.w; });
}

}  // namespace

bool LodChoice::drawsBlock(uint32_t k, MeshBlock b) const {
  const double scale = double(1u << k);
  int64_t lo[3], hi[3];
  const uint32_t c[3] = {b.x, b.y, b.z};
  for (int a = 0; a < 3; ++a) {
    // Cells of block b join the voxel centres 8b-1 .. 8b+7 of copy k: (8b - 0.5) .. (8b + 7.5)
    // coarse voxels from the grid's corner.
    const double from = (8.0 * c[a] - 0.5) * scale - kOverlapVoxels, to = (8.0 * c[a] + 7.5) * scale + kOverlapVoxels;
    lo[a] = std::max<int64_t>(0, int64_t(std::floor(from / kRegionVoxels)));
    hi[a] = std::min<int64_t>(int64_t(region_dim) - 1, int64_t(std::floor(to / kRegionVoxels)));
  }
  for (int64_t z = lo[2]; z <= hi[2]; ++z)
    for (int64_t y = lo[1]; y <= hi[1]; ++y)
      for (int64_t x = lo[0]; x <= hi[0]; ++x)
        if (at(uint32_t(x), uint32_t(y), uint32_t(z)) == k) return true;
  return false;
}

LodChoice chooseLod(const VolumeFrame& full, uint32_t coarse_copies, const LodView& view, const LodSettings& settings,
                    const LodRegions& regions) {
  const std::span<const std::vector<uint8_t>> ready = regions.ready;
  LodChoice choice;
  choice.region_dim = lodRegionDim(uint32_t(full.dim() >> DS_BRICK_LOG2));
  const uint32_t rd = choice.region_dim;
  choice.copy.assign(size_t(rd) * rd * rd, kLodHidden);
  const glm::mat4 view_proj = view.projection * view.view;
  const float focal_px = 0.5f * std::max(std::fabs(view.projection[0][0]) * float(view.width),
                                         std::fabs(view.projection[1][1]) * float(view.height));
  const double v = full.voxel_mm, dim = double(full.dim());
  const glm::vec3 origin(float(full.origin_mm[0]), float(full.origin_mm[1]), float(full.origin_mm[2]));
  for (uint32_t z = 0; z < rd; ++z)
    for (uint32_t y = 0; y < rd; ++y)
      for (uint32_t x = 0; x < rd; ++x) {
        const size_t index = (size_t(z) * rd + y) * rd + x;
        const uint32_t r[3] = {x, y, z};
        glm::vec3 lo, hi;
        for (int a = 0; a < 3; ++a) {
          lo[a] = origin[a] + float(double(r[a]) * kRegionVoxels * v);
          hi[a] = origin[a] + float(std::min(dim, double(r[a] + 1) * kRegionVoxels) * v);
        }
        std::array<glm::vec4, 8> clip;
        float nearest = INFINITY;
        for (int i = 0; i < 8; ++i) {
          const glm::vec4 p((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z, 1.0f);
          clip[size_t(i)] = view_proj * p;
          nearest = std::min(nearest, -(view.view * p).z);  // depth is linear, so a corner is nearest
        }
        if (outsideFrustum(clip)) continue;
        uint8_t k = 0;
        // Copy c's error here [full voxels]: measured, else half a voxel of it; never under a quarter
        // of its voxel, for what the measure does not see (its normals average a wider box, so its
        // shading differs over features smaller than its voxel).
        const auto error_voxels = [&](uint32_t c) {
          const double floor = kShadingShare * double(1u << c);
          if (c < regions.error.size() && regions.error[c].size() > index)
            return std::max(floor, double(regions.error[c][index]));
          return 0.5 * double(1u << c);
        };
        const bool keep_full =
            !(nearest > 0.0f) || settings.pixel_error <= 0.0f ||
            (view.bur_tip && glm::length(glm::clamp(*view.bur_tip, lo, hi) - *view.bur_tip) <= settings.bur_radius_mm);
        if (!keep_full) {
          const double px_per_mm = double(focal_px) / double(nearest);
          for (uint32_t c = coarse_copies; c >= 1 && k == 0; --c)
            if (error_voxels(c) * v * px_per_mm <= double(settings.pixel_error)) k = uint8_t(c);
        }
        const auto lags = [&](uint32_t c) {
          return c < regions.lagging.size() && regions.lagging[c].size() > index && regions.lagging[c][index];
        };
        const auto usable = [&](uint32_t c) { return (ready.empty() || ready[c][index]) && !lags(c); };
        if (!usable(k)) {
          // A copy that lags behind a cut gives way to a finer one (the full copy never lags); one not
          // yet meshed (a build in parts meshes the coarse copies first) to a coarser one.
          uint8_t alt = kLodHidden;
          const bool finer_first = lags(k);
          for (int pass = 0; pass < 2 && alt == kLodHidden; ++pass) {
            if ((pass == 0) == finer_first) {
              for (int c = int(k) - 1; c >= 0 && alt == kLodHidden; --c)
                if (usable(uint32_t(c))) alt = uint8_t(c);
            } else {
              for (uint32_t c = k + 1u; c <= coarse_copies && alt == kLodHidden; ++c)
                if (usable(c)) alt = uint8_t(c);
            }
          }
          k = alt;
        }
        choice.copy[index] = k;
      }
  return choice;
}

}  // namespace dentsim::render
