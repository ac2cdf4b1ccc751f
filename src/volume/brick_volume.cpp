// BrickVolume: two-level brick index (chunk table, index blocks) over a pool of dense 8^3 bricks.
#include "volume/brick_volume.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <numeric>

#include "volume/tissue_table.h"

namespace dentsim {
namespace {

constexpr uint32_t tile(Voxel v) { return DS_ENTRY_UNIFORM | v; }
constexpr bool isTile(uint32_t entry) { return (entry & DS_ENTRY_UNIFORM) != 0; }
constexpr Voxel tileValue(uint32_t entry) { return static_cast<Voxel>(entry & 0xffu); }
constexpr uint32_t entryIndex(uint32_t entry) { return entry & DS_ENTRY_INDEX_MASK; }

// A voxel code is valid when empty has no fill and every tissue has some.
bool validVoxel(Voxel v) {
  const uint32_t m = layout::voxelMaterial(v);
  const uint32_t f = layout::voxelFill(v);
  return m == DS_MAT_EMPTY ? f == 0 : f > 0;
}

// True and the common value when all 512 voxels are equal.
bool allEqual(const Voxel* voxels, Voxel* value) {
  const Voxel first = voxels[0];
  for (uint32_t i = 1; i < DS_BRICK_VOXELS; ++i)
    if (voxels[i] != first) return false;
  *value = first;
  return true;
}

}  // namespace

std::string materialName(Material m) {
  if (m == Material::Empty) return "empty";
  if (const TissueRow* row = findTissue(m)) return row->name;
  return "material" + std::to_string(static_cast<int>(m));
}

bool parseMaterial(const std::string& name, Material* out) {
  if (name == "empty") {
    *out = Material::Empty;
    return true;
  }
  for (const TissueRow& row : kTissueTable) {
    if (name == row.name) {
      *out = row.material;
      return true;
    }
  }
  return false;
}

// ---- creation and access ----------------------------------------------------------------------

BrickVolume::BrickVolume(int level) : level_(level) {
  assert(level >= DS_MIN_LEVEL && level <= DS_MAX_LEVEL);
  chunk_dim_ = level > int(DS_CHUNK_VOXEL_LOG2) ? 1u << (level - int(DS_CHUNK_VOXEL_LOG2)) : 1u;
  chunks_.assign(size_t(chunk_dim_) * chunk_dim_ * chunk_dim_, tile(0));
}

layout::GridInfo BrickVolume::gridInfo() const {
  const uint32_t bd = brickDim();
  return layout::GridInfo{uint32_t(level_), bd, chunk_dim_, bd * bd * bd};
}

uint32_t BrickVolume::chunkIndex(uint32_t cx, uint32_t cy, uint32_t cz) const {
  return layout::chunkCoordToIndex(cx, cy, cz, chunk_dim_);
}

Voxel BrickVolume::voxel(uint32_t x, uint32_t y, uint32_t z) const {
  assert(x < dim() && y < dim() && z < dim());
  const uint32_t centry = chunks_[chunkIndex(x >> DS_CHUNK_VOXEL_LOG2, y >> DS_CHUNK_VOXEL_LOG2, z >> DS_CHUNK_VOXEL_LOG2)];
  if (isTile(centry)) return tileValue(centry);
  const uint32_t bx = (x >> DS_BRICK_LOG2) & (DS_CHUNK_DIM - 1);
  const uint32_t by = (y >> DS_BRICK_LOG2) & (DS_CHUNK_DIM - 1);
  const uint32_t bz = (z >> DS_BRICK_LOG2) & (DS_CHUNK_DIM - 1);
  const uint32_t bentry = blocks_[size_t(entryIndex(centry)) * DS_CHUNK_BRICKS + layout::brickCoordToOffset(bx, by, bz)];
  if (isTile(bentry)) return tileValue(bentry);
  const uint32_t m = DS_BRICK_DIM - 1;
  return brickVoxels(entryIndex(bentry))[layout::brickCoordToOffset(x & m, y & m, z & m)];
}

uint32_t* BrickVolume::brickEntry(BrickCoord c, bool make_block) {
  uint32_t& centry = chunks_[chunkIndex(c.x >> DS_CHUNK_LOG2, c.y >> DS_CHUNK_LOG2, c.z >> DS_CHUNK_LOG2)];
  if (isTile(centry)) {
    if (!make_block) return nullptr;
    centry = allocBlock(tile(tileValue(centry)));
  }
  const uint32_t m = DS_CHUNK_DIM - 1;
  return &blocks_[size_t(entryIndex(centry)) * DS_CHUNK_BRICKS + layout::brickCoordToOffset(c.x & m, c.y & m, c.z & m)];
}

uint32_t BrickVolume::allocBlock(uint32_t fill_entry) {
  uint32_t index;
  if (!free_blocks_.empty()) {
    index = free_blocks_.back();
    free_blocks_.pop_back();
  } else {
    index = uint32_t(blocks_.size() / DS_CHUNK_BRICKS);
    assert(index <= DS_ENTRY_INDEX_MASK);
    blocks_.resize(blocks_.size() + DS_CHUNK_BRICKS);
  }
  std::fill_n(blocks_.begin() + std::ptrdiff_t(index) * DS_CHUNK_BRICKS, DS_CHUNK_BRICKS, fill_entry);
  return index;
}

uint32_t BrickVolume::allocBrick(Voxel fill_value) {
  uint32_t index;
  if (!free_bricks_.empty()) {
    index = free_bricks_.back();
    free_bricks_.pop_back();
  } else {
    index = uint32_t(bricks_.size() / DS_BRICK_WORDS);
    assert(index <= DS_ENTRY_INDEX_MASK);
    bricks_.resize(bricks_.size() + DS_BRICK_WORDS);
  }
  std::memset(brickVoxels(index), fill_value, DS_BRICK_VOXELS);
  return index;
}

void BrickVolume::freeBrick(uint32_t index) { free_bricks_.push_back(index); }

void BrickVolume::reserveSpare(size_t blocks, size_t bricks) {
  blocks_.reserve(blocks_.size() + blocks * DS_CHUNK_BRICKS);
  bricks_.reserve(bricks_.size() + bricks * DS_BRICK_WORDS);
}

void BrickVolume::setVoxel(uint32_t x, uint32_t y, uint32_t z, Voxel v) {
  assert(x < dim() && y < dim() && z < dim());
  assert(validVoxel(v));
  if (voxel(x, y, z) == v) return;  // keeps tiles intact for no-op writes
  uint32_t* entry = brickEntry({x >> DS_BRICK_LOG2, y >> DS_BRICK_LOG2, z >> DS_BRICK_LOG2}, true);
  if (isTile(*entry)) *entry = allocBrick(tileValue(*entry));
  const uint32_t m = DS_BRICK_DIM - 1;
  brickVoxels(entryIndex(*entry))[layout::brickCoordToOffset(x & m, y & m, z & m)] = v;
}

Voxel* BrickVolume::writableBrick(BrickCoord c) {
  assert(c.x < brickDim() && c.y < brickDim() && c.z < brickDim());
  uint32_t* entry = brickEntry(c, true);
  if (isTile(*entry)) *entry = allocBrick(tileValue(*entry));
  return brickVoxels(entryIndex(*entry));
}

BrickView BrickVolume::brick(BrickCoord c) const {
  assert(c.x < brickDim() && c.y < brickDim() && c.z < brickDim());
  BrickView view;
  view.coord = c;
  const uint32_t centry = chunks_[chunkIndex(c.x >> DS_CHUNK_LOG2, c.y >> DS_CHUNK_LOG2, c.z >> DS_CHUNK_LOG2)];
  if (isTile(centry)) {
    view.value = tileValue(centry);
    return view;
  }
  const uint32_t m = DS_CHUNK_DIM - 1;
  const uint32_t bentry = blocks_[size_t(entryIndex(centry)) * DS_CHUNK_BRICKS + layout::brickCoordToOffset(c.x & m, c.y & m, c.z & m)];
  if (isTile(bentry)) {
    view.value = tileValue(bentry);
    return view;
  }
  view.uniform = false;
  view.voxels = brickVoxels(entryIndex(bentry));
  return view;
}

void BrickVolume::setBrick(BrickCoord c, const Voxel* voxels) {
  Voxel same = 0;
  if (allEqual(voxels, &same)) {
    setBrickUniform(c, same);
    return;
  }
  uint32_t* entry = brickEntry(c, true);
  if (isTile(*entry)) *entry = allocBrick(0);
  std::memcpy(brickVoxels(entryIndex(*entry)), voxels, DS_BRICK_VOXELS);
}

void BrickVolume::setBrickUniform(BrickCoord c, Voxel v) {
  assert(validVoxel(v));
  uint32_t* entry = brickEntry(c, false);
  if (entry == nullptr) {
    // The chunk is a tile: writing its own value changes nothing and needs no block.
    const uint32_t centry = chunks_[chunkIndex(c.x >> DS_CHUNK_LOG2, c.y >> DS_CHUNK_LOG2, c.z >> DS_CHUNK_LOG2)];
    if (tileValue(centry) == v) return;
    entry = brickEntry(c, true);
  }
  if (!isTile(*entry)) freeBrick(entryIndex(*entry));
  *entry = tile(v);
}

std::optional<Voxel> BrickVolume::chunkTile(uint32_t cx, uint32_t cy, uint32_t cz) const {
  const uint32_t centry = chunks_[chunkIndex(cx, cy, cz)];
  if (!isTile(centry)) return std::nullopt;
  return tileValue(centry);
}

void BrickVolume::setChunkUniform(uint32_t cx, uint32_t cy, uint32_t cz, Voxel v) {
  assert(validVoxel(v) && cx < chunk_dim_ && cy < chunk_dim_ && cz < chunk_dim_);
  uint32_t& centry = chunks_[chunkIndex(cx, cy, cz)];
  if (!isTile(centry)) {
    const uint32_t block = entryIndex(centry);
    for (uint32_t i = 0; i < DS_CHUNK_BRICKS; ++i) {
      const uint32_t e = blocks_[size_t(block) * DS_CHUNK_BRICKS + i];
      if (!isTile(e)) freeBrick(entryIndex(e));
    }
    free_blocks_.push_back(block);
  }
  centry = tile(v);
}

void BrickVolume::forEachBrick(const std::function<void(const BrickView&)>& fn) const {
  const uint32_t bd = brickDim();
  for (uint32_t z = 0; z < bd; ++z)
    for (uint32_t y = 0; y < bd; ++y)
      for (uint32_t x = 0; x < bd; ++x) fn(brick({x, y, z}));
}

void BrickVolume::forEachDenseBrick(const std::function<void(const BrickView&)>& fn) const {
  // Walks chunks so that tile chunks cost one read, not 512.
  const uint32_t bd = brickDim();
  const uint32_t span = std::min<uint32_t>(bd, DS_CHUNK_DIM);
  for (uint32_t cz = 0; cz < chunk_dim_; ++cz)
    for (uint32_t cy = 0; cy < chunk_dim_; ++cy)
      for (uint32_t cx = 0; cx < chunk_dim_; ++cx) {
        if (isTile(chunks_[chunkIndex(cx, cy, cz)])) continue;
        for (uint32_t z = 0; z < span; ++z)
          for (uint32_t y = 0; y < span; ++y)
            for (uint32_t x = 0; x < span; ++x) {
              const BrickView v = brick({cx * DS_CHUNK_DIM + x, cy * DS_CHUNK_DIM + y, cz * DS_CHUNK_DIM + z});
              if (!v.uniform) fn(v);
            }
      }
}

void BrickVolume::compact() {
  // 1. Dense bricks whose voxels are all equal become tiles; chunks whose bricks are one tile too.
  const uint32_t used_span = std::min<uint32_t>(brickDim(), DS_CHUNK_DIM);
  std::vector<bool> block_live(blocks_.size() / DS_CHUNK_BRICKS, false);
  for (uint32_t& centry : chunks_) {
    if (isTile(centry)) continue;
    uint32_t* entries = &blocks_[size_t(entryIndex(centry)) * DS_CHUNK_BRICKS];
    for (uint32_t i = 0; i < DS_CHUNK_BRICKS; ++i) {
      Voxel same = 0;
      if (!isTile(entries[i]) && allEqual(brickVoxels(entryIndex(entries[i])), &same)) {
        freeBrick(entryIndex(entries[i]));
        entries[i] = tile(same);
      }
    }
    // Entries outside a grid smaller than one chunk stay empty tiles and do not count.
    bool uniform = true;
    uint32_t first = entries[0];
    for (uint32_t z = 0; z < used_span && uniform; ++z)
      for (uint32_t y = 0; y < used_span && uniform; ++y)
        for (uint32_t x = 0; x < used_span && uniform; ++x)
          uniform = isTile(first) && entries[layout::brickCoordToOffset(x, y, z)] == first;
    if (uniform) {
      centry = first;
    } else {
      block_live[entryIndex(centry)] = true;
    }
  }
  // 2. Pack blocks and bricks in chunk order so that equal volumes give equal words.
  std::vector<uint32_t> blocks;
  std::vector<uint32_t> bricks;
  for (uint32_t& centry : chunks_) {
    if (isTile(centry)) continue;
    const uint32_t new_block = uint32_t(blocks.size() / DS_CHUNK_BRICKS);
    blocks.insert(blocks.end(), blocks_.begin() + std::ptrdiff_t(entryIndex(centry)) * DS_CHUNK_BRICKS,
                  blocks_.begin() + std::ptrdiff_t(entryIndex(centry) + 1) * DS_CHUNK_BRICKS);
    uint32_t* entries = &blocks[size_t(new_block) * DS_CHUNK_BRICKS];
    for (uint32_t i = 0; i < DS_CHUNK_BRICKS; ++i) {
      if (isTile(entries[i])) continue;
      const uint32_t new_brick = uint32_t(bricks.size() / DS_BRICK_WORDS);
      bricks.insert(bricks.end(), bricks_.begin() + std::ptrdiff_t(entryIndex(entries[i])) * DS_BRICK_WORDS,
                    bricks_.begin() + std::ptrdiff_t(entryIndex(entries[i]) + 1) * DS_BRICK_WORDS);
      entries[i] = new_brick;
    }
    centry = new_block;
  }
  blocks_ = std::move(blocks);
  bricks_ = std::move(bricks);
  blocks_.shrink_to_fit();
  bricks_.shrink_to_fit();
  free_blocks_.clear();
  free_bricks_.clear();
}

// ---- raw arrays -------------------------------------------------------------------------------

Result<BrickVolume> BrickVolume::fromWords(int level, std::vector<uint32_t> chunks, std::vector<uint32_t> blocks,
                                           std::vector<uint32_t> bricks, const std::string& where) {
  if (level < DS_MIN_LEVEL || level > DS_MAX_LEVEL)
    return makeError(where, "grid level " + std::to_string(level) + " outside " + std::to_string(DS_MIN_LEVEL) +
                                ".." + std::to_string(DS_MAX_LEVEL));
  BrickVolume v(level);
  if (chunks.size() != v.chunks_.size())
    return makeError(where, "chunk table has " + std::to_string(chunks.size()) + " entries, level " +
                                std::to_string(level) + " needs " + std::to_string(v.chunks_.size()));
  if (blocks.size() % DS_CHUNK_BRICKS != 0) return makeError(where, "index blocks are not whole");
  if (bricks.size() % DS_BRICK_WORDS != 0) return makeError(where, "brick pool is not whole bricks");
  const size_t block_count = blocks.size() / DS_CHUNK_BRICKS;
  const size_t brick_count = bricks.size() / DS_BRICK_WORDS;
  std::vector<uint8_t> block_refs(block_count, 0), brick_refs(brick_count, 0);
  auto badTile = [&](uint32_t entry, const char* what, size_t i) -> Result<BrickVolume> {
    return makeError(where, std::string(what) + " " + std::to_string(i) + " holds invalid voxel code " +
                                std::to_string(entry & 0xffu) + " or stray bits");
  };
  for (size_t i = 0; i < chunks.size(); ++i) {
    const uint32_t e = chunks[i];
    if (isTile(e)) {
      if ((e & ~(DS_ENTRY_UNIFORM | 0xffu)) != 0 || !validVoxel(tileValue(e))) return badTile(e, "chunk", i);
      continue;
    }
    if (entryIndex(e) >= block_count || block_refs[entryIndex(e)]++ != 0)
      return makeError(where, "chunk " + std::to_string(i) + " points at index block " + std::to_string(e) +
                                  " which is out of range or shared");
  }
  for (size_t b = 0; b < block_count; ++b) {
    if (block_refs[b] == 0) return makeError(where, "index block " + std::to_string(b) + " is unreferenced");
    for (uint32_t i = 0; i < DS_CHUNK_BRICKS; ++i) {
      const uint32_t e = blocks[b * DS_CHUNK_BRICKS + i];
      if (isTile(e)) {
        if ((e & ~(DS_ENTRY_UNIFORM | 0xffu)) != 0 || !validVoxel(tileValue(e))) return badTile(e, "brick entry", i);
        continue;
      }
      if (entryIndex(e) >= brick_count || brick_refs[entryIndex(e)]++ != 0)
        return makeError(where, "index block " + std::to_string(b) + " points at brick " + std::to_string(e) +
                                    " which is out of range or shared");
    }
  }
  const auto* voxels = reinterpret_cast<const Voxel*>(bricks.data());
  for (size_t k = 0; k < brick_count; ++k) {
    if (brick_refs[k] == 0) return makeError(where, "brick " + std::to_string(k) + " is unreferenced");
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i)
      if (!validVoxel(voxels[k * DS_BRICK_VOXELS + i]))
        return makeError(where, "brick " + std::to_string(k) + " holds invalid voxel code " +
                                    std::to_string(voxels[k * DS_BRICK_VOXELS + i]));
  }
  v.chunks_ = std::move(chunks);
  v.blocks_ = std::move(blocks);
  v.bricks_ = std::move(bricks);
  return v;
}

// ---- statistics -------------------------------------------------------------------------------

BrickStats BrickVolume::stats() const {
  BrickStats s;
  s.chunks = chunks_.size();
  const uint32_t used_span = std::min<uint32_t>(brickDim(), DS_CHUNK_DIM);
  for (uint32_t centry : chunks_) {
    if (isTile(centry)) {
      ++s.uniform_chunks;
      continue;
    }
    ++s.blocks;
    const uint32_t* entries = &blocks_[size_t(entryIndex(centry)) * DS_CHUNK_BRICKS];
    for (uint32_t z = 0; z < used_span; ++z)
      for (uint32_t y = 0; y < used_span; ++y)
        for (uint32_t x = 0; x < used_span; ++x) {
          if (isTile(entries[layout::brickCoordToOffset(x, y, z)])) ++s.uniform_bricks;
          else ++s.dense_bricks;
        }
  }
  s.bytes = (s.chunks + s.blocks * DS_CHUNK_BRICKS + s.dense_bricks * DS_BRICK_WORDS) * sizeof(uint32_t);
  return s;
}

MaterialTotals BrickVolume::materialTotals() const {
  MaterialTotals t;
  auto addUniform = [&t](Voxel v, uint64_t count) {
    const uint32_t m = layout::voxelMaterial(v);
    t.voxels[m] += count;
    t.fill_sum[m] += count * layout::voxelFill(v);
  };
  // Voxels per chunk, clipped to the grid for grids smaller than one chunk.
  const uint64_t chunk_side = std::min<uint64_t>(dim(), uint64_t{1} << DS_CHUNK_VOXEL_LOG2);
  const uint32_t used_span = std::min<uint32_t>(brickDim(), DS_CHUNK_DIM);
  for (uint32_t centry : chunks_) {
    if (isTile(centry)) {
      addUniform(tileValue(centry), chunk_side * chunk_side * chunk_side);
      continue;
    }
    const uint32_t* entries = &blocks_[size_t(entryIndex(centry)) * DS_CHUNK_BRICKS];
    for (uint32_t z = 0; z < used_span; ++z)
      for (uint32_t y = 0; y < used_span; ++y)
        for (uint32_t x = 0; x < used_span; ++x) {
          const uint32_t e = entries[layout::brickCoordToOffset(x, y, z)];
          if (isTile(e)) {
            addUniform(tileValue(e), DS_BRICK_VOXELS);
            continue;
          }
          const Voxel* vox = brickVoxels(entryIndex(e));
          for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) addUniform(vox[i], 1);
        }
  }
  return t;
}

bool BrickVolume::operator==(const BrickVolume& other) const {
  if (level_ != other.level_) return false;
  // Chunk by chunk: two chunk tiles compare in one step, which is most of a large grid.
  const uint32_t bd = brickDim();
  const uint32_t span = std::min<uint32_t>(bd, DS_CHUNK_DIM);
  for (uint32_t cz = 0; cz < chunk_dim_; ++cz)
    for (uint32_t cy = 0; cy < chunk_dim_; ++cy)
      for (uint32_t cx = 0; cx < chunk_dim_; ++cx) {
        const std::optional<Voxel> ta = chunkTile(cx, cy, cz), tb = other.chunkTile(cx, cy, cz);
        if (ta && tb) {
          if (*ta != *tb) return false;
          continue;
        }
        for (uint32_t z = cz * span; z < cz * span + span; ++z)
          for (uint32_t y = cy * span; y < cy * span + span; ++y)
            for (uint32_t x = cx * span; x < cx * span + span; ++x) {
              const BrickView a = brick({x, y, z});
              const BrickView b = other.brick({x, y, z});
              if (a.uniform && b.uniform) {
                if (a.value != b.value) return false;
                continue;
              }
              for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
                const Voxel va = a.uniform ? a.value : a.voxels[i];
                const Voxel vb = b.uniform ? b.value : b.voxels[i];
                if (va != vb) return false;
              }
            }
      }
  return true;
}

BrickBox tissueBricks(const BrickVolume& volume) {
  BrickBox box;
  volume.forEachBrick([&](const BrickView& b) {
    if (b.uniform && voxelFill(b.value) == 0) return;
    box.lo = {std::min(box.lo.x, b.coord.x), std::min(box.lo.y, b.coord.y), std::min(box.lo.z, b.coord.z)};
    box.hi = {std::max(box.hi.x, b.coord.x), std::max(box.hi.y, b.coord.y), std::max(box.hi.z, b.coord.z)};
  });
  return box;
}

}  // namespace dentsim
