// GpuSurface: the tooth's surface kept on the GPU by marching cubes, re-meshed per dirty brick into per-block slots.
//
// The slots are meshed by the compute kernel, or on a CPU device (lavapipe) by the host's threads
// with the BlockMesher, written straight into host-visible slot pages (MesherKind). Either way the
// renderer reads the same pages and draw records.
//
// Contents
//   1. Options and statistics
//   2. GpuSurface: full build, incremental update, what the renderer binds, read-back for tests
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/worker_pool.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/mesher_kind.h"
#include "volume/surface_layout.h"
#include "volume/brick_volume.h"
#include "volume/surface_mesher.h"

namespace dentsim::gpu {

// ---- 1. options and statistics ----------------------------------------------------------------------

struct GpuSurfaceOptions {
  int normal_neighbours = 216;                  // 8, 64 or 216 (normalModeFromNeighbours); see SurfaceOptions
  Material tissue = Material::Empty;            // Empty: all tissue; else that tissue's own surface
  uint64_t initial_pool_bytes = 4ull << 20;     // first size of the slot pool; it doubles on demand [B]
  uint32_t max_groups_per_dispatch = 0;         // 0: the device limit; tests lower it to split dispatches
  uint64_t max_page_bytes = 0;                  // 0: one storage binding; tests lower it to open pages [B]
  MesherKind mesher = MesherKind::Auto;         // Auto: CPU threads on a CPU device, the kernel on a GPU
  uint32_t cpu_threads = 0;                     // CPU mesher threads, the caller's included; 0: one per core
  // The CPU mesher's threads shared with other surfaces that are only ever meshed one at a time
  // (a tooth's tissues and copies); null: the surface starts its own (cpu_threads).
  std::shared_ptr<WorkerPool> workers = nullptr;
};

// What one build or update did.
struct SurfaceUpdateStats {
  uint32_t dirty_bricks = 0;      // bricks the caller named
  uint32_t blocks_meshed = 0;     // cell blocks dispatched (dirty bricks widened by the normals' reach)
  uint32_t blocks_live = 0;       // blocks holding triangles after the update
  uint64_t triangles = 0;         // triangles in the whole surface after the update
  uint64_t vertices = 0;          // vertices in the whole surface (face copies counted per block)
  uint64_t pool_bytes = 0;        // size of the slot pool [B]
  uint64_t slot_bytes = 0;        // bytes held by live slots, rounded to their size class [B]
  uint64_t used_bytes = 0;        // bytes the live blocks' vertices and indices fill [B]
  bool pool_grew = false;         // the pool was reallocated (its contents copied on the GPU)
  double upload_ms = 0.0;         // wall time to sync the dirty bricks to the GPU mirror [ms]; 0 on the CPU mesher
  double count_ms = 0.0;          // wall time of the count pass incl. read-back (CPU mesher: its count pass) [ms]
  double emit_ms = 0.0;           // wall time of the slot allocation and emit pass (CPU mesher: its emit) [ms]
  double total_ms = 0.0;          // wall time of the whole call [ms]
  bool timestamps = false;        // the kernel times below are valid (never on the CPU mesher)
  double count_kernel_ms = 0.0;   // GPU time of the count dispatches [ms]
  double emit_kernel_ms = 0.0;    // GPU time of the emit dispatches [ms]
};

// One indexed draw per live block, as vkCmdDrawIndexedIndirect reads it (VkDrawIndexedIndirectCommand).
struct SurfaceDraw {
  uint32_t index_count;
  uint32_t instance_count;
  uint32_t first_index;
  int32_t vertex_offset;
  uint32_t first_instance;  // the block, packed as layout::meshBlockPack
};

// ---- 2. GpuSurface ----------------------------------------------------------------------------------

class GpuSurface {
 public:
  // Creates the pipelines (GPU mesher) or the threads (CPU mesher) and empty buffers. Errors: a
  // bad normal mode, a device the kernel cannot run on (GPU mesher), a Vulkan failure.
  static Result<GpuSurface> create(Context& ctx, const GpuSurfaceOptions& options);

  // The mesher this surface runs: options.mesher with Auto resolved for the context's device.
  MesherKind mesher() const;

  // Uploads the whole volume and meshes every block that can hold surface, dropping all slots.
  // Levels DS_MIN_LEVEL..12 (block coordinates must fit 10 bits).
  Status build(const BrickVolume& volume, SurfaceUpdateStats* stats = nullptr);

  // The volume changed only inside `dirty` bricks since the last build or update: syncs those bricks
  // to the GPU mirror and re-meshes the blocks whose cells or normals read them. The result equals
  // build() on the same volume, triangle for triangle. Errors: no build yet, a different level.
  Status update(const BrickVolume& volume, std::span<const BrickCoord> dirty, SurfaceUpdateStats* stats = nullptr);

  // A build in parts (the first frame drawn before the whole surface is meshed): clear() uploads
  // the whole volume and drops every slot, meshing nothing; meshBlocks() then meshes the blocks it
  // is given (those that can hold no surface are freed), a few at a time. The volume must be the one
  // last given to clear, build or update. Errors: no volume yet, a different level.
  Status clear(const BrickVolume& volume);
  Status meshBlocks(const BrickVolume& volume, std::span<const MeshBlock> blocks, SurfaceUpdateStats* stats = nullptr);

  // What the renderer binds, per page: a pool holds live blocks' vertices (MeshVertex) each followed
  // by the block's indices (uint32, local to the block); its draw buffer holds drawCount(page)
  // SurfaceDraw records, freed ones with index_count 0. A page is one storage binding, so it never
  // exceeds maxStorageBufferRange; more surface opens another page. Everything stays on the GPU.
  uint32_t pageCount() const;
  Buffer& pool(uint32_t page);
  Buffer& draws(uint32_t page);
  uint32_t drawCount(uint32_t page) const;
  uint64_t liveBlocks() const;  // blocks holding triangles

  // Reads the GPU's copy of the voxels back (for tests): after build() or update() it equals the
  // volume those were given. Errors: nothing uploaded yet, a Vulkan failure, an index out of range,
  // the CPU mesher (it reads the host's bricks and keeps no GPU copy).
  Result<BrickVolume> downloadVolume();

  // Reads every live block back (for tests and export), ordered by block.
  Result<std::vector<BlockMesh>> downloadBlocks();

  GpuSurface(GpuSurface&&) noexcept;
  GpuSurface& operator=(GpuSurface&&) noexcept;
  ~GpuSurface();

 private:
  struct State;
  explicit GpuSurface(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace dentsim::gpu
