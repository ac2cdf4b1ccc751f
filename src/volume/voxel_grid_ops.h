// Grid operations that label import and scan segmentation share: one bit a voxel, face neighbours, floods and box dilation on an i-fastest voxel grid.
//
// A grid is `dims` voxels (each >= 1) stored i fastest: index i + nx * (j + ny * k). Every flood
// here is 6-connected (face neighbours), as every piece dentsim counts is.
//
// Entry points:
//   VoxelBits                     one bit a voxel
//   voxelCoords / voxelIndex      index <-> (i, j, k)
//   forEachFaceNeighbour          the up to six face neighbours, in a fixed order
//   floodFromBorder               everything reachable from the grid's border through accepted voxels
//   floodPiece                    one connected piece of a VoxelBits mask, its size and bounding box
//   dilateBit                     a box dilation of one bit plane of a byte grid, linear in the grid
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace dentsim {

// One bit a voxel: 18 MB for a 600 x 600 x 400 scan, where a byte would be 144 MB.
class VoxelBits {
 public:
  explicit VoxelBits(size_t n = 0) : words_((n + 63) / 64, 0) {}
  bool test(uint64_t i) const { return (words_[i >> 6] >> (i & 63)) & 1u; }
  void set(uint64_t i) { words_[i >> 6] |= uint64_t{1} << (i & 63); }

 private:
  std::vector<uint64_t> words_;
};

// (i, j, k) of index `l` in a grid of dims `d`.
inline std::array<int64_t, 3> voxelCoords(uint64_t l, const std::array<int32_t, 3>& d) {
  const uint64_t row = l / uint64_t(d[0]);
  return {int64_t(l - row * uint64_t(d[0])), int64_t(row % uint64_t(d[1])), int64_t(row / uint64_t(d[1]))};
}

// The index of (i, j, k), which must lie in the grid.
inline uint64_t voxelIndex(const std::array<int64_t, 3>& c, const std::array<int32_t, 3>& d) {
  return uint64_t(c[0] + d[0] * (c[1] + int64_t{d[1]} * c[2]));
}

// Calls f(j) for each face neighbour j of voxel l inside the grid, in the order -i, +i, -j, +j,
// -k, +k. The order is part of the contract: seeded_split breaks ties between regions by it.
template <class F>
void forEachFaceNeighbour(uint64_t l, const std::array<int32_t, 3>& d, F&& f) {
  const std::array<int64_t, 3> c = voxelCoords(l, d);
  const uint64_t sy = uint64_t(d[0]), sz = uint64_t(d[0]) * uint64_t(d[1]);
  if (c[0] > 0) f(l - 1);
  if (c[0] + 1 < d[0]) f(l + 1);
  if (c[1] > 0) f(l - sy);
  if (c[1] + 1 < d[1]) f(l + sy);
  if (c[2] > 0) f(l - sz);
  if (c[2] + 1 < d[2]) f(l + sz);
}

// Breadth first from every border voxel: calls enter(l) on each border voxel, then on each face
// neighbour of a voxel it took. enter returns true when it takes the voxel, and must mark it so that
// it refuses it the next time (each voxel is then taken once). The queue stays near the size of the
// advancing front. Every 2^20 voxels taken, progress(taken / voxels) is asked; false stops the flood
// and is returned.
template <class Enter, class Progress>
bool floodFromBorder(const std::array<int32_t, 3>& d, std::deque<uint64_t>& queue, Enter&& enter,
                     Progress&& progress) {
  const int64_t nx = d[0], ny = d[1], nz = d[2];
  auto visit = [&](uint64_t l) {
    if (enter(l)) queue.push_back(l);
  };
  for (int64_t z = 0; z < nz; ++z)
    for (int64_t y = 0; y < ny; ++y) {
      const uint64_t row = uint64_t(nx * (y + ny * z));
      if (z == 0 || z == nz - 1 || y == 0 || y == ny - 1) {
        for (int64_t x = 0; x < nx; ++x) visit(row + uint64_t(x));
      } else {
        visit(row);
        if (nx > 1) visit(row + uint64_t(nx - 1));
      }
    }
  const double total = double(nx) * double(ny) * double(nz);
  uint64_t taken = 0;
  while (!queue.empty()) {
    const uint64_t l = queue.front();
    queue.pop_front();
    forEachFaceNeighbour(l, d, visit);
    if ((++taken & 0xFFFFF) == 0 && !progress(double(taken) / total)) {
      queue.clear();
      return false;
    }
  }
  return true;
}

// An inclusive box of voxel indices (empty while hi < lo on an axis).
struct IndexBox {
  std::array<int64_t, 3> lo{0, 0, 0}, hi{-1, -1, -1};
  int64_t size(int a) const { return hi[size_t(a)] - lo[size_t(a)] + 1; }
  std::array<int32_t, 3> dims() const { return {int32_t(size(0)), int32_t(size(1)), int32_t(size(2))}; }
  uint64_t count() const { return uint64_t(size(0)) * uint64_t(size(1)) * uint64_t(size(2)); }
};

// One 6-connected piece of a mask: its voxel count and bounding box.
struct VoxelPiece {
  uint64_t voxels = 0;
  IndexBox box;
};

// Floods the piece of `mask` holding `start` (which must be set in mask and not in seen), breadth
// first, setting its voxels in `seen`; voxels already in `seen` are walls. `queue` is scratch.
VoxelPiece floodPiece(const VoxelBits& mask, VoxelBits& seen, const std::array<int32_t, 3>& d, uint64_t start,
                      std::deque<uint64_t>& queue);

// Dilates bit `bit` of every cell by a box of side 2r+1 (a cell gets it when a cell within r along
// each axis, Chebyshev distance, had it; the grid's edge clips the box), in place. `scratch` is
// another bit, used as the ping-pong plane and left clear; other bits are untouched. Each axis is
// two streaming sweeps with one counter per line, so the cost does not grow with r. r >= 0.
void dilateBit(std::vector<uint8_t>& cells, const std::array<int32_t, 3>& d, int r, uint8_t bit, uint8_t scratch);

}  // namespace dentsim
