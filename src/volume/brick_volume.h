// BrickVolume: the sparse dense-brick octree that holds a tooth's voxels, on the CPU (the GPU mirrors its bytes).
//
// Contents
//   1. Entry points: creation, voxel access, brick access, iteration
//   2. Raw arrays (what the GPU uploads and the .dvol file stores) and their validation
//   3. Statistics: bytes, brick counts, tissue volumes
#pragma once

#include <algorithm>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/volume_frame.h"
#include "volume/brick_layout.h"

namespace dentsim {

using Voxel = uint8_t;  // material in bits 5..7, fill in bits 0..4 (see brick_layout.h)

enum class Material : uint8_t {
  Empty = DS_MAT_EMPTY,
  Enamel = DS_MAT_ENAMEL,
  Dentin = DS_MAT_DENTIN,
  Pulp = DS_MAT_PULP,
  Caries = DS_MAT_CARIES,
  Neighbour = DS_MAT_NEIGHBOUR,
};

constexpr Voxel makeVoxel(Material m, uint32_t fill = DS_FILL_FULL) {
  return static_cast<Voxel>(layout::makeVoxel(static_cast<uint32_t>(m), m == Material::Empty ? 0u : fill));
}
constexpr Material voxelMaterial(Voxel v) { return static_cast<Material>(layout::voxelMaterial(v)); }
constexpr uint32_t voxelFill(Voxel v) { return layout::voxelFill(v); }

// Lower-case tissue name ("enamel"), or "empty"; "material5".."material7" for the spare codes.
std::string materialName(Material m);
// Parses a tissue name; false if unknown.
bool parseMaterial(const std::string& name, Material* out);

// Brick coordinates in bricks, 0 .. brickDim()-1 on each axis.
struct BrickCoord {
  uint32_t x = 0, y = 0, z = 0;
};

// One brick as iteration sees it.
struct BrickView {
  BrickCoord coord;            // brick coordinate
  bool uniform = true;         // true: every voxel equals `value`, no storage
  Voxel value = 0;             // the tile value when uniform
  const Voxel* voxels = nullptr;  // (512) voxels, x fastest, when dense

  // The voxel at `offset` (brickCoordToOffset), uniform or dense alike.
  Voxel at(uint32_t offset) const { return uniform ? value : voxels[offset]; }
  // Whether both hold the same voxels (the same storage, or equal bytes).
  bool sameVoxels(const BrickView& o) const {
    if (uniform != o.uniform) return false;
    if (uniform) return value == o.value;
    return voxels == o.voxels || std::equal(voxels, voxels + DS_BRICK_VOXELS, o.voxels);
  }
};

// Per-tissue totals over the whole grid.
struct MaterialTotals {
  std::array<uint64_t, DS_MATERIAL_COUNT> voxels{};    // voxels of each material (any fill)
  std::array<uint64_t, DS_MATERIAL_COUNT> fill_sum{};  // sum of fill (units of 1/31 voxel)
  // Solid volume of material m [mm^3] for a voxel of edge voxel_mm.
  double volumeMm3(Material m, double voxel_mm) const {
    return double(fill_sum[size_t(m)]) / DS_FILL_FULL * voxel_mm * voxel_mm * voxel_mm;
  }
};

// Counts and bytes as `dentsim info` reports them.
struct BrickStats {
  uint64_t chunks = 0;            // chunk-table entries
  uint64_t uniform_chunks = 0;    // chunks stored as one tile
  uint64_t blocks = 0;            // live index blocks (chunks that are not uniform)
  uint64_t dense_bricks = 0;      // live dense bricks
  uint64_t uniform_bricks = 0;    // brick entries in live blocks that are tiles
  uint64_t bytes = 0;             // bytes of the three arrays, live entries only [B]
};

class BrickVolume {
 public:
  // ---- 1. creation and access -----------------------------------------------------------------
  // An empty grid of 2^level voxels per side, DS_MIN_LEVEL <= level <= DS_MAX_LEVEL.
  explicit BrickVolume(int level = DS_MIN_LEVEL);

  int level() const { return level_; }
  uint32_t dim() const { return 1u << level_; }                 // voxels per side
  uint32_t brickDim() const { return dim() >> DS_BRICK_LOG2; }  // bricks per side
  uint32_t chunkDim() const { return chunk_dim_; }              // chunks per side
  layout::GridInfo gridInfo() const;

  // Voxel at (x,y,z), each in [0, dim()).
  Voxel voxel(uint32_t x, uint32_t y, uint32_t z) const;
  // Sets one voxel, turning a uniform chunk or brick dense where needed.
  void setVoxel(uint32_t x, uint32_t y, uint32_t z, Voxel v);

  // The 512 voxels of brick c (x fastest), to write in place: a tile is turned dense first, as
  // setVoxel does. The pointer stays valid until the storage grows beyond its reserve or compact().
  Voxel* writableBrick(BrickCoord c);
  // The brick at c: a tile or its 512 voxels.
  BrickView brick(BrickCoord c) const;
  // Replaces a whole brick from 512 voxels (x fastest). A brick whose voxels are all equal is
  // stored as a tile and frees its storage. This is the fast path for importers.
  void setBrick(BrickCoord c, const Voxel* voxels);
  // Sets a whole brick to one value (a tile).
  void setBrickUniform(BrickCoord c, Voxel v);
  // The value of chunk (cx,cy,cz) when it is a tile (one value throughout); nullopt when it has bricks.
  std::optional<Voxel> chunkTile(uint32_t cx, uint32_t cy, uint32_t cz) const;
  // Sets a whole chunk (8^3 bricks) to one value (a chunk tile), freeing its block and bricks:
  // how importers fill a solid interior without touching its bricks one by one.
  void setChunkUniform(uint32_t cx, uint32_t cy, uint32_t cz, Voxel v);

  // Calls fn for every dense brick, in storage-independent order (z, then y, then x).
  void forEachDenseBrick(const std::function<void(const BrickView&)>& fn) const;
  // Calls fn for every brick, dense or tile, in the same order.
  void forEachBrick(const std::function<void(const BrickView&)>& fn) const;

  // Reserves room for `blocks` more index blocks and `bricks` more dense bricks beyond those in use,
  // so that setVoxel() can turn that many tiles dense without allocating (the haptic thread relies
  // on it). spareBlocks()/spareBricks() say how much reserved room is left.
  void reserveSpare(size_t blocks, size_t bricks);
  size_t spareBlocks() const {
    return free_blocks_.size() + (blocks_.capacity() - blocks_.size()) / DS_CHUNK_BRICKS;
  }
  size_t spareBricks() const {
    return free_bricks_.size() + (bricks_.capacity() - bricks_.size()) / DS_BRICK_WORDS;
  }

  // Turns dense bricks whose voxels became equal into tiles, and blocks whose entries became one
  // tile into chunk tiles; then packs the pools so no free slot remains.
  void compact();

  // ---- 2. raw arrays --------------------------------------------------------------------------
  // The exact words the GPU uploads and the .dvol stores. Call compact() first for no holes.
  std::span<const uint32_t> chunkWords() const { return chunks_; }
  std::span<const uint32_t> blockWords() const { return blocks_; }
  std::span<const uint32_t> brickWords() const { return bricks_; }
  // Rebuilds a volume from raw arrays, checking every entry: indices in range, each block and
  // brick referenced once, voxel codes valid. `where` names the source in the error.
  static Result<BrickVolume> fromWords(int level, std::vector<uint32_t> chunks,
                                       std::vector<uint32_t> blocks, std::vector<uint32_t> bricks,
                                       const std::string& where);

  // ---- 3. statistics --------------------------------------------------------------------------
  BrickStats stats() const;
  MaterialTotals materialTotals() const;
  bool operator==(const BrickVolume& other) const;  // same voxels (not the same storage)

 private:
  uint32_t chunkIndex(uint32_t cx, uint32_t cy, uint32_t cz) const;
  uint32_t* brickEntry(BrickCoord c, bool make_block);  // null when the chunk is a tile
  uint32_t allocBlock(uint32_t fill_entry);
  uint32_t allocBrick(Voxel fill_value);
  void freeBrick(uint32_t index);
  Voxel* brickVoxels(uint32_t index) { return reinterpret_cast<Voxel*>(&bricks_[size_t(index) * DS_BRICK_WORDS]); }
  const Voxel* brickVoxels(uint32_t index) const {
    return reinterpret_cast<const Voxel*>(&bricks_[size_t(index) * DS_BRICK_WORDS]);
  }

  int level_ = DS_MIN_LEVEL;
  uint32_t chunk_dim_ = 1;
  std::vector<uint32_t> chunks_;      // (chunkDim^3) chunk entries
  std::vector<uint32_t> blocks_;      // (blockCount x 512) brick entries
  std::vector<uint32_t> bricks_;      // (brickCount x 128) packed voxels
  std::vector<uint32_t> free_blocks_; // block slots that compact() will reclaim
  std::vector<uint32_t> free_bricks_; // brick slots ready for reuse
};

// The brick coordinates of every brick holding tissue, as an inclusive box; empty (lo > hi) when
// there is none.
struct BrickBox {
  BrickCoord lo{UINT32_MAX, UINT32_MAX, UINT32_MAX};
  BrickCoord hi{0, 0, 0};
  bool empty() const { return lo.x > hi.x; }
};
BrickBox tissueBricks(const BrickVolume& volume);

// How a tooth's tissues were known. Measured: each tissue from its own source (a surface per layer,
// a scan's grey values, labels). Synthesized: one closed surface split into enamel, dentin and pulp
// by published proportions (volume/tooth_layer_synth.h), which every view of the tooth must say.
enum class LayerSource : uint8_t { Measured = 0, Synthesized = 1 };

// A tooth as loaded: the constant frame and the mutable voxels.
struct ToothVolume {
  VolumeFrame frame;    // placement; never changes after loading
  BrickVolume voxels;   // the voxels; the simulation cuts these
  // Where the voxels came from and what was chosen on the way (a scan's thresholds), as lines for
  // `dentsim info`; kept in the .dvol file (io/dvol_file.h), empty when not recorded.
  std::string source_note{};
  LayerSource layers{LayerSource::Measured};  // kept in the .dvol; files before it load as Measured
  uint8_t synthesized_type{0};  // with Synthesized: the ToothType whose proportions were used (tooth_layer_synth.h); 0 unknown
};

}  // namespace dentsim
