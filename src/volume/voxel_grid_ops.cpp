// Grid operations shared by label import and scan segmentation: the piece flood and the box dilation.
#include "volume/voxel_grid_ops.h"

#include <algorithm>
#include <limits>

namespace dentsim {

VoxelPiece floodPiece(const VoxelBits& mask, VoxelBits& seen, const std::array<int32_t, 3>& d, uint64_t start,
                      std::deque<uint64_t>& queue) {
  assert(mask.test(start) && !seen.test(start));
  VoxelPiece piece;
  piece.box.lo = {d[0], d[1], d[2]};
  piece.box.hi = {-1, -1, -1};
  seen.set(start);
  queue.push_back(start);
  while (!queue.empty()) {
    const uint64_t l = queue.front();
    queue.pop_front();
    ++piece.voxels;
    const std::array<int64_t, 3> c = voxelCoords(l, d);
    for (size_t a = 0; a < 3; ++a) {
      piece.box.lo[a] = std::min(piece.box.lo[a], c[a]);
      piece.box.hi[a] = std::max(piece.box.hi[a], c[a]);
    }
    forEachFaceNeighbour(l, d, [&](uint64_t j) {
      if (mask.test(j) && !seen.test(j)) {
        seen.set(j);
        queue.push_back(j);
      }
    });
  }
  return piece;
}

// One axis: `to` is set where `from` lies within r along the axis. The forward sweep counts the
// cells since the last `from` on each line and the backward sweep the cells until the next; both
// walk memory in order (lines along j and k keep one counter per (i) or (i, j)).
void dilateBit(std::vector<uint8_t>& cells, const std::array<int32_t, 3>& d, int r, uint8_t bit, uint8_t scratch) {
  assert(r >= 0 && bit != 0 && scratch != 0 && (bit & scratch) == 0);
  assert(cells.size() == size_t(d[0]) * size_t(d[1]) * size_t(d[2]));
  const size_t nx = size_t(d[0]), ny = size_t(d[1]), nz = size_t(d[2]);
  constexpr int64_t kFar = std::numeric_limits<int32_t>::max();  // no `from` on the line yet
  auto axisPass = [&](int axis, uint8_t from, uint8_t to) {
    for (uint8_t& c : cells) c = uint8_t(c & ~to);
    std::vector<int64_t> run(axis == 0 ? 1 : axis == 1 ? nx : nx * ny);
    auto step = [&](size_t i, size_t line, bool line_start) {
      int64_t& c = run[line];
      if (line_start) c = kFar;
      c = (cells[i] & from) ? 0 : std::min(kFar, c + 1);
      if (c <= r) cells[i] |= to;
    };
    for (size_t z = 0, i = 0; z < nz; ++z)
      for (size_t y = 0; y < ny; ++y)
        for (size_t x = 0; x < nx; ++x, ++i) {
          if (axis == 0) step(i, 0, x == 0);
          else if (axis == 1) step(i, x, y == 0);
          else step(i, x + nx * y, z == 0);
        }
    for (size_t z = nz, i = cells.size(); z-- > 0;)
      for (size_t y = ny; y-- > 0;)
        for (size_t x = nx; x-- > 0;) {
          --i;
          if (axis == 0) step(i, 0, x == nx - 1);
          else if (axis == 1) step(i, x, y == ny - 1);
          else step(i, x + nx * y, z == nz - 1);
        }
  };
  // bit -> scratch -> bit -> scratch, then the result back into bit.
  axisPass(0, bit, scratch);
  axisPass(1, scratch, bit);
  axisPass(2, bit, scratch);
  for (uint8_t& c : cells) c = uint8_t((c & ~(bit | scratch)) | ((c & scratch) ? bit : 0));
}

}  // namespace dentsim
