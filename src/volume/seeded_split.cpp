// The seeded split of a mask at narrow joins: the pulp filled, depth, a counting sort by depth, and a union-find flood.
#include "volume/seeded_split.h"

#include "volume/distance_transform.h"
#include "volume/voxel_grid_ops.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>
#include <limits>

namespace dentsim {
namespace {

// Union-find over flood regions, each with its peak depth step.
struct Regions {
  std::vector<uint32_t> parent{0};  // region 0 is "not yet flooded"
  std::vector<uint32_t> peak{0};
  uint32_t find(uint32_t r) {
    while (parent[r] != r) {
      parent[r] = parent[parent[r]];
      r = parent[r];
    }
    return r;
  }
};

// The piece with the holes it encloses filled (the header's rule), 0/1. The wall is dilated by
// `seal` voxels and the outside flooded from the grid's border through what the dilation leaves
// empty; what that flood misses is a cavity. Then the outside is dilated back (the closing's
// second half), and the holes of the closing are filled where they join a cavity: a pulp chamber
// and its canals, not the thin wedge beside a contact. With seal 0 every cavity is a hole as it is.
std::vector<uint8_t> filledPiece(const std::vector<uint8_t>& piece, const std::array<int32_t, 3>& d, int seal) {
  constexpr uint8_t kWall = 1, kScratch = 2, kOutside = 4, kCavity = 8;
  std::vector<uint8_t> cells(piece.size());
  for (size_t i = 0; i < piece.size(); ++i) cells[i] = piece[i] ? kWall : 0;
  if (seal > 0) dilateBit(cells, d, seal, kWall, kScratch);
  std::deque<uint64_t> queue;
  floodFromBorder(
      d, queue,
      [&](uint64_t l) {
        if (cells[l] != 0) return false;
        cells[l] = kOutside;
        return true;
      },
      [](double) { return true; });
  std::vector<uint8_t> filled(piece);
  if (seal == 0) {
    for (size_t i = 0; i < cells.size(); ++i)
      if (cells[i] == 0) filled[i] = 1;
    return filled;
  }
  for (uint8_t& c : cells)
    if (c == 0) c = kCavity;
  dilateBit(cells, d, seal, kOutside, kScratch);
  const auto hole = [&](uint64_t l) { return !piece[l] && !(cells[l] & kOutside) && !filled[l]; };
  for (uint64_t l = 0; l < cells.size(); ++l) {
    if (!(cells[l] & kCavity) || !hole(l)) continue;
    filled[l] = 1;
    queue.push_back(l);
    while (!queue.empty()) {
      const uint64_t m = queue.front();
      queue.pop_front();
      forEachFaceNeighbour(m, d, [&](uint64_t n) {
        if (!hole(n)) return;
        filled[n] = 1;
        queue.push_back(n);
      });
    }
  }
  return filled;
}

}  // namespace

bool keepSeededPart(std::vector<uint8_t>& piece, const std::array<int32_t, 3>& d, const std::array<double, 3>& pitch,
                    uint64_t seed, double h_mm, double seal_mm, Interrupter& interrupter) {
  assert(piece.size() <= std::numeric_limits<uint32_t>::max() && seed < piece.size() && piece[seed]);
  assert(h_mm >= 0 && seal_mm >= 0);
  const double smallest = std::min({pitch[0], pitch[1], pitch[2]});  // [mm]
  // The cube's half-side: dilateBit counts voxels; 254 bounds it as the label import's seal does.
  const int seal = int(std::min(254L, std::lround(seal_mm / smallest)));
  // The depth and the flood run over the filled piece (the header's rule); `piece` keeps its own
  // voxels, so the fill never reaches the result.
  const std::vector<uint8_t> solid = filledPiece(piece, d, seal);
  if (!interrupter.progress(0.1)) return false;
  // Depth in 16-bit steps: 1/16 of a voxel resolves a neck's radius well below h, and 65535 steps
  // reach 4096 voxels deep, beyond any tooth.
  const double step = smallest / 16.0;  // [mm]
  std::vector<uint16_t> depth(piece.size(), 0);
  {
    const std::vector<float> d2 = squaredDistanceToOutside(solid, d, pitch);
    for (size_t i = 0; i < piece.size(); ++i)
      if (solid[i]) depth[i] = uint16_t(std::min(65535.0, std::floor(std::sqrt(double(d2[i])) / step)));
  }
  if (!interrupter.progress(0.3)) return false;

  // Counting sort of the piece's voxels by depth, deepest first (scan order within a step).
  std::vector<uint64_t> start(65537, 0);
  for (size_t i = 0; i < piece.size(); ++i)
    if (solid[i]) ++start[65535 - size_t(depth[i]) + 1];
  for (size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  std::vector<uint32_t> order(start.back());
  {
    std::vector<uint64_t> next(start.begin(), start.end() - 1);
    for (size_t i = 0; i < piece.size(); ++i)
      if (solid[i]) order[next[65535 - size_t(depth[i])]++] = uint32_t(i);
  }

  const uint32_t h_steps = uint32_t(std::max(0.0, std::ceil(h_mm / step - 1e-9)));
  Regions regions;
  std::vector<uint32_t> region(piece.size(), 0);
  for (size_t n = 0; n < order.size(); ++n) {
    const uint32_t i = order[n];
    const uint32_t level = depth[i];
    uint32_t roots[6];
    int count = 0;
    forEachFaceNeighbour(i, d, [&](uint64_t j) {
      if (region[j] == 0) return;
      const uint32_t r = regions.find(region[j]);
      for (int t = 0; t < count; ++t)
        if (roots[t] == r) return;
      roots[count++] = r;
    });
    if (count == 0) {
      const uint32_t id = uint32_t(regions.parent.size());
      regions.parent.push_back(id);
      regions.peak.push_back(level);
      region[i] = id;
      continue;
    }
    uint32_t top = roots[0];
    for (int t = 1; t < count; ++t)
      if (regions.peak[roots[t]] > regions.peak[top]) top = roots[t];
    for (int t = 0; t < count; ++t)
      if (roots[t] != top && regions.peak[roots[t]] - level < h_steps) regions.parent[roots[t]] = top;
    region[i] = top;
    if ((n & 0xFFFFF) == 0xFFFFF && !interrupter.progress(0.3 + 0.7 * double(n) / double(order.size()))) return false;
  }
  const uint32_t part = regions.find(region[seed]);
  for (size_t i = 0; i < piece.size(); ++i)
    if (piece[i] && regions.find(region[i]) != part) piece[i] = 0;
  return interrupter.progress(1.0);
}

}  // namespace dentsim
