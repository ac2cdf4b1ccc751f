// GpuSurface: the brick-volume mirror, the count and emit passes of surface_mesh.comp.glsl or of the CPU BlockMesher, and the slot pages.
//
// Contents
//   1. Pipelines, the volume mirror and the slot pages
//   2. One meshing round: count, allocate slots, emit, draw records; the count and emit on the GPU
//      or on the CPU threads
//   3. build, update, read-back
#include "gpu/gpu_surface.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstring>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "core/buddy_allocator.h"
#include "core/worker_pool.h"
#include "dentsim_compute_spirv_spirv.h"
#include "gpu/compute.h"
#include "gpu/vk_check.h"
#include "volume/block_mesher.h"

namespace dentsim::gpu {

namespace {

using Clock = std::chrono::steady_clock;
using layout::MeshJob;
using layout::MeshParams;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Shared memory of surface_mesh.comp.glsl [B]: prefix sums of 18^3 voxels, the F of 9^3 corners,
// three words for each of the 81 corner rows, 27 brick entries, the scan buffer and two totals.
constexpr uint32_t kKernelSharedBytes =
    4u * (DS_MESH_LOCAL_DIM * DS_MESH_LOCAL_DIM * DS_MESH_LOCAL_DIM + 729u + 3u * 81u + 27u + DS_MESH_GROUP_SIZE + 2u);

constexpr uint64_t kSlotUnit = 256;  // [B]; a multiple of the 16 B vertex, so vertexOffset is whole

// One page of slots: a pool buffer, its buddy allocator and its draw records.
struct Page {
  std::optional<Buffer> pool;
  std::optional<BuddyAllocator> slots;
  GrowingBuffer draws{{}, MemoryKind::HostVisible, "surface draws", BufferUse::Geometry};
  std::vector<SurfaceDraw> records;
  std::vector<uint32_t> free_records;
  std::vector<uint32_t> changed;  // records to copy to `draws` at the next writeDraws
};

// Where one block's triangles live.
struct Slot {
  uint32_t page = 0;
  uint64_t offset = 0;     // [B] in the page's pool
  uint32_t vertices = 0;
  uint32_t triangles = 0;
  uint32_t record = 0;     // draw record in the page
};

uint64_t slotBytesFor(uint32_t vertices, uint32_t triangles) {
  return uint64_t(vertices) * sizeof(layout::MeshVertex) + uint64_t(triangles) * 3u * sizeof(uint32_t);
}

}  // namespace

// ==== 1. state ====================================================================================
struct GpuSurface::State {
  Context* ctx = nullptr;
  GpuSurfaceOptions options;
  MesherKind mesher = MesherKind::Gpu;  // resolved: Gpu or Cpu
  uint32_t side = 0;
  // The CPU mesher: its threads and one BlockMesher (scratch) per thread.
  std::shared_ptr<WorkerPool> workers;  // the CPU mesher's threads, maybe shared with other surfaces
  std::vector<BlockMesher> block_meshers;
  std::vector<BlockCounts> cpu_counts;  // (blocks of the round) what the CPU count pass found
  std::optional<ComputePipeline> count, emit;
  std::optional<Buffer> cases;
  // The volume mirror: the three word arrays, with room to grow before a full re-upload.
  GrowingBuffer chunks{{}, MemoryKind::DeviceLocal, "surface mirror chunks", BufferUse::Storage};
  GrowingBuffer blocks{{}, MemoryKind::DeviceLocal, "surface mirror blocks", BufferUse::Storage};
  GrowingBuffer bricks{{}, MemoryKind::DeviceLocal, "surface mirror bricks", BufferUse::Storage};
  GrowingBuffer staging{{}, MemoryKind::HostVisible, "surface mirror staging", BufferUse::Transfer};
  GrowingBuffer jobs{{}, MemoryKind::HostVisible, "surface jobs", BufferUse::Storage};
  GrowingBuffer counts{{}, MemoryKind::HostVisible, "surface counts", BufferUse::Storage};
  std::optional<TimestampPool> stamps;
  std::vector<Page> pages;
  std::unordered_map<uint32_t, Slot> slots;  // packed block -> slot
  int level = -1;
  uint64_t page_limit = 0;  // largest page [B], a power of two
  std::array<size_t, 3> mirror_words{};  // chunk, block and brick words the mirror holds since the last sync

  Status uploadMirror(const BrickVolume& vol);
  Status syncMirror(const BrickVolume& vol, std::span<const BrickCoord> dirty);
  Status meshBlocks(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh, SurfaceUpdateStats& stats);
  Status countOnGpu(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh, SurfaceUpdateStats& stats);
  void countOnCpu(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh);
  Status emitOnGpu(const BrickVolume& vol, std::span<const MeshJob> placed,
                   const std::vector<std::vector<uint32_t>>& per_page, SurfaceUpdateStats& stats);
  Status emitOnCpu(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh, std::span<const MeshJob> placed,
                   std::span<const uint32_t> page_of, const std::vector<std::vector<uint32_t>>& per_page);
  Status dispatch(ComputePipeline& pipe, const BrickVolume& vol, Buffer& surface, uint32_t jobs_now, uint32_t pair,
                  const char* what, double& kernel_ms);
  // Grain of the CPU threads' pieces: a few pieces per thread, so a slow block does not hold up one.
  size_t cpuGrain(size_t n) const { return std::clamp<size_t>(n / (8u * workers->size()), 1, 32); }
  Result<Slot> allocateSlot(uint32_t vertices, uint32_t triangles, bool& grew);
  void freeSlot(uint32_t block);
  Status growPage(Page& page);
  // The CPU mesher writes its slots from the host.
  MemoryKind poolMemory() const { return mesher == MesherKind::Cpu ? MemoryKind::HostVisible : MemoryKind::DeviceLocal; }
  Status writeDraws();
  // Meshes `to_mesh`, publishes the draws and the statistics of the round begun at t0.
  Status finishRound(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh, SurfaceUpdateStats& stats,
                     Clock::time_point t0, SurfaceUpdateStats* stats_out);
  // Errors for a call that needs the volume last built or cleared: none yet, or another level.
  Status checkSameVolume(const BrickVolume& vol, const char* call) const;
  // Meshes those of `candidates` that can hold surface and frees the rest, then finishRound.
  Status meshCandidates(const BrickVolume& vol, std::span<const MeshBlock> candidates, SurfaceUpdateStats& stats,
                        Clock::time_point t0, SurfaceUpdateStats* stats_out);
  void fillStats(SurfaceUpdateStats& stats) const;
};

// ---- the volume mirror ----------------------------------------------------------------------------

Status GpuSurface::State::uploadMirror(const BrickVolume& vol) {
  // Headroom, so that the bricks a drill opens do not force a full upload every frame.
  const auto room = [](size_t words) { return uint64_t(words + words / 4 + 1024) * 4u; };
  Status s = chunks.ensure(*ctx, room(vol.chunkWords().size()));
  if (s) s = blocks.ensure(*ctx, room(vol.blockWords().size()));
  if (s) s = bricks.ensure(*ctx, room(vol.brickWords().size()));
  if (!s) return s;
  for (auto [buf, words] : {std::pair{&chunks, vol.chunkWords()}, {&blocks, vol.blockWords()}, {&bricks, vol.brickWords()}}) {
    if (words.empty()) continue;
    if (auto u = buf->buffer->upload(*ctx, std::as_bytes(words)); !u) return u;
  }
  level = vol.level();
  mirror_words = {vol.chunkWords().size(), vol.blockWords().size(), vol.brickWords().size()};
  return Ok{};
}

Status GpuSurface::State::syncMirror(const BrickVolume& vol, std::span<const BrickCoord> dirty) {
  const auto fits = [](const GrowingBuffer& b, size_t words) { return b.buffer && b.buffer->size() >= words * 4u; };
  if (!fits(chunks, vol.chunkWords().size()) || !fits(blocks, vol.blockWords().size()) ||
      !fits(bricks, vol.brickWords().size()))
    return uploadMirror(vol);

  // The chunk table is small (16^3 words at level 10): send it whole. Then, per dirty brick, its
  // index block and its dense brick; storage indices may have moved, which the entries carry.
  struct Region {
    GrowingBuffer* target;
    uint64_t word;
    uint64_t words;
    const uint32_t* src;
  };
  std::vector<Region> regions;
  regions.push_back({&chunks, 0, vol.chunkWords().size(), vol.chunkWords().data()});
  std::unordered_set<uint32_t> seen_blocks, seen_bricks;
  const uint32_t cd = vol.chunkDim();
  for (const BrickCoord& c : dirty) {
    const uint32_t chunk = vol.chunkWords()[layout::chunkCoordToIndex(c.x >> DS_CHUNK_LOG2, c.y >> DS_CHUNK_LOG2,
                                                                       c.z >> DS_CHUNK_LOG2, cd)];
    if (chunk & DS_ENTRY_UNIFORM) continue;
    const uint32_t block = chunk & DS_ENTRY_INDEX_MASK;
    if (seen_blocks.insert(block).second)
      regions.push_back({&blocks, uint64_t(block) * DS_CHUNK_BRICKS, DS_CHUNK_BRICKS,
                         vol.blockWords().data() + size_t(block) * DS_CHUNK_BRICKS});
    const uint32_t entry = vol.blockWords()[size_t(block) * DS_CHUNK_BRICKS +
                                            layout::brickCoordToOffset(c.x & (DS_CHUNK_DIM - 1), c.y & (DS_CHUNK_DIM - 1),
                                                                       c.z & (DS_CHUNK_DIM - 1))];
    if (entry & DS_ENTRY_UNIFORM) continue;
    const uint32_t brick = entry & DS_ENTRY_INDEX_MASK;
    if (seen_bricks.insert(brick).second)
      regions.push_back({&bricks, uint64_t(brick) * DS_BRICK_WORDS, DS_BRICK_WORDS,
                         vol.brickWords().data() + size_t(brick) * DS_BRICK_WORDS});
  }
  uint64_t total = 0;
  for (const Region& r : regions) total += r.words * 4u;
  if (auto s = staging.ensure(*ctx, std::bit_ceil(total)); !s) return s;
  auto* dst = static_cast<uint8_t*>(staging.buffer->mapped());
  uint64_t at = 0;
  std::vector<std::pair<GrowingBuffer*, VkBufferCopy>> copies;
  for (const Region& r : regions) {
    std::memcpy(dst + at, r.src, r.words * 4u);
    copies.push_back({r.target, VkBufferCopy{at, r.word * 4u, r.words * 4u}});
    at += r.words * 4u;
  }
  mirror_words = {vol.chunkWords().size(), vol.blockWords().size(), vol.brickWords().size()};
  return submitAndWait(*ctx, "surface mirror sync", [&](Commands& cmds) -> Status {
    cmds.use(*staging.buffer);
    for (GrowingBuffer* t : {&chunks, &blocks, &bricks}) cmds.use(*t->buffer);
    for (const auto& [target, copy] : copies)
      vkCmdCopyBuffer(cmds.cmd(), staging.buffer->handle(), target->buffer->handle(), 1, &copy);
    cmds.barrier();
    return Ok{};
  });
}

// ---- slot pages -----------------------------------------------------------------------------------

Status GpuSurface::State::growPage(Page& page) {
  const uint64_t old_bytes = page.slots->capacity();
  auto bigger = Buffer::create(*ctx, old_bytes * 2, poolMemory(), BufferUse::Geometry, "surface pool");
  if (!bigger) return bigger.error();
  if (mesher == MesherKind::Cpu) {  // host-visible both: live offsets stay valid after a memcpy
    std::memcpy(bigger->mapped(), page.pool->mapped(), old_bytes);
    page.pool.emplace(std::move(bigger).value());
    page.slots->grow();
    return Ok{};
  }
  Status s = submitAndWait(*ctx, "surface pool growth", [&](Commands& cmds) -> Status {
    cmds.use(*page.pool);
    cmds.use(*bigger);
    const VkBufferCopy copy{0, 0, old_bytes};
    vkCmdCopyBuffer(cmds.cmd(), page.pool->handle(), bigger->handle(), 1, &copy);
    cmds.barrier();
    return Ok{};
  });
  if (!s) return s;
  page.pool.emplace(std::move(bigger).value());
  page.slots->grow();
  return Ok{};
}

Result<Slot> GpuSurface::State::allocateSlot(uint32_t vertices, uint32_t triangles, bool& grew) {
  const uint64_t bytes = slotBytesFor(vertices, triangles);
  if (bytes > page_limit)
    return makeError("gpu surface", "a block needs " + formatBytes(bytes) + ", over one page");
  for (uint32_t p = 0;; ++p) {
    if (p == pages.size()) {
      Page page;
      const uint64_t first = std::min(page_limit, std::bit_ceil(std::max(options.initial_pool_bytes, kSlotUnit)));
      auto pool = Buffer::create(*ctx, first, poolMemory(), BufferUse::Geometry, "surface pool");
      if (!pool) return pool.error();
      page.pool.emplace(std::move(pool).value());
      page.slots.emplace(kSlotUnit, first);
      pages.push_back(std::move(page));
    }
    Page& page = pages[p];
    std::optional<uint64_t> at = page.slots->allocate(bytes);
    // Grow the last page before opening another, up to one binding's worth.
    while (!at && p + 1 == pages.size() && page.slots->capacity() < page_limit) {
      if (auto s = growPage(page); !s) return s.error();
      grew = true;
      at = page.slots->allocate(bytes);
    }
    if (!at) continue;
    Slot slot;
    slot.page = p;
    slot.offset = *at;
    slot.vertices = vertices;
    slot.triangles = triangles;
    if (!page.free_records.empty()) {
      slot.record = page.free_records.back();
      page.free_records.pop_back();
    } else {
      slot.record = uint32_t(page.records.size());
      page.records.push_back({});
    }
    return slot;
  }
}

void GpuSurface::State::freeSlot(uint32_t block) {
  auto it = slots.find(block);
  if (it == slots.end()) return;
  Page& page = pages[it->second.page];
  page.slots->release(it->second.offset);
  page.records[it->second.record] = SurfaceDraw{0, 0, 0, 0, 0};
  page.changed.push_back(it->second.record);
  page.free_records.push_back(it->second.record);
  slots.erase(it);
}

// Draw records are host-visible: a round copies the records it changed (freed ones are zero), or
// all of them when the buffer had to grow.
Status GpuSurface::State::writeDraws() {
  for (Page& page : pages) {
    const Buffer* before = page.draws.buffer ? &*page.draws.buffer : nullptr;
    const uint64_t old_size = before ? before->size() : 0;
    if (auto r = page.draws.ensure(*ctx, std::bit_ceil(page.records.size() * sizeof(SurfaceDraw))); !r) return r;
    auto* out = static_cast<SurfaceDraw*>(page.draws.buffer->mapped());
    if (page.draws.buffer->size() != old_size || !before) {
      if (!page.records.empty()) std::memcpy(out, page.records.data(), page.records.size() * sizeof(SurfaceDraw));
    } else {
      for (uint32_t r : page.changed) out[r] = page.records[r];
    }
    page.changed.clear();
  }
  return Ok{};
}

void GpuSurface::State::fillStats(SurfaceUpdateStats& stats) const {
  stats.blocks_live = uint32_t(slots.size());
  stats.triangles = stats.vertices = stats.pool_bytes = stats.slot_bytes = stats.used_bytes = 0;
  for (const auto& [block, slot] : slots) {
    stats.triangles += slot.triangles;
    stats.vertices += slot.vertices;
    stats.used_bytes += slotBytesFor(slot.vertices, slot.triangles);
    stats.slot_bytes += pages[slot.page].slots->slotBytesAt(slot.offset);
  }
  for (const Page& p : pages) stats.pool_bytes += p.slots->capacity();
}

// ==== 2. one meshing round =======================================================================
// Dispatches `jobs_now` jobs (the first ones in the jobs buffer), split by the group-count limit.
Status GpuSurface::State::dispatch(ComputePipeline& pipe, const BrickVolume& vol, Buffer& surface, uint32_t jobs_now,
                                   uint32_t pair, const char* what, double& kernel_ms) {
  MeshParams params{};
  params.grid = vol.gridInfo();
  params.jobCount = jobs_now;
  params.tissue = uint32_t(options.tissue);
  const uint32_t max_groups = options.max_groups_per_dispatch ? options.max_groups_per_dispatch
                                                              : ctx->limits().max_group_count[0];
  std::array<Buffer*, DS_MESH_BINDING_COUNT> bindings{&*chunks.buffer, &*blocks.buffer, &*bricks.buffer, &*jobs.buffer,
                                                      &*counts.buffer, &surface, &*cases};
  Status r = submitAndWait(*ctx, what, [&](Commands& cmds) -> Status {
    if (stamps) stamps->begin(cmds, pair);
    for (uint32_t first = 0; first < jobs_now; first += max_groups) {
      params.firstJob = first;
      const uint32_t groups = std::min(max_groups, jobs_now - first);
      if (auto d = pipe.dispatch(cmds, std::span<Buffer* const>(bindings), params, groups); !d) return d;
    }
    if (stamps) stamps->end(cmds, pair);
    return Ok{};
  });
  if (r && stamps) {
    if (auto ns = stamps->elapsedNs(pair)) kernel_ms += *ns * 1e-6;
  }
  return r;
}

// Count on the GPU: the counts buffer receives (vertices, triangles) per job.
Status GpuSurface::State::countOnGpu(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh,
                                     SurfaceUpdateStats& stats) {
  const uint32_t n = uint32_t(to_mesh.size());
  Status s = jobs.ensure(*ctx, std::bit_ceil(uint64_t(n) * sizeof(MeshJob)));
  if (s) s = counts.ensure(*ctx, std::bit_ceil(uint64_t(n) * 8u));
  if (!s) return s;
  auto* job_words = static_cast<MeshJob*>(jobs.buffer->mapped());
  for (uint32_t i = 0; i < n; ++i) job_words[i] = MeshJob{to_mesh[i].packed(), 0, 0, 0};
  // The pool is not written; any page's pool (or the counts buffer) fills the binding.
  Buffer& dummy_surface = pages.empty() ? *counts.buffer : *pages[0].pool;
  return dispatch(*count, vol, dummy_surface, n, 0, "surface count", stats.count_kernel_ms);
}

// Count on the CPU threads: cpu_counts receives each block's counts.
void GpuSurface::State::countOnCpu(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh) {
  cpu_counts.resize(to_mesh.size());
  workers->run(to_mesh.size(), cpuGrain(to_mesh.size()), [&](size_t begin, size_t end, unsigned worker) {
    BlockMesher& m = block_meshers[worker];
    for (size_t i = begin; i < end; ++i) cpu_counts[i] = m.count(vol, to_mesh[i]);
  });
}

// Emit on the GPU, one page at a time (each page is its own binding), listing only that page's jobs.
Status GpuSurface::State::emitOnGpu(const BrickVolume& vol, std::span<const MeshJob> placed,
                                    const std::vector<std::vector<uint32_t>>& per_page, SurfaceUpdateStats& stats) {
  auto* job_words = static_cast<MeshJob*>(jobs.buffer->mapped());
  for (uint32_t p = 0; p < per_page.size(); ++p) {
    if (per_page[p].empty()) continue;
    const uint32_t m = uint32_t(per_page[p].size());
    for (uint32_t k = 0; k < m; ++k) job_words[k] = placed[per_page[p][k]];
    if (auto e = dispatch(*emit, vol, *pages[p].pool, m, 1, "surface emit", stats.emit_kernel_ms); !e) return e;
  }
  return Ok{};
}

// Emit on the CPU threads, straight into the host-visible slots. Each block owns its slot, so the
// threads never write the same bytes.
Status GpuSurface::State::emitOnCpu(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh,
                                    std::span<const MeshJob> placed, std::span<const uint32_t> page_of,
                                    const std::vector<std::vector<uint32_t>>& per_page) {
  // Draws are recorded and waited for in the same thread (submitAndWait), so nothing should be in
  // flight; if a submission still is, it may read these pages.
  if (!ctx->core().pending.empty()) DS_TRY_STATUS(ctx->waitIdle());
  std::vector<uint32_t> order;
  for (const auto& jobs_of_page : per_page) order.insert(order.end(), jobs_of_page.begin(), jobs_of_page.end());
  std::atomic<bool> mismatch{false};
  workers->run(order.size(), cpuGrain(order.size()), [&](size_t begin, size_t end, unsigned worker) {
    BlockMesher& m = block_meshers[worker];
    for (size_t k = begin; k < end; ++k) {
      const uint32_t i = order[k];
      auto* words = static_cast<uint32_t*>(pages[page_of[i]].pool->mapped());
      const MeshJob& job = placed[i];
      const BlockCounts wrote = m.emit(vol, to_mesh[i], reinterpret_cast<layout::MeshVertex*>(words + job.slotWord),
                                       words + job.indexWord);
      if (wrote.vertices != cpu_counts[i].vertices || wrote.triangles != cpu_counts[i].triangles)
        mismatch.store(true, std::memory_order_relaxed);
    }
  });
  // The two passes read the same voxels, so this is a bug, not a condition of the environment.
  if (mismatch.load()) return makeError("gpu surface", "the CPU mesher emitted other counts than it counted");
  return Ok{};
}

Status GpuSurface::State::meshBlocks(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh,
                                     SurfaceUpdateStats& stats) {
  stats.blocks_meshed = uint32_t(to_mesh.size());
  if (to_mesh.empty()) return Ok{};
  const uint32_t n = uint32_t(to_mesh.size());

  // Count: vertices and triangles per block.
  auto t0 = Clock::now();
  const uint32_t* gpu_counts = nullptr;
  if (mesher == MesherKind::Gpu) {
    DS_TRY_STATUS(countOnGpu(vol, to_mesh, stats));
    gpu_counts = static_cast<const uint32_t*>(counts.buffer->mapped());
  } else {
    countOnCpu(vol, to_mesh);
  }
  const auto countOf = [&](uint32_t i) -> BlockCounts {
    return gpu_counts ? BlockCounts{gpu_counts[2 * i], gpu_counts[2 * i + 1]} : cpu_counts[i];
  };
  stats.count_ms = msSince(t0);

  // Allocate: a block keeps its slot while it fits and is not four times too large.
  t0 = Clock::now();
  std::vector<MeshJob> placed(n);
  std::vector<uint32_t> page_of(n, 0);
  std::vector<std::vector<uint32_t>> per_page;  // job indices by page
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t block = to_mesh[i].packed();
    const auto [v, t] = countOf(i);
    if (t == 0) {
      freeSlot(block);
      continue;
    }
    auto it = slots.find(block);
    const uint64_t need = slotBytesFor(v, t);
    if (it != slots.end()) {
      const uint64_t have = pages[it->second.page].slots->slotBytesAt(it->second.offset);
      if (have < need || have > 4 * std::max(need, kSlotUnit)) {
        freeSlot(block);
        it = slots.end();
      }
    }
    if (it == slots.end()) {
      auto slot = allocateSlot(v, t, stats.pool_grew);
      if (!slot) return slot.error();
      it = slots.emplace(block, *slot).first;
    }
    Slot& slot = it->second;
    slot.vertices = v;
    slot.triangles = t;
    const uint64_t index_byte = slot.offset + uint64_t(v) * sizeof(layout::MeshVertex);
    placed[i] = MeshJob{block, uint32_t(slot.offset / 4u), v, uint32_t(index_byte / 4u)};
    page_of[i] = slot.page;
    pages[slot.page].records[slot.record] =
        SurfaceDraw{3u * t, 1u, uint32_t(index_byte / 4u), int32_t(slot.offset / sizeof(layout::MeshVertex)), block};
    pages[slot.page].changed.push_back(slot.record);
    if (per_page.size() <= slot.page) per_page.resize(slot.page + 1);
    per_page[slot.page].push_back(i);
  }

  // Emit into the slots.
  if (mesher == MesherKind::Gpu)
    DS_TRY_STATUS(emitOnGpu(vol, placed, per_page, stats));
  else
    DS_TRY_STATUS(emitOnCpu(vol, to_mesh, placed, page_of, per_page));
  stats.emit_ms = msSince(t0);
  return Ok{};
}

Status GpuSurface::State::finishRound(const BrickVolume& vol, const std::vector<MeshBlock>& to_mesh,
                                      SurfaceUpdateStats& stats, Clock::time_point t0, SurfaceUpdateStats* stats_out) {
  if (auto m = meshBlocks(vol, to_mesh, stats); !m) return m;
  if (auto w = writeDraws(); !w) return w;
  stats.total_ms = msSince(t0);
  fillStats(stats);
  if (stats_out) *stats_out = stats;
  return Ok{};
}

Status GpuSurface::State::meshCandidates(const BrickVolume& vol, std::span<const MeshBlock> candidates,
                                         SurfaceUpdateStats& stats, Clock::time_point t0, SurfaceUpdateStats* stats_out) {
  const std::vector<bool> active = meshBlocksActive(vol, options.tissue, candidates);
  std::vector<MeshBlock> to_mesh;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (active[i])
      to_mesh.push_back(candidates[i]);
    else
      freeSlot(candidates[i].packed());
  }
  return finishRound(vol, to_mesh, stats, t0, stats_out);
}

// ==== 3. build, update, read-back ================================================================
Result<GpuSurface> GpuSurface::create(Context& ctx, const GpuSurfaceOptions& options) {
  auto state = std::make_unique<State>();
  state->ctx = &ctx;
  state->options = options;
  const std::optional<NormalMode> mode = normalModeFromNeighbours(options.normal_neighbours);
  if (!mode)
    return makeError("gpu surface", std::string("normal_neighbours must be ") + kNormalModeChoices + ", not " +
                                        std::to_string(options.normal_neighbours));
  state->side = normalBoxSide(*mode);
  state->mesher = resolveMesher(options.mesher, ctx.device().type);
  const DeviceLimits& lim = ctx.limits();
  uint64_t limit = lim.max_storage_buffer_range;
  if (lim.max_memory_allocation_size) limit = std::min(limit, lim.max_memory_allocation_size);
  if (options.max_page_bytes) limit = std::min(limit, std::max(options.max_page_bytes, kSlotUnit));
  state->page_limit = std::bit_floor(limit);

  if (state->mesher == MesherKind::Cpu) {
    // Threads that live as long as the surface: a frame's re-mesh starts none.
    state->workers = options.workers ? options.workers : std::make_shared<WorkerPool>(options.cpu_threads);
    for (unsigned i = 0; i < state->workers->size(); ++i) state->block_meshers.emplace_back(options.tissue, state->side);
    return GpuSurface(std::move(state));
  }

  // What surface_mesh.comp.glsl needs: its shared arrays and subgroup scans.
  if (!lim.subgroup_arithmetic_in_compute)
    return makeError("gpu surface", "this device has no subgroup arithmetic in compute shaders, which the mesher's scans use");
  if (lim.max_compute_shared_memory < kKernelSharedBytes)
    return makeError("gpu surface", "the mesher needs " + formatBytes(kKernelSharedBytes) +
                                        " of shared memory per workgroup; this device has " +
                                        formatBytes(lim.max_compute_shared_memory));

  const std::span<const uint32_t> spirv{surface_mesh_comp_spv, surface_mesh_comp_spv_words};
  auto count = ComputePipeline::create(ctx, PipelineDesc{"surface_count", spirv, DS_MESH_BINDING_COUNT, {{0, 0}}});
  if (!count) return count.error();
  state->count.emplace(std::move(count).value());
  auto emit = ComputePipeline::create(ctx, PipelineDesc{"surface_emit", spirv, DS_MESH_BINDING_COUNT, {{0, 1}, {1, state->side}}});
  if (!emit) return emit.error();
  state->emit.emplace(std::move(emit).value());

  const std::vector<uint32_t> table = packedMeshCaseTable();
  auto cases = Buffer::create(ctx, table.size() * 4u, MemoryKind::DeviceLocal, BufferUse::Storage, "surface case table");
  if (!cases) return cases.error();
  if (auto s = cases->upload(ctx, std::as_bytes(std::span<const uint32_t>(table))); !s) return s.error();
  state->cases.emplace(std::move(cases).value());
  if (TimestampPool::supported(ctx)) {
    auto stamps = TimestampPool::create(ctx, 2, "surface timestamps");
    if (stamps) state->stamps.emplace(std::move(stamps).value());
  }
  return GpuSurface(std::move(state));
}

Status GpuSurface::build(const BrickVolume& volume, SurfaceUpdateStats* stats_out) {
  State& s = *state_;
  SurfaceUpdateStats stats;
  stats.timestamps = s.stamps.has_value();
  const auto t0 = Clock::now();
  if (auto c = clear(volume); !c) return c;
  if (s.mesher == MesherKind::Gpu) stats.upload_ms = msSince(t0);
  return s.finishRound(volume, activeMeshBlocks(volume, s.options.tissue), stats, t0, stats_out);
}

Status GpuSurface::State::checkSameVolume(const BrickVolume& vol, const char* call) const {
  if (level < 0) return makeError("gpu surface", std::string(call) + " before build");
  if (vol.level() != level)
    return makeError("gpu surface", std::string(call) + " of a level-" + std::to_string(vol.level()) +
                                        " volume on a level-" + std::to_string(level) + " surface; build again");
  return Ok{};
}

Status GpuSurface::update(const BrickVolume& volume, std::span<const BrickCoord> dirty, SurfaceUpdateStats* stats_out) {
  State& s = *state_;
  if (auto same = s.checkSameVolume(volume, "update"); !same) return same;
  SurfaceUpdateStats stats;
  stats.timestamps = s.stamps.has_value();
  stats.dirty_bricks = uint32_t(dirty.size());
  const auto t0 = Clock::now();
  if (dirty.empty()) {
    s.fillStats(stats);
    if (stats_out) *stats_out = stats;
    return Ok{};
  }
  if (s.mesher == MesherKind::Gpu) {
    if (auto u = s.syncMirror(volume, dirty); !u) return u;
    stats.upload_ms = msSince(t0);
  }
  return s.meshCandidates(volume, blocksReadingBricks(volume, dirty), stats, t0, stats_out);
}

Status GpuSurface::clear(const BrickVolume& volume) {
  State& s = *state_;
  if (volume.level() > 12)
    return makeError("gpu surface", "level " + std::to_string(volume.level()) + " is over 12, the most a mesh block can address");
  s.slots.clear();
  s.pages.clear();
  if (s.mesher == MesherKind::Gpu) return s.uploadMirror(volume);
  s.level = volume.level();  // the CPU mesher reads the host's bricks: no mirror
  return Ok{};
}

Status GpuSurface::meshBlocks(const BrickVolume& volume, std::span<const MeshBlock> blocks, SurfaceUpdateStats* stats_out) {
  State& s = *state_;
  if (auto same = s.checkSameVolume(volume, "meshBlocks"); !same) return same;
  SurfaceUpdateStats stats;
  stats.timestamps = s.stamps.has_value();
  return s.meshCandidates(volume, blocks, stats, Clock::now(), stats_out);
}

MesherKind GpuSurface::mesher() const { return state_->mesher; }
uint32_t GpuSurface::pageCount() const { return uint32_t(state_->pages.size()); }
Buffer& GpuSurface::pool(uint32_t page) { return *state_->pages.at(page).pool; }
Buffer& GpuSurface::draws(uint32_t page) { return *state_->pages.at(page).draws.buffer; }
uint32_t GpuSurface::drawCount(uint32_t page) const { return uint32_t(state_->pages.at(page).records.size()); }
uint64_t GpuSurface::liveBlocks() const { return state_->slots.size(); }

Result<BrickVolume> GpuSurface::downloadVolume() {
  State& s = *state_;
  if (s.mesher == MesherKind::Cpu)
    return makeError("surface mirror", "the CPU mesher reads the host's bricks and keeps no copy on the device");
  if (s.level < 0) return makeError("surface mirror", "nothing uploaded yet");
  std::array<std::vector<uint32_t>, 3> words;
  const std::array<GrowingBuffer*, 3> buffers{&s.chunks, &s.blocks, &s.bricks};
  for (size_t i = 0; i < 3; ++i) {
    words[i].resize(s.mirror_words[i]);
    if (words[i].empty()) continue;
    if (auto d = buffers[i]->buffer->download(*s.ctx, std::as_writable_bytes(std::span<uint32_t>(words[i]))); !d)
      return d.error();
  }
  // Walk the index as the kernels do, so storage nothing references is ignored.
  BrickVolume out(s.level);
  const uint32_t cd = out.chunkDim(), span = std::min<uint32_t>(out.brickDim(), DS_CHUNK_DIM);
  const auto bad = [](const char* what) { return makeError("surface mirror", std::string(what) + " out of range"); };
  for (uint32_t cz = 0; cz < cd; ++cz)
    for (uint32_t cy = 0; cy < cd; ++cy)
      for (uint32_t cx = 0; cx < cd; ++cx) {
        const uint32_t centry = words[0][layout::chunkCoordToIndex(cx, cy, cz, cd)];
        for (uint32_t bz = 0; bz < span; ++bz)
          for (uint32_t by = 0; by < span; ++by)
            for (uint32_t bx = 0; bx < span; ++bx) {
              const BrickCoord c{cx * DS_CHUNK_DIM + bx, cy * DS_CHUNK_DIM + by, cz * DS_CHUNK_DIM + bz};
              if (centry & DS_ENTRY_UNIFORM) {
                out.setBrickUniform(c, Voxel(centry & 0xffu));
                continue;
              }
              const size_t e = size_t(centry & DS_ENTRY_INDEX_MASK) * DS_CHUNK_BRICKS + layout::brickCoordToOffset(bx, by, bz);
              if (e >= words[1].size()) return bad("an index block");
              const uint32_t bentry = words[1][e];
              if (bentry & DS_ENTRY_UNIFORM) {
                out.setBrickUniform(c, Voxel(bentry & 0xffu));
                continue;
              }
              const size_t w = size_t(bentry & DS_ENTRY_INDEX_MASK) * DS_BRICK_WORDS;
              if (w + DS_BRICK_WORDS > words[2].size()) return bad("a brick");
              out.setBrick(c, reinterpret_cast<const Voxel*>(words[2].data() + w));
            }
      }
  return out;
}

Result<std::vector<BlockMesh>> GpuSurface::downloadBlocks() {
  State& s = *state_;
  std::vector<std::vector<uint32_t>> words(s.pages.size());
  for (size_t p = 0; p < s.pages.size(); ++p) {
    words[p].resize(s.pages[p].pool->size() / 4u);
    if (auto d = s.pages[p].pool->download(*s.ctx, std::as_writable_bytes(std::span<uint32_t>(words[p]))); !d)
      return d.error();
  }
  std::vector<uint32_t> order;
  order.reserve(s.slots.size());
  for (const auto& [block, slot] : s.slots) order.push_back(block);
  std::sort(order.begin(), order.end());
  std::vector<BlockMesh> out;
  out.reserve(order.size());
  for (uint32_t block : order) {
    const Slot& slot = s.slots.at(block);
    BlockMesh m;
    m.block = MeshBlock::unpack(block);
    const uint32_t* w = words[slot.page].data() + slot.offset / 4u;
    m.vertices.resize(slot.vertices);
    std::memcpy(m.vertices.data(), w, size_t(slot.vertices) * sizeof(layout::MeshVertex));
    m.indices.assign(w + size_t(slot.vertices) * DS_MESH_VERTEX_WORDS,
                     w + size_t(slot.vertices) * DS_MESH_VERTEX_WORDS + size_t(slot.triangles) * 3u);
    // The welder indexes vertices by these; a device that wrote garbage must not take the host down.
    for (uint32_t index : m.indices)
      if (index >= slot.vertices)
        return makeError("GPU surface", "block (" + std::to_string(m.block.x) + ", " + std::to_string(m.block.y) +
                                            ", " + std::to_string(m.block.z) + ") names vertex " +
                                            std::to_string(index) + " of " + std::to_string(slot.vertices) +
                                            ": the device wrote a corrupt slot");
    out.push_back(std::move(m));
  }
  return out;
}

GpuSurface::GpuSurface(std::unique_ptr<State> state) : state_(std::move(state)) {}
GpuSurface::GpuSurface(GpuSurface&&) noexcept = default;
GpuSurface& GpuSurface::operator=(GpuSurface&&) noexcept = default;
GpuSurface::~GpuSurface() = default;

}  // namespace dentsim::gpu
