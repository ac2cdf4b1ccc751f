// Label images into brick volumes and back: label-map parsing, small-piece clean-up, enclosed-space filling, direct and resampled placement, export.
//
// Contents
//   1. Label maps
//   2. Source voxel codes (label -> voxel through the map)
//   3. Relabelling small pieces (one flood per piece, one bit per voxel)
//   4. Filling enclosed empty space (breadth-first from the border)
//   5. Placement without resampling
//   6. Placement with resampling
//   7. importLabels (and cleanSmallPieces, section 3's clean-up for other callers)
//   8. exportLabels
#include "volume/label_import.h"

#include "volume/tissue_table.h"
#include "volume/tooth_frame.h"
#include "volume/voxel_grid_ops.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>
#include <deque>
#include <limits>
#include <sstream>
#include <vector>

namespace dentsim {
namespace {

constexpr uint8_t kOutsideMark = 0xFF;  // not a valid voxel code: marks empty space reached from the border
constexpr uint8_t kPieceMark = 0xFF;    // not a valid voxel code: marks the small piece being voted on

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  const size_t e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

std::string withThousands(uint64_t v) {
  std::string s = std::to_string(v);
  for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(size_t(i), ",");
  return s;
}

// Progress over consecutive stages: stage k of the job covers [begin, end) of the bar.
struct Stage {
  Interrupter& interrupter;
  double begin = 0.0, end = 1.0;
  bool report(double fraction) const { return interrupter.progress(begin + (end - begin) * fraction); }
  Stage sub(double from, double to) const {
    return Stage{interrupter, begin + (end - begin) * from, begin + (end - begin) * to};
  }
};

Error cancelled(const std::string& where) { return makeError(where, "import cancelled"); }

// Inner tissue wins ties: pulp > caries > dentin > enamel.
int tieRank(uint32_t material) {
  switch (material) {
    case DS_MAT_PULP: return 4;
    case DS_MAT_CARIES: return 3;
    case DS_MAT_DENTIN: return 2;
    case DS_MAT_ENAMEL: return 1;
    default: return 0;
  }
}

// ---- 2. source voxel codes ------------------------------------------------------------------

// One voxel code per source voxel, after checking that every label present is mapped.
Result<std::vector<uint8_t>> sourceCodes(const LabelImage& image, const LabelImportOptions& options,
                                         const Stage& stage) {
  const size_t n = image.labels.size();
  constexpr size_t kLabelValues = 65536;
  auto slot = [](Label l) { return size_t(uint16_t(l)); };
  std::vector<uint64_t> histogram(kLabelValues, 0);
  for (Label l : image.labels) ++histogram[slot(l)];

  std::vector<uint8_t> lut(kLabelValues, 0);
  for (size_t s = 0; s < kLabelValues; ++s) {
    if (histogram[s] == 0) continue;
    const int32_t label = int16_t(uint16_t(s));
    if (label == 0) continue;
    const auto it = options.map.find(label);
    if (it == options.map.end())
      return makeError(options.where, "label " + std::to_string(label) + " (" + withThousands(histogram[s]) +
                                          " voxels) is not in the label map");
    lut[s] = makeVoxel(it->second, DS_FILL_FULL);
  }
  if (!stage.report(0.5)) return cancelled(options.where);
  std::vector<uint8_t> codes(n);
  for (size_t i = 0; i < n; ++i) codes[i] = lut[slot(image.labels[i])];
  if (!stage.report(1.0)) return cancelled(options.where);
  return codes;
}

// ---- 3. small pieces ------------------------------------------------------------------------

// The tissue most faces of the piece (its voxels hold kPieceMark) touch outside it, ties to the
// inner tissue; nullopt when no face has a voxel outside the piece.
std::optional<uint32_t> majorityAround(const std::vector<uint8_t>& codes, const std::vector<uint64_t>& piece,
                                       const std::array<int32_t, 3>& dims) {
  std::array<uint64_t, DS_MATERIAL_COUNT> faces{};
  uint64_t votes = 0;
  for (uint64_t i : piece)
    forEachFaceNeighbour(i, dims, [&](uint64_t j) {
      if (codes[j] == kPieceMark) return;
      ++faces[layout::voxelMaterial(codes[j])];
      ++votes;
    });
  if (votes == 0) return std::nullopt;
  uint32_t best = 0;
  for (uint32_t m = 1; m < DS_MATERIAL_COUNT; ++m)
    if (faces[m] > faces[best] || (faces[m] == faces[best] && tieRank(m) > tieRank(best))) best = m;
  return best;
}

// Relabels every 6-connected piece of one code with fewer than min_voxels voxels (see importLabels).
// Each piece is flooded once from its first voxel in scan order, a run along i at a time: a run is
// extended both ways, marked, and the rows beside it (j +- 1, k +- 1) push one seed per stretch of
// the same code. So the work is a few visits per voxel however large the pieces, and the stack holds
// runs rather than voxels. Only the first min_voxels voxels of a piece are listed: a piece that
// reaches the limit is kept, and the rest of its flood only marks voxels as seen. Codes must be empty
// or full (as sourceCodes makes them), which is what lets the vote read a neighbour's tissue and write
// makeVoxel(tissue, full) back.
Status relabelSmallPieces(std::vector<uint8_t>& codes, const std::array<int32_t, 3>& dims, int64_t min_voxels,
                          PieceCleanup& report, const Stage& stage, const std::string& where) {
  assert(min_voxels > 0);
  const int64_t nx = dims[0], ny = dims[1], nz = dims[2];
  const uint64_t n = codes.size();
  const size_t limit = size_t(min_voxels);
  VoxelBits seen(n);
  struct Seed {
    int32_t x, y, z;
  };
  std::vector<Seed> stack;
  std::vector<uint64_t> piece;
  piece.reserve(std::min<size_t>(limit, size_t{1} << 16));
  uint64_t flooded = 0, reported = 0;
  for (uint64_t seed = 0; seed < n; ++seed) {
    if (seen.test(seed)) continue;
    const uint8_t code = codes[seed];
    assert(code == 0 || voxelFill(code) == DS_FILL_FULL);
    // Unseen voxels all still hold their input code, and two input pieces of one code never touch,
    // so this flood covers exactly the input piece, even beside pieces relabelled into its code.
    auto joins = [&](uint64_t i) { return !seen.test(i) && codes[i] == code; };
    piece.clear();
    const uint64_t row0 = seed / uint64_t(nx);
    stack.push_back({int32_t(seed - row0 * uint64_t(nx)), int32_t(row0 % uint64_t(ny)), int32_t(row0 / uint64_t(ny))});
    while (!stack.empty()) {
      const Seed s = stack.back();
      stack.pop_back();
      const uint64_t row = uint64_t(s.y) * uint64_t(nx) + uint64_t(s.z) * uint64_t(nx * ny);
      if (!joins(row + uint64_t(s.x))) continue;  // reached through another run since it was pushed
      int64_t x0 = s.x, x1 = s.x;
      while (x0 > 0 && joins(row + uint64_t(x0 - 1))) --x0;
      while (x1 + 1 < nx && joins(row + uint64_t(x1 + 1))) ++x1;
      for (int64_t x = x0; x <= x1; ++x) {
        seen.set(row + uint64_t(x));
        if (piece.size() < limit) piece.push_back(row + uint64_t(x));
      }
      flooded += uint64_t(x1 - x0 + 1);
      auto pushStretches = [&](int64_t y, int64_t z) {
        if (y < 0 || y >= ny || z < 0 || z >= nz) return;
        const uint64_t beside = uint64_t(y) * uint64_t(nx) + uint64_t(z) * uint64_t(nx * ny);
        bool inside = false;
        for (int64_t x = x0; x <= x1; ++x) {
          const bool j = joins(beside + uint64_t(x));
          if (j && !inside) stack.push_back({int32_t(x), int32_t(y), int32_t(z)});
          inside = j;
        }
      };
      pushStretches(s.y - 1, s.z);
      pushStretches(s.y + 1, s.z);
      pushStretches(s.y, s.z - 1);
      pushStretches(s.y, s.z + 1);
      if (flooded - reported > (uint64_t{1} << 22)) {
        reported = flooded;
        if (!stage.report(double(flooded) / double(n))) return cancelled(where);
      }
    }
    if (piece.size() >= limit) continue;

    for (uint64_t i : piece) codes[i] = kPieceMark;
    const std::optional<uint32_t> tissue = majorityAround(codes, piece, dims);
    // Voxels relabelled earlier into this piece's tissue vote for it, and then nothing changes.
    const uint32_t from = layout::voxelMaterial(code);
    const uint32_t to = tissue.value_or(from);
    const uint8_t result = to == from ? code : makeVoxel(static_cast<Material>(to), DS_FILL_FULL);
    for (uint64_t i : piece) codes[i] = result;
    if (to == from) continue;
    ++report.pieces[from];
    report.voxels[from] += piece.size();
    report.voxels_into[to] += piece.size();
  }
  if (!stage.report(1.0)) return cancelled(where);
  return Ok{};
}

// ---- 4. enclosed space ----------------------------------------------------------------------

// Marks with kOutsideMark every zero cell 6-connected to the border through zero cells.
Status markOutside(std::vector<uint8_t>& cells, const std::array<int32_t, 3>& dims, const Stage& stage,
                   const std::string& where) {
  std::deque<uint64_t> queue;
  const bool done = floodFromBorder(
      dims, queue,
      [&](uint64_t i) {
        if (cells[i] != 0) return false;
        cells[i] = kOutsideMark;
        return true;
      },
      [&](double fraction) { return stage.report(fraction); });
  return done ? Status(Ok{}) : Status(cancelled(where));
}

// Empty voxels that the tooth encloses become `fill`. With seal_voxels > 0 the walls are first
// closed (dilated by the radius, flooded from the border, and the flood dilated back), so that
// openings narrower than about twice the radius, such as apical foramina, do not let the flood into
// the pulp. Only voxels of `wall` (every tissue when unset) are closed, so grooves in other tissues
// stay open.
Status fillEnclosed(std::vector<uint8_t>& codes, const std::array<int32_t, 3>& dims, uint8_t fill,
                    std::optional<Material> wall, int seal_voxels, const Stage& stage, const std::string& where) {
  if (seal_voxels <= 0) {
    if (Status s = markOutside(codes, dims, stage, where); !s) return s;
    for (uint8_t& c : codes) c = c == kOutsideMark ? 0 : (c == 0 ? fill : c);
    return Ok{};
  }
  std::vector<uint8_t> cells(codes.size());
  for (size_t i = 0; i < codes.size(); ++i)
    cells[i] = wall ? voxelMaterial(codes[i]) == *wall : codes[i] != 0;
  dilateBit(cells, dims, seal_voxels, 1, 2);  // a 0/1 mask: bit 1, scratch bit 2
  if (!stage.report(0.3)) return cancelled(where);
  if (Status s = markOutside(cells, dims, stage.sub(0.3, 0.7), where); !s) return s;
  for (uint8_t& c : cells) c = c == kOutsideMark ? 1 : 0;
  dilateBit(cells, dims, seal_voxels, 1, 2);  // a 0/1 mask: bit 1, scratch bit 2
  for (size_t i = 0; i < codes.size(); ++i)
    if (codes[i] == 0 && cells[i] == 0) codes[i] = fill;
  if (!stage.report(1.0)) return cancelled(where);
  return Ok{};
}

// ---- 5. placement without resampling --------------------------------------------------------

Status placeDirect(const std::vector<uint8_t>& codes, const std::array<int32_t, 3>& dims, BrickVolume& volume,
                   const Stage& stage, const std::string& where) {
  const int64_t nx = dims[0], ny = dims[1], nz = dims[2];
  const uint32_t bricks[3] = {uint32_t((nx + 7) / 8), uint32_t((ny + 7) / 8), uint32_t((nz + 7) / 8)};
  std::array<Voxel, DS_BRICK_VOXELS> buf{};
  for (uint32_t bz = 0; bz < bricks[2]; ++bz) {
    for (uint32_t by = 0; by < bricks[1]; ++by)
      for (uint32_t bx = 0; bx < bricks[0]; ++bx) {
        const int64_t x0 = int64_t(bx) * 8, y0 = int64_t(by) * 8, z0 = int64_t(bz) * 8;
        const int64_t wx = std::min<int64_t>(8, nx - x0);
        bool any = false;
        buf.fill(0);
        for (int64_t z = 0; z < 8 && z0 + z < nz; ++z)
          for (int64_t y = 0; y < 8 && y0 + y < ny; ++y) {
            const uint8_t* row = &codes[size_t(x0 + nx * (y0 + y) + nx * ny * (z0 + z))];
            Voxel* dst = &buf[layout::brickCoordToOffset(0, uint32_t(y), uint32_t(z))];
            for (int64_t x = 0; x < wx; ++x) {
              dst[x] = row[x];
              any |= row[x] != 0;
            }
          }
        if (any) volume.setBrick(BrickCoord{bx, by, bz}, buf.data());  // the grid starts empty
      }
    if (!stage.report(double(bz + 1) / double(bricks[2]))) return cancelled(where);
  }
  return Ok{};
}

// ---- 6. placement with resampling -----------------------------------------------------------

// Where the target grid lies in source index space (voxel k covers [k-0.5, k+0.5)).
struct Resampling {
  int level = 0;
  double voxel_mm = 0;               // target voxel edge [mm]
  std::array<double, 3> ratio{};     // target voxel edge in source voxels, per axis
  std::array<double, 3> low{};       // source index coordinate of the target grid's low corner
  std::array<int, 3> samples{};      // point samples per target voxel along each axis
};

// For each target index along one axis, its samples' source indices (-1 outside the source).
std::vector<int32_t> sampleTable(const Resampling& rs, size_t axis, int32_t source_dim) {
  const int64_t dim = int64_t{1} << rs.level;
  const int n = rs.samples[axis];
  std::vector<int32_t> table(size_t(dim * n));
  for (int64_t i = 0; i < dim; ++i)
    for (int s = 0; s < n; ++s) {
      const double u = rs.low[axis] + (double(i) + (s + 0.5) / n) * rs.ratio[axis];
      const double k = std::floor(u + 0.5);
      table[size_t(i * n + s)] = (k >= 0 && k < source_dim) ? int32_t(k) : -1;
    }
  return table;
}

// The source indices that the samples of target voxels [i0, i1] along one axis read: their
// lowest and highest, and whether any falls outside the source.
struct SampleSpan {
  int32_t lo = std::numeric_limits<int32_t>::max(), hi = -1;
  bool outside = false;
};

SampleSpan sampleSpan(const std::vector<int32_t>& table, int n, int64_t i0, int64_t i1) {
  SampleSpan span;
  for (int64_t t = i0 * n; t < (i1 + 1) * n; ++t) {
    const int32_t k = table[size_t(t)];
    if (k < 0) {
      span.outside = true;
      continue;
    }
    span.lo = std::min(span.lo, k);
    span.hi = std::max(span.hi, k);
  }
  return span;
}

// What every sample of a box of target voxels reads, when it is all one thing: the one voxel all
// of them become (a full voxel of one tissue, or empty), or nothing when they differ. A box whose
// source indices hold one tissue and no sample outside the source resamples to that tissue, full;
// one whose source indices are all empty resamples to empty. Checking the source box costs its
// source voxels once, so the whole import stays linear in the source and in the output's bricks.
std::optional<Voxel> uniformBox(const std::vector<uint8_t>& codes, const std::array<int32_t, 3>& dims,
                                const std::array<SampleSpan, 3>& span) {
  bool any_sample = true, outside = false;
  for (const SampleSpan& a : span) {
    any_sample = any_sample && a.hi >= 0;
    outside = outside || a.outside;
  }
  if (!any_sample) return Voxel(0);  // every sample lies outside the source
  const int64_t sy = dims[0], sz = int64_t{dims[0]} * dims[1];
  const uint8_t first = codes[size_t(span[0].lo + sy * span[1].lo + sz * span[2].lo)];
  const uint32_t kind = first == 0 ? 0u : 1u + layout::voxelMaterial(first);
  for (int32_t k = span[2].lo; k <= span[2].hi; ++k)
    for (int32_t j = span[1].lo; j <= span[1].hi; ++j) {
      const uint8_t* row = &codes[size_t(sy * j + sz * k)];
      for (int32_t i = span[0].lo; i <= span[0].hi; ++i)
        if ((row[i] == 0 ? 0u : 1u + layout::voxelMaterial(row[i])) != kind) return std::nullopt;
    }
  if (kind == 0) return Voxel(0);
  if (outside) return std::nullopt;  // partly outside: a partial fill, sampled voxel by voxel
  return makeVoxel(static_cast<Material>(kind - 1), DS_FILL_FULL);
}

Status placeResampled(const std::vector<uint8_t>& codes, const std::array<int32_t, 3>& dims,
                      const Resampling& rs, BrickVolume& volume, const Stage& stage, const std::string& where,
                      bool uniform_shortcuts, uint64_t* sampled_voxels) {
  std::array<std::vector<int32_t>, 3> table;
  std::array<int64_t, 3> first{}, last{};  // target voxels with at least one sample inside the source
  const int64_t dim = int64_t{1} << rs.level;
  for (size_t a = 0; a < 3; ++a) {
    table[a] = sampleTable(rs, a, dims[a]);
    first[a] = dim;
    last[a] = -1;
    for (int64_t i = 0; i < dim; ++i)
      for (int s = 0; s < rs.samples[a]; ++s)
        if (table[a][size_t(i * rs.samples[a] + s)] >= 0) {
          first[a] = std::min(first[a], i);
          last[a] = std::max(last[a], i);
        }
    if (last[a] < 0) return Ok{};  // the source misses the grid: nothing to place
  }
  const int nxs = rs.samples[0], nys = rs.samples[1], nzs = rs.samples[2];
  const int total = nxs * nys * nzs;
  const int64_t sy = dims[0], sz = int64_t{dims[0]} * dims[1];
  // Target voxel (i,j,k) from its n^3 point samples: the most frequent solid tissue, filled by the
  // solid share.
  auto sampleVoxel = [&](int64_t i, int64_t j, int64_t k) -> Voxel {
    std::array<int, DS_MATERIAL_COUNT> count{};
    int solid = 0;
    for (int s = 0; s < nzs; ++s) {
      const int32_t zk = table[2][size_t(k * nzs + s)];
      if (zk < 0) continue;
      for (int t = 0; t < nys; ++t) {
        const int32_t yj = table[1][size_t(j * nys + t)];
        if (yj < 0) continue;
        const uint8_t* row = &codes[size_t(sy * yj + sz * zk)];
        for (int u = 0; u < nxs; ++u) {
          const int32_t xi = table[0][size_t(i * nxs + u)];
          if (xi < 0) continue;
          const uint8_t c = row[xi];
          if (c == 0) continue;
          ++solid;
          ++count[layout::voxelMaterial(c)];
        }
      }
    }
    if (solid == 0) return 0;
    uint32_t best = 0;
    for (uint32_t m = 1; m < DS_MATERIAL_COUNT; ++m)
      if (count[m] > count[best] || (count[m] == count[best] && count[m] > 0 && tieRank(m) > tieRank(best))) best = m;
    const uint32_t fill = std::max(1u, uint32_t(std::lround(double(DS_FILL_FULL) * solid / double(total))));
    return makeVoxel(static_cast<Material>(best), fill);
  };
  // The source span of each brick and each chunk along each axis, so that a box's check reads it
  // in three look-ups.
  constexpr int64_t kChunkVoxels = int64_t{DS_BRICK_DIM} * DS_CHUNK_DIM;
  std::array<std::vector<SampleSpan>, 3> brick_span, chunk_span;
  for (size_t a = 0; a < 3; ++a) {
    for (int64_t b = 0; b * DS_BRICK_DIM < dim; ++b)
      brick_span[a].push_back(sampleSpan(table[a], rs.samples[a], b * DS_BRICK_DIM, b * DS_BRICK_DIM + DS_BRICK_DIM - 1));
    for (int64_t c = 0; c * kChunkVoxels < dim; ++c)
      chunk_span[a].push_back(
          sampleSpan(table[a], rs.samples[a], c * kChunkVoxels, std::min(dim, (c + 1) * kChunkVoxels) - 1));
  }

  std::array<Voxel, DS_BRICK_VOXELS> buf{};
  auto placeBrick = [&](uint32_t bx, uint32_t by, uint32_t bz) {
    if (uniform_shortcuts) {
      if (auto v = uniformBox(codes, dims, {brick_span[0][bx], brick_span[1][by], brick_span[2][bz]})) {
        if (*v != 0) volume.setBrickUniform(BrickCoord{bx, by, bz}, *v);
        return;
      }
    }
    bool any = false;
    *sampled_voxels += DS_BRICK_VOXELS;
    for (uint32_t lz = 0; lz < 8; ++lz)
      for (uint32_t ly = 0; ly < 8; ++ly)
        for (uint32_t lx = 0; lx < 8; ++lx) {
          const Voxel v = sampleVoxel(int64_t(bx) * 8 + lx, int64_t(by) * 8 + ly, int64_t(bz) * 8 + lz);
          buf[layout::brickCoordToOffset(lx, ly, lz)] = v;
          any = any || v != 0;
        }
    if (any) volume.setBrick(BrickCoord{bx, by, bz}, buf.data());
  };
  const uint32_t b0[3] = {uint32_t(first[0] / 8), uint32_t(first[1] / 8), uint32_t(first[2] / 8)};
  const uint32_t b1[3] = {uint32_t(last[0] / 8), uint32_t(last[1] / 8), uint32_t(last[2] / 8)};
  // Chunk by chunk: a chunk whose samples all read one tissue (or nothing) is one tile, the
  // solid interior and the empty space around the tooth; only the others go brick by brick.
  const uint32_t c0[3] = {b0[0] / DS_CHUNK_DIM, b0[1] / DS_CHUNK_DIM, b0[2] / DS_CHUNK_DIM};
  const uint32_t c1[3] = {b1[0] / DS_CHUNK_DIM, b1[1] / DS_CHUNK_DIM, b1[2] / DS_CHUNK_DIM};
  const bool whole_chunks = dim >= kChunkVoxels;  // below that a chunk reaches past the grid
  for (uint32_t cz = c0[2]; cz <= c1[2]; ++cz) {
    for (uint32_t cy = c0[1]; cy <= c1[1]; ++cy)
      for (uint32_t cx = c0[0]; cx <= c1[0]; ++cx) {
        if (uniform_shortcuts && whole_chunks) {
          if (auto v = uniformBox(codes, dims, {chunk_span[0][cx], chunk_span[1][cy], chunk_span[2][cz]})) {
            if (*v != 0) volume.setChunkUniform(cx, cy, cz, *v);
            continue;
          }
        }
        for (uint32_t bz = std::max(b0[2], cz * DS_CHUNK_DIM); bz <= std::min(b1[2], cz * DS_CHUNK_DIM + DS_CHUNK_DIM - 1); ++bz)
          for (uint32_t by = std::max(b0[1], cy * DS_CHUNK_DIM); by <= std::min(b1[1], cy * DS_CHUNK_DIM + DS_CHUNK_DIM - 1); ++by)
            for (uint32_t bx = std::max(b0[0], cx * DS_CHUNK_DIM); bx <= std::min(b1[0], cx * DS_CHUNK_DIM + DS_CHUNK_DIM - 1); ++bx)
              placeBrick(bx, by, bz);
      }
    if (!stage.report(double(cz - c0[2] + 1) / double(c1[2] - c0[2] + 1))) return cancelled(where);
  }
  return Ok{};
}

// Area [mm^2] of the faces between source voxels of different tissues, and of tissue faces on the
// image's border: the surface that resampling turns into dense bricks.
double tissueSurfaceMm2(const std::vector<uint8_t>& codes, const std::array<int32_t, 3>& dims,
                        const std::array<double, 3>& pitch) {
  const int64_t nx = dims[0], ny = dims[1], nz = dims[2];
  auto kind = [&](int64_t i) { return codes[size_t(i)] == 0 ? 0u : 1u + layout::voxelMaterial(codes[size_t(i)]); };
  const std::array<int64_t, 3> step{1, nx, nx * ny};
  const std::array<double, 3> face{pitch[1] * pitch[2], pitch[0] * pitch[2], pitch[0] * pitch[1]};
  std::array<uint64_t, 3> count{};
  for (int64_t z = 0; z < nz; ++z)
    for (int64_t y = 0; y < ny; ++y)
      for (int64_t x = 0; x < nx; ++x) {
        const int64_t i = x + nx * (y + ny * z);
        const uint32_t k = kind(i);
        const std::array<int64_t, 3> at{x, y, z};
        for (size_t a = 0; a < 3; ++a) {
          const bool last = at[a] + 1 == dims[a];
          if (last ? k != 0 : kind(i + step[a]) != k) ++count[a];
          if (at[a] == 0 && k != 0) ++count[a];
        }
      }
  return double(count[0]) * face[0] + double(count[1]) * face[1] + double(count[2]) * face[2];
}

// ---- 7. import helpers ----------------------------------------------------------------------

// The source matrix with each column rescaled to `pitch` (direction and sign kept, offset kept).
int levelFor(double voxels_per_side) {
  int level = DS_MIN_LEVEL;
  while (level <= DS_MAX_LEVEL && double(int64_t{1} << level) < voxels_per_side) ++level;
  return level;
}

}  // namespace

// ---- 1. label maps --------------------------------------------------------------------------

Result<LabelMap> parseLabelMap(const std::string& text) {
  const std::string where = "label map '" + text + "'";
  LabelMap map;
  std::stringstream items(text);
  std::string item;
  while (std::getline(items, item, ',')) {
    item = trim(item);
    const size_t eq = item.find('=');
    if (item.empty() || eq == std::string::npos)
      return makeError(where, "expected LABEL=TISSUE items separated by commas, got '" + item + "'");
    const std::string label_text = trim(item.substr(0, eq));
    const std::string tissue = trim(item.substr(eq + 1));
    int64_t label = 0;
    size_t used = 0;
    try {
      label = std::stoll(label_text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (label_text.empty() || used != label_text.size())
      return makeError(where, "'" + label_text + "' is not an integer label");
    if (label == 0) return makeError(where, "label 0 is always empty and cannot be mapped");
    if (label < std::numeric_limits<Label>::min() || label > std::numeric_limits<Label>::max())
      return makeError(where, "label " + label_text + " is outside -32768..32767");
    Material m{};
    if (!parseMaterial(tissue, &m))
      return makeError(where, "unknown tissue '" + tissue + "' (expected " + tissueNameList(true) + ")");
    if (!map.emplace(int32_t(label), m).second)
      return makeError(where, "label " + std::to_string(label) + " is mapped twice");
  }
  if (map.empty()) return makeError(where, "no LABEL=TISSUE items");
  if (!text.empty() && text.back() == ',') return makeError(where, "trailing comma");
  return map;
}

// ---- 7. importLabels ------------------------------------------------------------------------

Result<ToothVolume> importLabels(const LabelImage& image, const LabelImportOptions& options,
                                 Interrupter& interrupter, LabelImportReport* report) {
  const std::string& where = options.where;
  LabelImportReport ignored;
  LabelImportReport& out = report ? *report : ignored;
  out = LabelImportReport{};
  for (int32_t d : image.dims)
    if (d <= 0) return makeError(where, "label image has no voxels");
  if (image.labels.size() != size_t(image.voxelCount()))
    return makeError(where, "label count does not match the dimensions");
  if (options.level && options.voxel_mm)
    return makeError(where, "give a target voxel size or a level, not both");
  if (options.level && (*options.level < DS_MIN_LEVEL || *options.level > DS_MAX_LEVEL))
    return makeError(where, "level " + std::to_string(*options.level) + " is outside " +
                                std::to_string(DS_MIN_LEVEL) + ".." + std::to_string(DS_MAX_LEVEL));
  if (options.voxel_mm && !(std::isfinite(*options.voxel_mm) && *options.voxel_mm > 0))
    return makeError(where, "voxel size must be a positive number of mm");
  if (options.source_pitch_mm && !(std::isfinite(*options.source_pitch_mm) && *options.source_pitch_mm > 0))
    return makeError(where, "source voxel size must be a positive number of mm");
  if (options.min_piece_voxels < 0)
    return makeError(where, "minimum piece size must be 0 or more voxels, not " +
                                std::to_string(options.min_piece_voxels));

  // The pitch that holds: an override replaces the header's (which CT exports often get wrong).
  std::array<double, 3> pitch = image.pitch_mm;
  std::array<double, 12> scanner = image.scanner_from_voxel;
  if (options.source_pitch_mm) {
    pitch = {*options.source_pitch_mm, *options.source_pitch_mm, *options.source_pitch_mm};
    scanner = scannerWithPitch(scanner, pitch);
  }
  auto same = [](double a, double b) { return std::fabs(a - b) <= 1e-9 * std::max(a, b); };
  const bool isotropic = same(pitch[0], pitch[1]) && same(pitch[0], pitch[2]);
  const bool direct = !options.level && isotropic && (!options.voxel_mm || same(*options.voxel_mm, pitch[0]));
  if (!options.level && !options.voxel_mm && !isotropic)
    return makeError(where, "anisotropic voxels; give a voxel size or a level to resample to");

  interrupter.start("importing labels");
  const bool cleaning = options.min_piece_voxels > 0;
  const bool filling = options.fill_enclosed.has_value();
  // Progress: codes 15 %, clean-up 15 %, fill 30 %, placement the rest.
  const double cleaned_at = cleaning ? 0.3 : 0.15;
  const double filled_at = cleaned_at + (filling ? 0.3 : 0.0);
  Result<std::vector<uint8_t>> codes = sourceCodes(image, options, Stage{interrupter, 0.0, 0.15});
  if (!codes) return codes.error();
  // Before the fill: a lone empty voxel inside dentin would otherwise become a pulp speck.
  if (cleaning) {
    if (Status s = relabelSmallPieces(*codes, image.dims, options.min_piece_voxels, out.cleanup,
                                      Stage{interrupter, 0.15, cleaned_at}, where);
        !s)
      return s.error();
  }
  if (filling) {
    const uint8_t fill = makeVoxel(*options.fill_enclosed, DS_FILL_FULL);
    // Dentin walls the pulp; a tooth without dentin is sealed as a whole.
    const bool has_dentin = std::any_of(codes->begin(), codes->end(),
                                        [](uint8_t c) { return voxelMaterial(c) == Material::Dentin; });
    const int seal_voxels = int(std::lround(options.seal_mm / pitch[0]));
    if (seal_voxels > 254) return makeError(where, "seal radius is over 254 source voxels");
    if (Status s = fillEnclosed(*codes, image.dims, fill, has_dentin ? std::optional(Material::Dentin) : std::nullopt,
                                seal_voxels, Stage{interrupter, cleaned_at, filled_at}, where);
        !s)
      return s.error();
  }
  const Stage place{interrupter, filled_at, 1.0};

  ToothVolume tooth;
  if (direct) {
    const int32_t longest = std::max({image.dims[0], image.dims[1], image.dims[2]});
    const int level = levelFor(double(longest));
    if (level > DS_MAX_LEVEL)
      return makeError(where, "a " + std::to_string(longest) + "-voxel side needs a grid beyond level " +
                                  std::to_string(DS_MAX_LEVEL));
    tooth.voxels = BrickVolume(level);
    if (Status s = placeDirect(*codes, image.dims, tooth.voxels, place, where); !s) return s.error();
    tooth.frame.level = level;
    tooth.frame.voxel_mm = pitch[0];
    tooth.frame.origin_mm = {0, 0, 0};
    tooth.frame.source_offset = {0, 0, 0};
    tooth.frame.source_dims = image.dims;
    tooth.frame.scanner_from_grid = scanner;
  } else {
    // The tissue's bounding box, in source voxels.
    std::array<int64_t, 3> lo{image.dims[0], image.dims[1], image.dims[2]}, hi{-1, -1, -1};
    const int64_t nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
    for (int64_t z = 0; z < nz; ++z)
      for (int64_t y = 0; y < ny; ++y) {
        const uint8_t* row = &(*codes)[size_t(nx * (y + ny * z))];
        for (int64_t x = 0; x < nx; ++x)
          if (row[x] != 0) {
            lo = {std::min(lo[0], x), std::min(lo[1], y), std::min(lo[2], z)};
            hi = {std::max(hi[0], x), std::max(hi[1], y), std::max(hi[2], z)};
          }
      }
    if (hi[0] < 0) return makeError(where, "no tissue to resample (every mapped voxel is empty)");
    if (options.fit_box) {
      for (size_t a = 0; a < 3; ++a) {
        lo[a] = (*options.fit_box)[a][0];
        hi[a] = (*options.fit_box)[a][1];
        if (hi[a] < lo[a]) return makeError(where, "the box to fit is empty");
      }
    }
    double extent = 0;  // longest side of the box [mm]
    for (size_t a = 0; a < 3; ++a) extent = std::max(extent, double(hi[a] - lo[a] + 1) * pitch[a]);
    Resampling rs;
    if (options.level) {
      rs.level = *options.level;
      rs.voxel_mm = extent / double((int64_t{1} << rs.level) - 4);  // 2 margin voxels each side
    } else {
      rs.voxel_mm = *options.voxel_mm;
      rs.level = levelFor(extent / rs.voxel_mm + 4.0);
      if (rs.level > DS_MAX_LEVEL) {
        std::ostringstream msg;  // shortest form: a hostile 1e-300 must not print 300 digits
        msg << "voxel size " << rs.voxel_mm << " mm needs a grid beyond level " << DS_MAX_LEVEL;
        return makeError(where, msg.str());
      }
    }
    if (options.approve) {
      const double faces = tissueSurfaceMm2(*codes, image.dims, pitch) / (rs.voxel_mm * rs.voxel_mm);
      if (Status s = options.approve(estimateLabelImport(rs.level, faces, uint64_t(image.voxelCount()))); !s)
        return s.error();
    }
    const double grid = double(int64_t{1} << rs.level);
    for (size_t a = 0; a < 3; ++a) {
      rs.ratio[a] = rs.voxel_mm / pitch[a];
      rs.samples[a] = std::clamp(int(std::ceil(rs.ratio[a] - 1e-9)), 1, 4);
      const double centre = 0.5 * double(lo[a] + hi[a]);
      rs.low[a] = centre - 0.5 * grid * rs.ratio[a];
    }
    tooth.voxels = BrickVolume(rs.level);
    if (Status s = placeResampled(*codes, image.dims, rs, tooth.voxels, place, where, options.uniform_shortcuts,
                                   &out.sampled_voxels); !s) return s.error();
    tooth.frame.level = rs.level;
    tooth.frame.voxel_mm = rs.voxel_mm;
    tooth.frame.origin_mm = {0, 0, 0};
    // Target voxel centre (i,j,k) sits at source index low + (i + 0.5) * ratio.
    std::array<double, 12>& g = tooth.frame.scanner_from_grid;
    for (size_t r = 0; r < 3; ++r) {
      g[4 * r + 3] = scanner[4 * r + 3];
      for (size_t c = 0; c < 3; ++c) {
        g[4 * r + c] = scanner[4 * r + c] * rs.ratio[c];
        g[4 * r + 3] += scanner[4 * r + c] * (rs.low[c] + 0.5 * rs.ratio[c]);
      }
    }
  }
  interrupter.end();
  return tooth;
}

Status cleanSmallPieces(std::vector<Voxel>& codes, const std::array<int32_t, 3>& dims, int64_t min_voxels,
                        PieceCleanup& report, Interrupter& interrupter, const std::string& where) {
  assert(codes.size() == size_t(int64_t{dims[0]} * dims[1] * dims[2]));
  return relabelSmallPieces(codes, dims, min_voxels, report, Stage{interrupter, 0.0, 1.0}, where);
}

// ---- 8. exportLabels ------------------------------------------------------------------------

LabelImage exportLabels(const ToothVolume& tooth, ExportRegion region) {
  if (tooth.frame.tooth.turned()) {
    // Labels go out in the source's own grid, voxel for voxel, as they came in.
    ToothVolume source = tooth;
    turnTooth(source, inverseTurn(tooth.frame.tooth.turn));
    return exportLabels(source, region);
  }
  const VolumeFrame& frame = tooth.frame;
  const BrickVolume& volume = tooth.voxels;
  std::array<int64_t, 3> offset{0, 0, 0};
  std::array<int32_t, 3> dims{int32_t(volume.dim()), int32_t(volume.dim()), int32_t(volume.dim())};
  if (region == ExportRegion::Auto && frame.hasSource()) {
    for (size_t a = 0; a < 3; ++a) {
      // A source box is clipped to the grid, so a damaged frame cannot make us read outside it.
      offset[a] = std::clamp<int64_t>(frame.source_offset[a], 0, volume.dim() - 1);
      dims[a] = int32_t(std::min<int64_t>(frame.source_dims[a], volume.dim() - offset[a]));
    }
  }
  LabelImage image;
  image.dims = dims;
  image.pitch_mm = {frame.voxel_mm, frame.voxel_mm, frame.voxel_mm};
  image.scanner_from_voxel = frame.scanner_from_grid;
  for (size_t r = 0; r < 3; ++r)
    for (size_t c = 0; c < 3; ++c)
      image.scanner_from_voxel[4 * r + 3] += frame.scanner_from_grid[4 * r + c] * double(offset[c]);
  image.labels.assign(size_t(image.voxelCount()), 0);

  // Each code's label from the tissue table; a spare code (no row) keeps its code, so no voxel is lost.
  std::array<Label, DS_MATERIAL_COUNT> code_label{};
  for (uint32_t m = 1; m < DS_MATERIAL_COUNT; ++m) {
    const TissueRow* row = findTissue(Material(m));
    code_label[m] = Label(row ? row->nifti_label : int32_t(m));
  }
  // Half-solid rule: a voxel counts as its tissue when at least 16 of 31 fill units remain.
  auto label = [&code_label](Voxel v) -> Label {
    return voxelFill(v) >= 16 ? code_label[layout::voxelMaterial(v)] : Label(0);
  };
  const int64_t end[3] = {offset[0] + dims[0], offset[1] + dims[1], offset[2] + dims[2]};
  for (int64_t bz = offset[2] / 8; bz * 8 < end[2]; ++bz)
    for (int64_t by = offset[1] / 8; by * 8 < end[1]; ++by)
      for (int64_t bx = offset[0] / 8; bx * 8 < end[0]; ++bx) {
        const BrickView view = volume.brick(BrickCoord{uint32_t(bx), uint32_t(by), uint32_t(bz)});
        if (view.uniform && label(view.value) == 0) continue;
        for (int64_t z = std::max(bz * 8, offset[2]); z < std::min(bz * 8 + 8, end[2]); ++z)
          for (int64_t y = std::max(by * 8, offset[1]); y < std::min(by * 8 + 8, end[1]); ++y)
            for (int64_t x = std::max(bx * 8, offset[0]); x < std::min(bx * 8 + 8, end[0]); ++x) {
              const Voxel v = view.uniform ? view.value
                                           : view.voxels[layout::brickCoordToOffset(
                                                 uint32_t(x - bx * 8), uint32_t(y - by * 8), uint32_t(z - bz * 8))];
              image.labels[image.index(x - offset[0], y - offset[1], z - offset[2])] = label(v);
            }
      }
  return image;
}

}  // namespace dentsim
