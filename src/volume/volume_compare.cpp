// Per-tissue overlap of two brick volumes: one pass over the bricks, whole tiles counted at once.
#include "volume/volume_compare.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cstring>
#include <string>

namespace dentsim {
namespace {

// Integer sums, so that the counts are exact whatever the order of the bricks.
struct Tally {
  uint64_t a = 0, b = 0, both = 0, either = 0;  // voxels in the tissue
  uint64_t min_fill = 0, max_fill = 0;          // fill sums [1/31 voxel]
};

// The tissue's fill of every voxel code: the fill when the code holds the tissue, else 0.
using FillTable = std::array<uint8_t, 256>;
FillTable tissueFills(Material tissue) {
  FillTable t{};
  for (uint32_t v = 0; v < 256; ++v)
    t[v] = voxelMaterial(Voxel(v)) == tissue ? uint8_t(voxelFill(Voxel(v))) : uint8_t(0);
  return t;
}

constexpr bool inside(uint32_t fill) { return 2 * fill > DS_FILL_FULL; }

// Adds `count` voxels whose tissue fills are fa in a and fb in b.
void tallyVoxels(Tally& t, uint32_t fa, uint32_t fb, uint64_t count) {
  const bool ia = inside(fa), ib = inside(fb);
  t.a += ia ? count : 0;
  t.b += ib ? count : 0;
  t.both += ia && ib ? count : 0;
  t.either += ia || ib ? count : 0;
  t.min_fill += std::min(fa, fb) * count;
  t.max_fill += std::max(fa, fb) * count;
}

// A brick's 512 voxels whether it is a tile or dense; `scratch` holds the tile's expansion.
const Voxel* brickVoxels(const BrickView& view, Voxel* scratch) {
  if (!view.uniform) return view.voxels;
  std::memset(scratch, view.value, DS_BRICK_VOXELS);
  return scratch;
}

}  // namespace

Result<TissueOverlap> compareTissues(const BrickVolume& a, const BrickVolume& b, Material tissue) {
  assert(tissue != Material::Empty);
  if (a.level() != b.level())
    return makeError("compare", "the volumes are on different grids (level " + std::to_string(a.level()) +
                                    " and level " + std::to_string(b.level()) + ")");
  const FillTable fills = tissueFills(tissue);
  Tally t;
  alignas(16) Voxel scratch_a[DS_BRICK_VOXELS];
  alignas(16) Voxel scratch_b[DS_BRICK_VOXELS];
  const uint32_t bd = a.brickDim();
  for (uint32_t z = 0; z < bd; ++z)
    for (uint32_t y = 0; y < bd; ++y)
      for (uint32_t x = 0; x < bd; ++x) {
        const BrickView va = a.brick({x, y, z});
        const BrickView vb = b.brick({x, y, z});
        // Two tiles are one voxel pair 512 times; that covers the empty space of both volumes.
        if (va.uniform && vb.uniform) {
          const uint32_t fa = fills[va.value], fb = fills[vb.value];
          if (fa != 0 || fb != 0) tallyVoxels(t, fa, fb, DS_BRICK_VOXELS);
          continue;
        }
        const Voxel* pa = brickVoxels(va, scratch_a);
        const Voxel* pb = brickVoxels(vb, scratch_b);
        for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
          const uint32_t fa = fills[pa[i]], fb = fills[pb[i]];
          if (fa != 0 || fb != 0) tallyVoxels(t, fa, fb, 1);
        }
      }

  TissueOverlap o;
  o.a_voxels = t.a;
  o.b_voxels = t.b;
  o.intersection = t.both;
  o.union_voxels = t.either;
  o.iou = t.either == 0 ? 1.0 : double(t.both) / double(t.either);
  o.min_fill_sum = t.min_fill;
  o.max_fill_sum = t.max_fill;
  o.soft_iou = t.max_fill == 0 ? 1.0 : double(t.min_fill) / double(t.max_fill);
  return o;
}

}  // namespace dentsim
