// GPU voxelizer host: bands of chunk rows, the raster/scan/sort/donor/paint/chunk passes, and the CPU mirror.
//
// Per band (a slab of chunk rows, the whole grid when it fits):
//   submission 1: count hits per ray (raster MODE 0), then the three scan phases -> offsets
//   then, each in submissions of bounded work: store hits (raster MODE 1), sort each ray and find
//   donors; paint bricks (8192 workgroups a submission); pack chunks
// The raster passes take a triangle a tile of rays at a time and the paint pass a column a segment
// of bricks at a time, to stay within lavapipe's loop budget per invocation (voxelize_layout.h).
// The hit total read back between the two sizes the hit buffer exactly. A brick pool that overflows
// is grown and the band painted again; a band whose rays, hits or blocks exceed one binding is split.
#include "gpu/gpu_voxelizer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <optional>
#include <vector>

#include "dentsim_compute_spirv_spirv.h"
#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "volume/voxelize_layout.h"

namespace dentsim::gpu {
namespace {

using Clock = std::chrono::steady_clock;
using layout::VoxelizeParams;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

constexpr uint64_t kMaxBandRays = uint64_t{1} << 24;  // 64 MiB of counts and as much of offsets
// Paint workgroups per submission: a few seconds of lavapipe on a loaded 2-core machine at most.
constexpr uint64_t kPaintGroupsPerSubmission = 8192;

struct Pipelines {
  std::optional<ComputePipeline> count, scatter, scan_reduce, scan_blocks, scan_apply, sort, donor, paint, chunks;
};

Result<Pipelines> makePipelines(Context& ctx, uint32_t subsamples) {
  Pipelines p;
  const uint32_t n = DS_VOX_BINDING_COUNT;
  auto make = [&](std::optional<ComputePipeline>& slot, const char* name, const uint32_t* words, size_t count,
                  std::vector<SpecValue> spec) -> Status {
    auto pipe = ComputePipeline::create(ctx, PipelineDesc{name, {words, count}, n, std::move(spec)});
    if (!pipe) return pipe.error();
    slot.emplace(std::move(pipe).value());
    return Ok{};
  };
  Status s = make(p.count, "voxelize_count", voxelize_raster_comp_spv, voxelize_raster_comp_spv_words, {{0, 0}});
  if (s) s = make(p.scatter, "voxelize_scatter", voxelize_raster_comp_spv, voxelize_raster_comp_spv_words, {{0, 1}});
  if (s) s = make(p.scan_reduce, "voxelize_scan_reduce", voxelize_scan_comp_spv, voxelize_scan_comp_spv_words, {{0, 0}});
  if (s) s = make(p.scan_blocks, "voxelize_scan_blocks", voxelize_scan_comp_spv, voxelize_scan_comp_spv_words, {{0, 1}});
  if (s) s = make(p.scan_apply, "voxelize_scan_apply", voxelize_scan_comp_spv, voxelize_scan_comp_spv_words, {{0, 2}});
  if (s) s = make(p.sort, "voxelize_sort", voxelize_sort_comp_spv, voxelize_sort_comp_spv_words, {});
  if (s) s = make(p.donor, "voxelize_donor", voxelize_donor_comp_spv, voxelize_donor_comp_spv_words, {});
  if (s) s = make(p.paint, "voxelize_paint", voxelize_paint_comp_spv, voxelize_paint_comp_spv_words, {{1, subsamples}});
  if (s) s = make(p.chunks, "voxelize_chunks", voxelize_chunks_comp_spv, voxelize_chunks_comp_spv_words, {});
  if (!s) return s.error();
  return p;
}

// Runs items [first, first + items) of a pass: one invocation per item, or with `per_group` one
// workgroup per item.
Status runPass(Commands& cmds, ComputePipeline& pipe, std::span<Buffer* const> bindings, VoxelizeParams params,
               uint64_t items, bool per_group, uint64_t first = 0) {
  if (items == 0) return Ok{};
  const uint64_t local = pipe.localSize()[0];
  params.itemLimit = uint32_t(first + items);
  for (const DispatchRange& part : pipe.split(per_group ? items * local : items)) {
    params.firstItem = uint32_t(first + (per_group ? part.first / local : part.first));
    if (auto s = pipe.dispatch(cmds, bindings, params, part.groups); !s) return s;
  }
  return Ok{};
}

void fillZero(Commands& cmds, Buffer& b, uint64_t bytes) {
  vkCmdFillBuffer(cmds.cmd(), b.handle(), 0, std::max<uint64_t>(4, (bytes + 3) / 4 * 4), 0);
  cmds.use(b);
}

template <class T>
Status downloadWords(Context& ctx, Buffer& b, std::vector<T>& out, size_t count) {
  out.resize(count);
  if (count == 0) return Ok{};
  return b.download(ctx, std::as_writable_bytes(std::span<T>(out)));
}

// Raster items: each triangle's footprint cut into tiles of DS_VOX_RASTER_TILE rays a side, as
// (triangle, tile x | tile y << 16), ordered by tile row so a band takes a contiguous run. The span
// is the kernel's own (voxRaySpan), so an item never misses a ray the kernel would test.
struct RasterItems {
  std::vector<uint32_t> words;         // 2 per item
  std::vector<uint32_t> first_of_row;  // item index where each tile row starts, one past the end last
};

// A triangle's tiles: first and one-past-last tile column and row (empty when it misses the footprint).
std::array<uint32_t, 4> triangleTiles(const RaySetup& setup, size_t t) {
  const uint32_t tile = DS_VOX_RASTER_TILE;
  const float* c = &setup.corners[t * 9];
  uint32_t x0, x1, y0, y1;
  layout::voxRaySpan(std::min({c[0], c[3], c[6]}), std::max({c[0], c[3], c[6]}), setup.ray_x1, x0, x1);
  layout::voxRaySpan(std::min({c[1], c[4], c[7]}), std::max({c[1], c[4], c[7]}), setup.ray_y1, y0, y1);
  x0 = std::max(x0, setup.ray_x0);
  y0 = std::max(y0, setup.ray_y0);
  if (x0 >= x1 || y0 >= y1) return {0, 0, 0, 0};
  return {x0 / tile, (x1 - 1) / tile + 1, y0 / tile, (y1 - 1) / tile + 1};
}

// The items, or an error before anything is allocated when they would not fit one binding (a
// hostile mesh of huge triangles at a fine level: each one's tiles are counted first).
Result<RasterItems> rasterItems(const RaySetup& setup, uint64_t max_binding, const std::string& where) {
  uint64_t total = 0;
  for (size_t t = 0; t < setup.triangle_layer.size(); ++t) {
    const auto [tx0, tx1, ty0, ty1] = triangleTiles(setup, t);
    total += uint64_t(tx1 - tx0) * (ty1 - ty0);
  }
  if (total * 8 > max_binding)
    return makeError(where, std::to_string(total) + " raster tiles exceed one storage binding (" +
                                formatBytes(max_binding) + "); decimate the meshes or choose a lower level");
  const uint32_t tile = DS_VOX_RASTER_TILE;
  std::vector<std::vector<uint32_t>> by_row((setup.ray_y1 + tile - 1) / tile);
  for (size_t t = 0; t < setup.triangle_layer.size(); ++t) {
    const auto [tx0, tx1, ty0, ty1] = triangleTiles(setup, t);
    for (uint32_t ty = ty0; ty < ty1; ++ty)
      for (uint32_t tx = tx0; tx < tx1; ++tx) {
        by_row[ty].push_back(uint32_t(t));
        by_row[ty].push_back(tx | (ty << 16));
      }
  }
  RasterItems items;
  for (const auto& row : by_row) {
    items.first_of_row.push_back(uint32_t(items.words.size() / 2));
    items.words.insert(items.words.end(), row.begin(), row.end());
  }
  items.first_of_row.push_back(uint32_t(items.words.size() / 2));
  return items;
}

}  // namespace

Result<BrickVolume> voxelizeGpu(Context& ctx, const RaySetup& setup, const VoxelizeOptions& options,
                                VoxelizeTiming* timing, Interrupter& interrupter) {
  const auto t_start = Clock::now();
  const std::string where = "gpu voxelize";
  VoxelizeTiming local_timing;
  VoxelizeTiming& tm = timing ? *timing : local_timing;
  tm = {};
  if (setup.level < DS_MIN_LEVEL || setup.level > DS_MAX_LEVEL || setup.subsamples < 1 ||
      setup.subsamples > int(DS_VOX_MAX_SUBSAMPLES) || setup.layer_material.empty() ||
      setup.layer_material.size() > DS_VOX_MAX_LAYERS || setup.corners.size() != setup.triangle_layer.size() * 9)
    return makeError(where, "invalid ray set-up");
  if (options.hole_radius < 0 || options.hole_radius > 64) return makeError(where, "hole radius must be 0..64");
  interrupter.start("voxelize (GPU)");

  auto pipes = makePipelines(ctx, uint32_t(setup.subsamples));
  if (!pipes) return makeError(where, pipes.message());
  const uint64_t max_binding = ctx.limits().max_storage_buffer_range;

  // Triangles go up once for every band.
  const auto t_upload = Clock::now();
  const uint64_t triangles = setup.triangle_layer.size();
  GrowingBuffer corners{{}, MemoryKind::DeviceLocal, "voxelize corners"};
  GrowingBuffer tri_layer{{}, MemoryKind::DeviceLocal, "voxelize triangle layers"};
  if (triangles * 36 > max_binding)
    return makeError(where, std::to_string(triangles) + " triangles exceed one storage binding (" +
                                formatBytes(max_binding) + "); decimate the meshes");
  if (auto s = corners.ensure(ctx, triangles * 36); !s) return makeError(where, s.message());
  if (auto s = tri_layer.ensure(ctx, triangles * 4); !s) return makeError(where, s.message());
  if (triangles) {
    if (auto s = corners.buffer->upload(ctx, std::as_bytes(std::span(setup.corners))); !s) return s.error();
    if (auto s = tri_layer.buffer->upload(ctx, std::as_bytes(std::span(setup.triangle_layer))); !s) return s.error();
  }
  auto raster_or = rasterItems(setup, max_binding, where);
  if (!raster_or) return raster_or.error();
  const RasterItems raster = std::move(raster_or).value();
  GrowingBuffer raster_items{{}, MemoryKind::DeviceLocal, "voxelize raster items"};
  if (auto s = raster_items.ensure(ctx, raster.words.size() * 4); !s) return makeError(where, s.message());
  if (!raster.words.empty())
    if (auto s = raster_items.buffer->upload(ctx, std::as_bytes(std::span(raster.words))); !s) return s.error();
  tm.upload_ms = msSince(t_upload);

  GrowingBuffer counts{{}, MemoryKind::DeviceLocal, "voxelize counts"};
  GrowingBuffer offsets{{}, MemoryKind::DeviceLocal, "voxelize offsets"};
  GrowingBuffer hits{{}, MemoryKind::DeviceLocal, "voxelize hits"};
  GrowingBuffer leaky{{}, MemoryKind::DeviceLocal, "voxelize leaky masks"};
  GrowingBuffer donors{{}, MemoryKind::DeviceLocal, "voxelize donors"};
  GrowingBuffer blocks{{}, MemoryKind::DeviceLocal, "voxelize band blocks"};
  GrowingBuffer bricks{{}, MemoryKind::DeviceLocal, "voxelize brick pool"};
  GrowingBuffer counters{{}, MemoryKind::HostVisible, "voxelize counters"};
  GrowingBuffer chunk_out{{}, MemoryKind::DeviceLocal, "voxelize band chunks"};
  GrowingBuffer packed{{}, MemoryKind::DeviceLocal, "voxelize packed blocks"};
  GrowingBuffer scan_sums{{}, MemoryKind::DeviceLocal, "voxelize scan sums"};
  if (auto s = counters.ensure(ctx, 16); !s) return makeError(where, s.message());

  const uint32_t level = uint32_t(setup.level);
  const uint32_t S = uint32_t(setup.subsamples);
  const uint32_t brick_dim = 1u << (level - DS_BRICK_LOG2);
  const uint32_t chunk_dim = std::max(1u, brick_dim >> DS_CHUNK_LOG2);
  const uint32_t rows_per_chunk = std::min(brick_dim, DS_CHUNK_DIM);
  const uint32_t radius = uint32_t(options.hole_radius);

  std::vector<uint32_t> chunk_table(size_t(chunk_dim) * chunk_dim * chunk_dim, DS_ENTRY_UNIFORM);
  std::vector<uint32_t> block_words, brick_words;
  std::vector<uint32_t> band_chunks, band_blocks, band_bricks;

  std::string stamp_note;
  const bool timed = TimestampPool::supported(ctx, &stamp_note);
  std::optional<TimestampPool> stamps;
  if (timed) {
    auto pool = TimestampPool::create(ctx, 4, "voxelize timestamps");
    if (!pool) return makeError(where, pool.message());
    stamps.emplace(std::move(pool).value());
  }
  // Pairs: 0 count and scan, 1 store, sort and donors, 2 paint, 3 chunks.
  auto addKernelTime = [&](uint32_t pair, double* part) {
    if (!stamps) return;
    if (auto ns = stamps->elapsedNs(pair); ns) {
      tm.kernels_ms += *ns * 1e-6;
      *part += *ns * 1e-6;
    }
  };

  // Chunk rows per band; halved when a band does not fit.
  uint32_t band_rows = options.max_band_chunk_rows ? std::min(options.max_band_chunk_rows, chunk_dim) : chunk_dim;
  uint32_t cy = 0;
  while (cy < chunk_dim) {
    if (!interrupter.progress(double(cy) / chunk_dim)) return makeError(where, "cancelled");
    const uint32_t rows = std::min(band_rows, chunk_dim - cy);
    auto splitBand = [&](const std::string& why) -> Status {
      if (rows == 1) return makeError(where, "one chunk row is too large for the device: " + why);
      band_rows = rows / 2;
      return Ok{};
    };

    VoxelizeParams p{};
    p.level = level;
    p.subsamples = S;
    p.brickRow0 = cy * rows_per_chunk;
    p.brickRows = std::min(rows * rows_per_chunk, brick_dim - p.brickRow0);
    p.chunkRow0 = cy;
    p.chunkRows = rows;
    p.holeRadius = radius;
    p.layerMaterials = layerMaterialWord(setup);
    // The band's rays: its painted rows plus a halo of the hole radius, inside the footprint.
    const int64_t ray_row0 = int64_t(p.brickRow0) * DS_BRICK_DIM * S - radius;
    const int64_t ray_row1 = int64_t(p.brickRow0 + p.brickRows) * DS_BRICK_DIM * S + radius;
    p.rayX0 = setup.ray_x0;
    p.rayX1 = setup.ray_x1;
    p.rayY0 = uint32_t(std::clamp<int64_t>(ray_row0, setup.ray_y0, setup.ray_y1));
    p.rayY1 = uint32_t(std::clamp<int64_t>(ray_row1, p.rayY0, setup.ray_y1));
    const uint64_t rays = uint64_t(p.rayX1 - p.rayX0) * (p.rayY1 - p.rayY0);
    const uint64_t band_chunk_count = uint64_t(chunk_dim) * rows * chunk_dim;
    const uint64_t block_bytes = band_chunk_count * DS_CHUNK_BRICKS * 4;
    if (rays > kMaxBandRays || (rays + 1) * 4 > max_binding || block_bytes > max_binding) {
      if (auto s = splitBand("its rays or index blocks exceed one binding"); !s) return s.error();
      continue;
    }
    p.scanCount = uint32_t(rays);
    // The raster items whose tile rows meet the band's rays.
    const uint32_t tile = DS_VOX_RASTER_TILE;
    const size_t tile_rows = raster.first_of_row.size() - 1;
    const uint32_t item0 = raster.first_of_row[std::min<size_t>(p.rayY0 / tile, tile_rows)];
    const uint32_t item1 = raster.first_of_row[std::min<size_t>((p.rayY1 + tile - 1) / tile, tile_rows)];

    const uint64_t scan_blocks = (rays + DS_VOX_SCAN_BLOCK - 1) / DS_VOX_SCAN_BLOCK;
    for (auto [buf, bytes] : {std::pair{&counts, rays * 4}, {&offsets, (rays + 1) * 4}, {&leaky, rays * 4},
                              {&donors, rays * 4}, {&blocks, block_bytes}, {&chunk_out, band_chunk_count * 4},
                              {&packed, block_bytes}, {&scan_sums, scan_blocks * 4}}) {
      if (auto s = buf->ensure(ctx, bytes); !s) return makeError(where, s.message());
    }
    // The hit buffer must exist to be bound in the first submission; it is sized after it.
    if (auto s = hits.ensure(ctx, 16); !s) return makeError(where, s.message());
    if (auto s = bricks.ensure(ctx, DS_BRICK_WORDS * 4 * 64); !s) return makeError(where, s.message());

    auto bindings = [&]() {
      std::array<Buffer*, DS_VOX_BINDING_COUNT> b{};
      b[DS_VOX_BINDING_CORNERS] = &*corners.buffer;
      b[DS_VOX_BINDING_TRILAYER] = &*tri_layer.buffer;
      b[DS_VOX_BINDING_COUNTS] = &*counts.buffer;
      b[DS_VOX_BINDING_OFFSETS] = &*offsets.buffer;
      b[DS_VOX_BINDING_HITS] = &*hits.buffer;
      b[DS_VOX_BINDING_RAYINFO] = &*leaky.buffer;
      b[DS_VOX_BINDING_BLOCKS] = &*blocks.buffer;
      b[DS_VOX_BINDING_BRICKS] = &*bricks.buffer;
      b[DS_VOX_BINDING_COUNTERS] = &*counters.buffer;
      b[DS_VOX_BINDING_CHUNKS] = &*chunk_out.buffer;
      b[DS_VOX_BINDING_PACKED] = &*packed.buffer;
      b[DS_VOX_BINDING_SCANSUMS] = &*scan_sums.buffer;
      b[DS_VOX_BINDING_DONORS] = &*donors.buffer;
      b[DS_VOX_BINDING_RASTER] = &*raster_items.buffer;
      return b;
    };

    // Submission 1: count and scan.
    auto* counter_words = static_cast<uint32_t*>(counters.buffer->mapped());
    std::fill_n(counter_words, 4, 0u);
    auto first = submitAndWait(ctx, "voxelize count", [&](Commands& cmds) -> Status {
      auto b = bindings();
      if (stamps) stamps->begin(cmds, 0);
      fillZero(cmds, *counts.buffer, rays * 4);
      cmds.barrier();
      if (rays > 0) {
        if (auto s = runPass(cmds, *pipes->count, b, p, item1 - item0, false, item0); !s) return s;
        if (auto s = runPass(cmds, *pipes->scan_reduce, b, p, scan_blocks, true); !s) return s;
        if (auto s = runPass(cmds, *pipes->scan_blocks, b, p, 1, true); !s) return s;
        if (auto s = runPass(cmds, *pipes->scan_apply, b, p, scan_blocks, true); !s) return s;
      }
      if (stamps) stamps->end(cmds, 0);
      return Ok{};
    });
    if (!first) return makeError(where, first.message());
    addKernelTime(0, &tm.count_scan_ms);
    const uint64_t band_hits = counter_words[2];
    if (band_hits * 4 > max_binding) {
      if (auto s = splitBand(std::to_string(band_hits) + " hits exceed one binding"); !s) return s.error();
      continue;
    }
    if (auto s = hits.ensure(ctx, band_hits * 4); !s) return makeError(where, s.message());
    // Dense bricks sit where surfaces cross: a few per brick column that a surface sheet crosses.
    const uint64_t max_bricks = max_binding / (DS_BRICK_WORDS * 4);
    uint64_t capacity = std::min<uint64_t>(max_bricks, 1024 + 4 * band_hits / (uint64_t(S) * S * 64) + band_hits / 64);
    if (options.initial_brick_capacity) capacity = options.initial_brick_capacity;
    if (auto s = bricks.ensure(ctx, capacity * DS_BRICK_WORDS * 4); !s) return makeError(where, s.message());
    capacity = bricks.buffer->size() / (DS_BRICK_WORDS * 4);

    // Submission 2: store, sort, donors, paint, pack. Repeated with a larger pool on overflow.
    // Paint visits only the brick columns under the footprint; every other entry stays the empty
    // tile the block buffer is filled with.
    VoxelizeParams paint = p;
    const uint32_t span = DS_BRICK_DIM * S;
    const uint32_t col0 = setup.ray_x0 / span, col1 = (setup.ray_x1 + span - 1) / span;
    const uint32_t row0 = std::max(p.brickRow0, setup.ray_y0 / span);
    const uint32_t row1 = std::min(p.brickRow0 + p.brickRows, (setup.ray_y1 + span - 1) / span);
    paint.paintColumn0 = col0;
    paint.paintColumns = std::max(1u, col1 - col0);
    paint.brickRow0 = row0;
    paint.brickRows = row1 > row0 && col1 > col0 ? row1 - row0 : 0;
    const uint64_t segments = (brick_dim + DS_VOX_PAINT_SEGMENT - 1) / DS_VOX_PAINT_SEGMENT;
    const uint64_t columns = uint64_t(paint.paintColumns) * paint.brickRows * segments;  // workgroups
    bool stored = false;
    uint64_t dense = 0, live_blocks = 0;
    for (int attempt = 0; attempt < 2; ++attempt) {
      p.brickCapacity = uint32_t(capacity);
      std::fill_n(counter_words, 2, 0u);
      // Store, paint and pack go in submissions of bounded work, so that a level-12 band on a
      // loaded CPU device still finishes each within the context's submit timeout.
      if (!stored && rays > 0) {
        auto store = submitAndWait(ctx, "voxelize store", [&](Commands& cmds) -> Status {
          auto b = bindings();
          if (stamps) stamps->begin(cmds, 1);
          if (auto s = runPass(cmds, *pipes->scatter, b, p, item1 - item0, false, item0); !s) return s;
          if (auto s = runPass(cmds, *pipes->sort, b, p, rays, false); !s) return s;
          if (auto s = runPass(cmds, *pipes->donor, b, p, rays, false); !s) return s;
          if (stamps) stamps->end(cmds, 1);
          return Ok{};
        });
        if (!store) return makeError(where, store.message());
        addKernelTime(1, &tm.store_sort_ms);
      }
      paint.brickCapacity = p.brickCapacity;
      paint.itemLimit = uint32_t(columns);
      uint64_t g = 0;
      do {
        const uint64_t g_end = std::min<uint64_t>(columns, g + kPaintGroupsPerSubmission);
        auto painted = submitAndWait(ctx, "voxelize paint", [&](Commands& cmds) -> Status {
          auto b = bindings();
          if (stamps) stamps->begin(cmds, 2);
          if (g == 0) {
            vkCmdFillBuffer(cmds.cmd(), blocks.buffer->handle(), 0, block_bytes, DS_ENTRY_UNIFORM);
            cmds.use(*blocks.buffer);
            cmds.barrier();
          }
          for (uint64_t next = g; next < g_end;) {
            const uint32_t n = uint32_t(std::min<uint64_t>(g_end - next, ctx.limits().max_group_count[0]));
            paint.firstItem = uint32_t(next);
            if (auto s = pipes->paint->dispatch(cmds, b, paint, n); !s) return s;
            next += n;
          }
          if (stamps) stamps->end(cmds, 2);
          return Ok{};
        });
        if (!painted) return makeError(where, painted.message());
        addKernelTime(2, &tm.paint_ms);
        g = g_end;
      } while (g < columns);
      auto packed_chunks = submitAndWait(ctx, "voxelize chunks", [&](Commands& cmds) -> Status {
        auto b = bindings();
        if (stamps) stamps->begin(cmds, 3);
        if (auto s = runPass(cmds, *pipes->chunks, b, p, band_chunk_count, true); !s) return s;
        if (stamps) stamps->end(cmds, 3);
        return Ok{};
      });
      if (!packed_chunks) return makeError(where, packed_chunks.message());
      addKernelTime(3, &tm.chunks_ms);
      stored = true;
      dense = counter_words[0];
      live_blocks = counter_words[1];
      if (dense <= capacity) break;
      if (dense > max_bricks) break;
      capacity = dense;
      if (auto s = bricks.ensure(ctx, capacity * DS_BRICK_WORDS * 4); !s) return makeError(where, s.message());
    }
    if (dense > capacity) {
      if (auto s = splitBand(std::to_string(dense) + " dense bricks exceed one binding"); !s) return s.error();
      continue;
    }

    const auto t_read = Clock::now();
    if (auto s = downloadWords(ctx, *chunk_out.buffer, band_chunks, band_chunk_count); !s) return s.error();
    if (auto s = downloadWords(ctx, *packed.buffer, band_blocks, live_blocks * DS_CHUNK_BRICKS); !s) return s.error();
    if (auto s = downloadWords(ctx, *bricks.buffer, band_bricks, dense * DS_BRICK_WORDS); !s) return s.error();
    // Indices in the band's arrays become indices in the whole volume's.
    const uint32_t block_base = uint32_t(block_words.size() / DS_CHUNK_BRICKS);
    const uint32_t brick_base = uint32_t(brick_words.size() / DS_BRICK_WORDS);
    for (uint32_t& e : band_blocks)
      if (!(e & DS_ENTRY_UNIFORM)) e += brick_base;
    block_words.insert(block_words.end(), band_blocks.begin(), band_blocks.end());
    brick_words.insert(brick_words.end(), band_bricks.begin(), band_bricks.end());
    for (uint32_t cz = 0; cz < chunk_dim; ++cz)
      for (uint32_t r = 0; r < rows; ++r)
        for (uint32_t cx = 0; cx < chunk_dim; ++cx) {
          uint32_t e = band_chunks[cx + size_t(chunk_dim) * (r + size_t(rows) * cz)];
          if (!(e & DS_ENTRY_UNIFORM)) e += block_base;
          chunk_table[layout::chunkCoordToIndex(cx, cy + r, cz, chunk_dim)] = e;
        }
    tm.readback_ms += msSince(t_read);
    tm.hits += band_hits;
    tm.dense_bricks += dense;
    tm.bands += 1;
    cy += rows;
  }

  auto volume = BrickVolume::fromWords(setup.level, std::move(chunk_table), std::move(block_words),
                                       std::move(brick_words), where);
  if (!volume) return volume.error();
  interrupter.end();
  tm.total_ms = msSince(t_start);
  return volume;
}

}  // namespace dentsim::gpu
