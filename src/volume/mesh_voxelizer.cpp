// CPU reference voxelizer of mesh layers, grid fitting and the ray set-up both voxelizers share.
#include "volume/mesh_voxelizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <numeric>

#include "volume/voxelize_layout.h"

namespace dentsim {

using namespace layout;

int materialPriority(Material m) {
  for (int i = 0; i < 4; ++i)
    if (((DS_VOX_PRIORITY_ORDER >> (4 * i)) & 15u) == uint32_t(m) && m != Material::Empty) return i + 1;
  return 0;
}

namespace {

Result<VolumeFrame> frameFor(const Bounds3& bounds, int level, double voxel_mm) {
  const double dim = double(int64_t{1} << level);
  std::array<double, 3> origin{};
  for (int a = 0; a < 3; ++a) origin[a] = 0.5 * (bounds.lo[a] + bounds.hi[a]) - 0.5 * dim * voxel_mm;
  return VolumeFrame::axisAligned(level, voxel_mm, origin);
}

Status checkBounds(const Bounds3& bounds) {
  if (bounds.empty() || !(bounds.maxExtent() > 0.0) || !std::isfinite(bounds.maxExtent()))
    return makeError("voxelize", "the meshes have no extent to fit a grid to");
  return Ok{};
}

}  // namespace

Result<VolumeFrame> fitGridToLevel(const Bounds3& bounds, int level, int margin_voxels) {
  if (auto s = checkBounds(bounds); !s) return s.error();
  if (level < DS_MIN_LEVEL || level > DS_MAX_LEVEL)
    return makeError("voxelize", "level " + std::to_string(level) + " outside " + std::to_string(DS_MIN_LEVEL) +
                                     ".." + std::to_string(DS_MAX_LEVEL));
  const int64_t usable = (int64_t{1} << level) - 2 * int64_t(margin_voxels);
  if (usable < 1) return makeError("voxelize", "level " + std::to_string(level) + " leaves no room inside the margin");
  return frameFor(bounds, level, bounds.maxExtent() / double(usable));
}

Result<VolumeFrame> fitGridToVoxelSize(const Bounds3& bounds, double voxel_mm, int margin_voxels) {
  if (auto s = checkBounds(bounds); !s) return s.error();
  if (!(voxel_mm > 0.0) || !std::isfinite(voxel_mm))
    return makeError("voxelize", "voxel size must be a positive number of mm");
  const double needed = std::ceil(bounds.maxExtent() / voxel_mm) + 2.0 * margin_voxels;
  for (int level = DS_MIN_LEVEL; level <= DS_MAX_LEVEL; ++level)
    if (double(int64_t{1} << level) >= needed) return frameFor(bounds, level, voxel_mm);
  std::ostringstream msg;  // shortest form: a hostile size must not print 300 digits
  msg << "a voxel of " << voxel_mm << " mm needs a grid above level " << DS_MAX_LEVEL << " for an extent of "
      << bounds.maxExtent() << " mm";
  return makeError("voxelize", msg.str());
}

Result<RaySetup> makeRaySetup(const std::vector<MeshLayer>& layers, const VolumeFrame& frame,
                              const VoxelizeOptions& options) {
  const std::string where = "voxelize";
  if (layers.empty()) return makeError(where, "no mesh layers given");
  if (layers.size() > DS_VOX_MAX_LAYERS)
    return makeError(where, std::to_string(layers.size()) + " layers given, at most " +
                                std::to_string(DS_VOX_MAX_LAYERS) + " are supported");
  if (options.subsamples < 1 || options.subsamples > int(DS_VOX_MAX_SUBSAMPLES))
    return makeError(where, "subsamples must be 1.." + std::to_string(DS_VOX_MAX_SUBSAMPLES));
  if (options.hole_radius < 0 || options.hole_radius > 64) return makeError(where, "hole radius must be 0..64");
  if (frame.level < DS_MIN_LEVEL || frame.level > DS_MAX_LEVEL || !(frame.voxel_mm > 0.0))
    return makeError(where, "invalid grid");
  const uint64_t rays_per_side = (uint64_t{1} << frame.level) * uint64_t(options.subsamples);
  if (rays_per_side > (uint64_t{1} << 15))
    return makeError(where, "level " + std::to_string(frame.level) + " with " + std::to_string(options.subsamples) +
                                " subsamples needs more than 32768 rays per side");

  std::vector<size_t> order(layers.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return materialPriority(layers[a].material) < materialPriority(layers[b].material);
  });

  RaySetup setup;
  setup.level = frame.level;
  setup.subsamples = options.subsamples;
  size_t triangles = 0;
  for (const MeshLayer& layer : layers) {
    const std::string name = layer.name.empty() ? materialName(layer.material) : layer.name;
    if (materialPriority(layer.material) == 0) return makeError(name, "a layer must hold a tissue, not empty");
    if (!layer.mesh || layer.mesh->triangles.empty()) return makeError(name, "the layer has no triangles");
    triangles += layer.mesh->triangles.size();
  }
  setup.corners.reserve(triangles * 9);
  setup.triangle_layer.reserve(triangles);

  const double S = options.subsamples;
  const double inv = 1.0 / frame.voxel_mm;
  double lo_x = INFINITY, lo_y = INFINITY, hi_x = -INFINITY, hi_y = -INFINITY;
  for (size_t rank = 0; rank < order.size(); ++rank) {
    const MeshLayer& layer = layers[order[rank]];
    setup.layer_material.push_back(layer.material);
    const TriangleMesh& mesh = *layer.mesh;
    std::vector<std::array<float, 3>> grid(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const Vec3f& p = mesh.positions[v];
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        return makeError(layer.name, "vertex " + std::to_string(v) + " is not a finite number");
      const double x = (double(p[0]) - frame.origin_mm[0]) * inv * S;
      const double y = (double(p[1]) - frame.origin_mm[1]) * inv * S;
      const double z = (double(p[2]) - frame.origin_mm[2]) * inv;
      grid[v] = {float(x), float(y), float(z)};
      lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x);
      lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
    }
    for (const auto& t : mesh.triangles) {
      for (uint32_t c : t) {
        if (c >= grid.size()) return makeError(layer.name, "a triangle indexes a missing vertex");
        setup.corners.insert(setup.corners.end(), grid[c].begin(), grid[c].end());
      }
      setup.triangle_layer.push_back(uint32_t(rank));
    }
  }
  const uint32_t limit = uint32_t(rays_per_side);
  voxRaySpan(float(std::max(lo_x, -1.0)), float(std::min(hi_x, double(limit) + 1.0)), limit, setup.ray_x0,
             setup.ray_x1);
  voxRaySpan(float(std::max(lo_y, -1.0)), float(std::min(hi_y, double(limit) + 1.0)), limit, setup.ray_y0,
             setup.ray_y1);
  return setup;
}

uint32_t layerMaterialWord(const RaySetup& setup) {
  uint32_t word = 0;
  for (size_t l = 0; l < setup.layer_material.size(); ++l) word |= uint32_t(setup.layer_material[l]) << (4 * l);
  return word;
}

namespace {

// Rays of the footprint rectangle with their sorted hit keys.
struct RayHits {
  uint32_t x0 = 0, y0 = 0, w = 0, h = 0;
  std::vector<std::vector<uint32_t>> keys;  // per ray, row-major
  std::vector<uint32_t> leaky;              // per ray: mask of layers whose hits do not balance

  bool inside(int64_t x, int64_t y) const {
    return x >= int64_t(x0) && y >= int64_t(y0) && x < int64_t(x0 + w) && y < int64_t(y0 + h);
  }
  size_t index(uint32_t x, uint32_t y) const { return size_t(y - y0) * w + (x - x0); }
};

RayHits castRays(const RaySetup& setup) {
  RayHits rays;
  rays.x0 = setup.ray_x0;
  rays.y0 = setup.ray_y0;
  rays.w = setup.ray_x1 - setup.ray_x0;
  rays.h = setup.ray_y1 - setup.ray_y0;
  rays.keys.resize(size_t(rays.w) * rays.h);
  rays.leaky.assign(rays.keys.size(), 0);
  const size_t triangles = setup.triangle_layer.size();
  for (size_t t = 0; t < triangles; ++t) {
    const float* c = &setup.corners[t * 9];
    uint32_t ix0, ix1, iy0, iy1;
    voxRaySpan(std::min({c[0], c[3], c[6]}), std::max({c[0], c[3], c[6]}), setup.ray_x1, ix0, ix1);
    voxRaySpan(std::min({c[1], c[4], c[7]}), std::max({c[1], c[4], c[7]}), setup.ray_y1, iy0, iy1);
    ix0 = std::max(ix0, rays.x0);
    iy0 = std::max(iy0, rays.y0);
    for (uint32_t y = iy0; y < iy1; ++y)
      for (uint32_t x = ix0; x < ix1; ++x) {
        float depth;
        uint32_t entering;
        if (!voxRayHitsTriangle(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], float(x) + 0.5f,
                                float(y) + 0.5f, depth, entering))
          continue;
        rays.keys[rays.index(x, y)].push_back(
            voxHitKey(voxQuantiseDepth(depth, uint32_t(setup.level)), setup.triangle_layer[t], entering));
      }
  }
  for (size_t r = 0; r < rays.keys.size(); ++r) {
    std::sort(rays.keys[r].begin(), rays.keys[r].end());
    uint32_t winding = 0;
    for (uint32_t key : rays.keys[r]) winding = voxWindingStep(winding, key);
    for (uint32_t l = 0; l < DS_VOX_MAX_LAYERS; ++l)
      if (((winding >> (8 * l)) & 0xffu) != 0) rays.leaky[r] |= 1u << l;
  }
  return rays;
}

// The ray a leaky ray borrows `layer` from: the first balanced ray in rings of growing Chebyshev
// radius, each ring scanned row by row. A ray outside the footprint has no hits and so is balanced.
// Returns false when none lies within the radius; *donor is then left unset.
bool findDonor(const RayHits& rays, uint32_t x, uint32_t y, uint32_t layer, int radius, int64_t* donor) {
  for (int r = 1; r <= radius; ++r)
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        if (std::max(std::abs(dx), std::abs(dy)) != r) continue;
        const int64_t cx = int64_t(x) + dx, cy = int64_t(y) + dy;
        if (!rays.inside(cx, cy)) {
          *donor = -1;
          return true;
        }
        const size_t i = rays.index(uint32_t(cx), uint32_t(cy));
        if (((rays.leaky[i] >> layer) & 1u) == 0) {
          *donor = int64_t(i);
          return true;
        }
      }
  return false;
}

}  // namespace

Result<BrickVolume> voxelizeCpu(const RaySetup& setup, const VoxelizeOptions& options, Interrupter& interrupter) {
  interrupter.start("voxelize (CPU reference)");
  BrickVolume volume(setup.level);
  const RayHits rays = castRays(setup);
  const uint32_t S = uint32_t(setup.subsamples);
  const uint32_t dim = 1u << setup.level;
  const uint32_t unit = voxDepthPerVoxel(uint32_t(setup.level));
  const uint32_t full = S * S * unit;
  const uint32_t materials = layerMaterialWord(setup);

  // The layers that a ray replaces from a donor, and the donor's keys of that layer.
  std::vector<std::vector<uint32_t>> merged(rays.keys.size());
  for (size_t i = 0; i < rays.keys.size(); ++i) {
    const uint32_t leaky = rays.leaky[i];
    if (leaky == 0) continue;
    const uint32_t x = rays.x0 + uint32_t(i % rays.w), y = rays.y0 + uint32_t(i / rays.w);
    uint32_t borrow = 31u - uint32_t(__builtin_clz(leaky));  // the highest-priority leaky layer
    int64_t donor = -1;
    const bool found = findDonor(rays, x, y, borrow, options.hole_radius, &donor);
    for (uint32_t key : rays.keys[i])
      if (((leaky >> voxKeyLayer(key)) & 1u) == 0) merged[i].push_back(key);
    if (found && donor >= 0)
      for (uint32_t key : rays.keys[size_t(donor)])
        if (voxKeyLayer(key) == borrow) merged[i].push_back(key);
    std::sort(merged[i].begin(), merged[i].end());
  }
  auto keysOf = [&](size_t i) -> const std::vector<uint32_t>& {
    return rays.leaky[i] != 0 ? merged[i] : rays.keys[i];
  };

  const uint32_t bdim = dim / DS_BRICK_DIM;
  std::vector<uint32_t> cov(size_t(dim) * 4);
  std::vector<Voxel> column_voxels(size_t(DS_BRICK_DIM) * DS_BRICK_DIM * dim);
  std::vector<Voxel> brick(DS_BRICK_VOXELS);
  for (uint32_t by = 0; by < bdim; ++by) {
    if (!interrupter.progress(double(by) / bdim)) return makeError("voxelize", "cancelled");
    for (uint32_t bx = 0; bx < bdim; ++bx) {
      // Skip brick columns whose rays all miss the footprint: they stay empty.
      const uint32_t rx0 = bx * DS_BRICK_DIM * S, ry0 = by * DS_BRICK_DIM * S, span = DS_BRICK_DIM * S;
      if (rx0 + span <= rays.x0 || ry0 + span <= rays.y0 || rx0 >= rays.x0 + rays.w || ry0 >= rays.y0 + rays.h)
        continue;
      bool any = false;
      for (uint32_t ly = 0; ly < DS_BRICK_DIM; ++ly)
        for (uint32_t lx = 0; lx < DS_BRICK_DIM; ++lx) {
          std::fill(cov.begin(), cov.end(), 0u);
          const uint32_t vx = bx * DS_BRICK_DIM + lx, vy = by * DS_BRICK_DIM + ly;
          for (uint32_t sy = 0; sy < S; ++sy)
            for (uint32_t sx = 0; sx < S; ++sx) {
              const uint32_t gx = vx * S + sx, gy = vy * S + sy;
              if (!rays.inside(gx, gy)) continue;
              const std::vector<uint32_t>& keys = keysOf(rays.index(gx, gy));
              uint32_t winding = 0, pos = 0;
              // Each span between hits adds its length to the voxels it overlaps.
              auto paint = [&](uint32_t from, uint32_t to, uint32_t material) {
                if (material == 0 || to <= from) return;
                for (uint32_t z = from / unit; z < dim && z * unit < to; ++z) {
                  const uint32_t a = std::max(from, z * unit), b = std::min(to, (z + 1) * unit);
                  if (b > a) cov[size_t(z) * 4 + material - 1] += b - a;
                }
              };
              for (uint32_t key : keys) {
                paint(pos, voxKeyDepth(key), voxMaterialOf(winding, materials));
                pos = voxKeyDepth(key);
                winding = voxWindingStep(winding, key);
              }
              paint(pos, dim * unit, voxMaterialOf(winding, materials));
            }
          for (uint32_t z = 0; z < dim; ++z) {
            const uint32_t* c = &cov[size_t(z) * 4];
            const Voxel v = Voxel(voxVoxelFromCoverage(c[0], c[1], c[2], c[3], full, voxDither(vx, vy, z)));
            column_voxels[(size_t(z) * DS_BRICK_DIM + ly) * DS_BRICK_DIM + lx] = v;
            any = any || v != 0;
          }
        }
      if (!any) continue;
      for (uint32_t bz = 0; bz < bdim; ++bz) {
        std::copy_n(&column_voxels[size_t(bz) * DS_BRICK_VOXELS], DS_BRICK_VOXELS, brick.data());
        volume.setBrick({bx, by, bz}, brick.data());
      }
    }
  }
  volume.compact();
  interrupter.end();
  return volume;
}

Result<ToothVolume> voxelizeLayersCpu(const std::vector<MeshLayer>& layers, int level, const VoxelizeOptions& options) {
  Bounds3 bounds;
  for (const MeshLayer& l : layers) bounds.add(l.mesh->bounds());
  auto frame = fitGridToLevel(bounds, level);
  if (!frame) return frame.error();
  auto setup = makeRaySetup(layers, *frame, options);
  if (!setup) return setup.error();
  auto voxels = voxelizeCpu(*setup, options);
  if (!voxels) return voxels.error();
  voxels->compact();
  return ToothVolume{*frame, std::move(voxels).value()};
}

}  // namespace dentsim
