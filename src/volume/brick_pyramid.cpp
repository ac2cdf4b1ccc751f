// Coarse copies of a brick volume, brick by brick, with whole empty or solid chunks copied as tiles.
#include "volume/brick_pyramid.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <optional>
#include <tuple>

namespace dentsim {

namespace {

// Summed fill per material beneath one coarse voxel; f^3 * 31 <= 512 * 31 fits 16 bits.
using FillSums = std::array<uint16_t, DS_MATERIAL_COUNT>;

Voxel coarseFromSums(const FillSums& sums, uint32_t count) {
  uint32_t total = 0, best = 0;
  size_t best_material = 0;
  for (size_t m = 1; m < sums.size(); ++m) {
    total += sums[m];
    if (sums[m] > best) {
      best = sums[m];
      best_material = m;
    }
  }
  const uint32_t fill = (total + count / 2) / count;
  if (fill == 0) return makeVoxel(Material::Empty);
  return makeVoxel(Material(best_material), fill);
}

// A voxel as the coarse rule sees f^3 copies of it: the same tissue and fill, or empty at fill 0.
Voxel normalised(Voxel v) { return voxelFill(v) == 0 ? makeVoxel(Material::Empty) : v; }

// Rewrites coarse brick c from the f^3 full bricks beneath it.
void downsampleBrick(const BrickVolume& fine, uint32_t k, BrickCoord c, BrickVolume& coarse) {
  const uint32_t f = 1u << k;
  const uint32_t per = DS_BRICK_DIM / f;  // coarse voxels per axis that one full brick covers (0 when f > 8)
  std::array<BrickView, 512> views;
  bool all_same = true;
  uint32_t n = 0;
  // f <= 8 here: k is at most 3 (see downsampleVolume), so f^3 <= 512 full bricks.
  for (uint32_t z = 0; z < f; ++z)
    for (uint32_t y = 0; y < f; ++y)
      for (uint32_t x = 0; x < f; ++x) {
        views[n] = fine.brick({c.x * f + x, c.y * f + y, c.z * f + z});
        all_same = all_same && views[n].uniform && views[n].value == views[0].value;
        ++n;
      }
  if (all_same) {
    coarse.setBrickUniform(c, normalised(views[0].value));
    return;
  }
  std::array<FillSums, DS_BRICK_VOXELS> sums{};
  n = 0;
  for (uint32_t z = 0; z < f; ++z)
    for (uint32_t y = 0; y < f; ++y)
      for (uint32_t x = 0; x < f; ++x) {
        const BrickView& v = views[n++];
        if (v.uniform) {
          const uint32_t fill = voxelFill(v.value);
          if (fill == 0) continue;
          const size_t m = size_t(voxelMaterial(v.value));
          // The full brick covers a per^3 box of coarse voxels, each over f^3 of its voxels.
          const uint32_t under = f * f * f;
          for (uint32_t cz = 0; cz < per; ++cz)
            for (uint32_t cy = 0; cy < per; ++cy)
              for (uint32_t cx = 0; cx < per; ++cx)
                sums[layout::brickCoordToOffset(x * per + cx, y * per + cy, z * per + cz)][m] +=
                    uint16_t(fill * under);
          continue;
        }
        for (uint32_t vz = 0; vz < DS_BRICK_DIM; ++vz)
          for (uint32_t vy = 0; vy < DS_BRICK_DIM; ++vy) {
            const Voxel* row = v.voxels + layout::brickCoordToOffset(0, vy, vz);
            const uint32_t cy = (y * DS_BRICK_DIM + vy) / f, cz = (z * DS_BRICK_DIM + vz) / f;
            for (uint32_t vx = 0; vx < DS_BRICK_DIM; ++vx) {
              const Voxel voxel = row[vx];
              const uint32_t fill = voxelFill(voxel);
              if (fill == 0) continue;
              sums[layout::brickCoordToOffset((x * DS_BRICK_DIM + vx) / f, cy, cz)][size_t(voxelMaterial(voxel))] +=
                  uint16_t(fill);
            }
          }
      }
  std::array<Voxel, DS_BRICK_VOXELS> out;
  for (size_t i = 0; i < out.size(); ++i) out[i] = coarseFromSums(sums[i], f * f * f);
  coarse.setBrick(c, out.data());
}

}  // namespace

Voxel coarseVoxelReference(const BrickVolume& fine, uint32_t x, uint32_t y, uint32_t z, uint32_t k) {
  const uint32_t f = 1u << k;
  FillSums sums{};
  for (uint32_t dz = 0; dz < f; ++dz)
    for (uint32_t dy = 0; dy < f; ++dy)
      for (uint32_t dx = 0; dx < f; ++dx) {
        const Voxel v = fine.voxel(x + dx, y + dy, z + dz);
        sums[size_t(voxelMaterial(v))] += uint16_t(voxelFill(v));
      }
  sums[size_t(Material::Empty)] = 0;
  return coarseFromSums(sums, f * f * f);
}

BrickVolume downsampleVolume(const BrickVolume& fine, uint32_t k) {
  assert(k >= 1 && k <= 3 && fine.level() - int(k) >= DS_MIN_LEVEL);
  const uint32_t f = 1u << k;
  BrickVolume coarse(fine.level() - int(k));
  const uint32_t cbd = coarse.brickDim(), fcd = fine.chunkDim();
  for (uint32_t cz = 0; cz < coarse.chunkDim(); ++cz)
    for (uint32_t cy = 0; cy < coarse.chunkDim(); ++cy)
      for (uint32_t cx = 0; cx < coarse.chunkDim(); ++cx) {
        // The coarse chunk's bricks, and the full chunks beneath them.
        const uint32_t lo[3] = {cx * DS_CHUNK_DIM, cy * DS_CHUNK_DIM, cz * DS_CHUNK_DIM};
        uint32_t hi[3], flo[3], fhi[3];
        for (int a = 0; a < 3; ++a) {
          hi[a] = std::min(lo[a] + DS_CHUNK_DIM, cbd);
          flo[a] = lo[a] * f / DS_CHUNK_DIM;
          fhi[a] = std::min(fcd, (hi[a] * f + DS_CHUNK_DIM - 1) / DS_CHUNK_DIM);
        }
        std::optional<Voxel> tile;
        bool tiled = true;
        for (uint32_t z = flo[2]; z < fhi[2] && tiled; ++z)
          for (uint32_t y = flo[1]; y < fhi[1] && tiled; ++y)
            for (uint32_t x = flo[0]; x < fhi[0] && tiled; ++x) {
              const std::optional<Voxel> t = fine.chunkTile(x, y, z);
              tiled = t && (!tile || *t == *tile);
              if (tiled) tile = t;
            }
        if (tiled && tile) {
          coarse.setChunkUniform(cx, cy, cz, normalised(*tile));
          continue;
        }
        for (uint32_t z = lo[2]; z < hi[2]; ++z)
          for (uint32_t y = lo[1]; y < hi[1]; ++y)
            for (uint32_t x = lo[0]; x < hi[0]; ++x) downsampleBrick(fine, k, {x, y, z}, coarse);
      }
  return coarse;
}

std::vector<BrickCoord> downsampleBricks(const BrickVolume& fine, uint32_t k, std::span<const BrickCoord> fine_dirty,
                                         BrickVolume& coarse) {
  assert(coarse.level() == fine.level() - int(k));
  std::vector<BrickCoord> out;
  out.reserve(fine_dirty.size());
  for (const BrickCoord& b : fine_dirty) out.push_back({b.x >> k, b.y >> k, b.z >> k});
  const auto key = [](const BrickCoord& b) { return std::tuple(b.z, b.y, b.x); };
  std::sort(out.begin(), out.end(), [&](const BrickCoord& a, const BrickCoord& b) { return key(a) < key(b); });
  out.erase(std::unique(out.begin(), out.end(), [&](const BrickCoord& a, const BrickCoord& b) { return key(a) == key(b); }),
            out.end());
  for (const BrickCoord& c : out) downsampleBrick(fine, k, c, coarse);
  return out;
}

}  // namespace dentsim
