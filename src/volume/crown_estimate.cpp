// The crown estimate: fill-weighted centroids of the enamel and of every tissue, then the extent along their difference.
#include "volume/crown_estimate.h"

#include <algorithm>
#include <limits>

#include "volume/tissue_table.h"

namespace dentsim {

namespace {

// Fill-weighted sums of voxel centres [voxels x fill units].
struct Moments {
  double weight = 0.0;
  Vec3 sum;
  void add(const Vec3& centre, double fill) {
    weight += fill;
    sum += centre * fill;
  }
  Vec3 centroid() const { return weight > 0 ? sum / weight : Vec3{}; }
};

// The treated tooth's tissue: a neighbour beside it would pull the centroid and the extent its way.
bool isTissue(Voxel v) { return isToothTissue(voxelMaterial(v)) && voxelFill(v) > 0; }

}  // namespace

CrownEstimate estimateCrown(const BrickVolume& volume) {
  Moments tooth, enamel;
  volume.forEachBrick([&](const BrickView& b) {
    const Vec3 origin{double(b.coord.x * DS_BRICK_DIM), double(b.coord.y * DS_BRICK_DIM), double(b.coord.z * DS_BRICK_DIM)};
    if (b.uniform) {
      if (!isTissue(b.value)) return;
      // A uniform brick's voxel centres average to the brick's centre.
      const Vec3 centre = origin + Vec3{0.5, 0.5, 0.5} * double(DS_BRICK_DIM);
      const double fill = double(voxelFill(b.value)) * DS_BRICK_VOXELS;
      tooth.add(centre, fill);
      if (voxelMaterial(b.value) == Material::Enamel) enamel.add(centre, fill);
      return;
    }
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
      const Voxel v = b.voxels[n];
      if (!isTissue(v)) continue;
      const Vec3 centre = origin + Vec3{double(n & 7u) + 0.5, double((n >> 3) & 7u) + 0.5, double(n >> 6) + 0.5};
      tooth.add(centre, voxelFill(v));
      if (voxelMaterial(v) == Material::Enamel) enamel.add(centre, voxelFill(v));
    }
  });
  CrownEstimate out;
  const Vec3 towards_enamel = enamel.centroid() - tooth.centroid();
  if (enamel.weight > 0 && norm(towards_enamel) >= 1.0) {
    out.axis = normalized(towards_enamel);
    out.from_enamel = true;
  }
  // The extent over the corners of the bricks that hold tissue.
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  volume.forEachBrick([&](const BrickView& b) {
    bool any = b.uniform && isTissue(b.value);
    for (uint32_t n = 0; !b.uniform && !any && n < DS_BRICK_VOXELS; ++n) any = isTissue(b.voxels[n]);
    if (!any) return;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p{double((b.coord.x + (corner & 1)) * DS_BRICK_DIM), double((b.coord.y + ((corner >> 1) & 1)) * DS_BRICK_DIM),
                   double((b.coord.z + (corner >> 2)) * DS_BRICK_DIM)};
      lo = std::min(lo, dot(p, out.axis));
      hi = std::max(hi, dot(p, out.axis));
    }
  });
  if (lo <= hi) {
    out.lo = lo;
    out.hi = hi;
  }
  return out;
}

}  // namespace dentsim
