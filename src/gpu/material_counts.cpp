// GPU material counts: upload a brick volume, dispatch material_counts.comp.glsl over all bricks, sum the records.
#include "gpu/material_counts.h"

#include <array>
#include <vector>

#include "dentsim_compute_spirv_spirv.h"
#include "gpu/buffer.h"
#include "gpu/compute.h"

namespace dentsim::gpu {
namespace {

// A device-local storage buffer holding `words`; an empty array becomes a small zeroed buffer, since
// every binding needs a buffer even when the volume has no blocks or bricks.
Result<Buffer> uploadWords(Context& ctx, std::span<const uint32_t> words, const std::string& name) {
  constexpr uint64_t kEmptyBytes = 16;
  const uint64_t bytes = words.empty() ? kEmptyBytes : words.size_bytes();
  auto b = Buffer::create(ctx, bytes, MemoryKind::DeviceLocal, BufferUse::Storage, name);
  if (!b) return b.error();
  if (words.empty()) {
    if (auto s = b->clear(ctx); !s) return s.error();
  } else if (auto s = b->upload(ctx, std::as_bytes(words)); !s) {
    return s.error();
  }
  return b;
}

}  // namespace

Result<MaterialTotals> countMaterialsGpu(Context& ctx, const BrickVolume& volume, TimingOut* timing,
                                         const CountOptions& options) {
  const std::string where = "gpu: material counts";
  auto pipeline = ComputePipeline::create(
      ctx, PipelineDesc{"material_counts", {material_counts_comp_spv, material_counts_comp_spv_words}, 4, {}});
  if (!pipeline) return pipeline.error();

  const layout::GridInfo grid = volume.gridInfo();
  const uint64_t records = pipeline->groupsFor(grid.brickCount);
  const uint64_t out_bytes = records * DS_COUNT_OUT_WORDS * sizeof(uint32_t);

  // Pools over one binding's range cannot be counted in one pass yet; the error names the pool.
  auto chunks = uploadWords(ctx, volume.chunkWords(), "volume chunks");
  if (!chunks) return makeError(where, chunks.message());
  auto blocks = uploadWords(ctx, volume.blockWords(), "volume blocks");
  if (!blocks) return makeError(where, blocks.message());
  auto bricks = uploadWords(ctx, volume.brickWords(), "volume bricks");
  if (!bricks) return makeError(where, bricks.message());
  auto out = Buffer::create(ctx, out_bytes, MemoryKind::HostVisible, BufferUse::Storage, "material count records");
  if (!out) return makeError(where, out.message());
  if (auto s = out->clear(ctx); !s) return s.error();

  std::string note;
  const bool timed = timing && TimestampPool::supported(ctx, &note);
  Result<TimestampPool> stamps = timed ? TimestampPool::create(ctx, 1, "material counts timestamps")
                                       : Result<TimestampPool>(Error{note});
  if (timed && !stamps) return stamps.error();

  // Split by brick range so that no dispatch exceeds the group-count limit; each part starts at a
  // multiple of the group size, so its records land at firstBrick / groupSize.
  const std::vector<DispatchRange> parts = pipeline->split(grid.brickCount, options.max_groups_per_dispatch);
  std::array<Buffer*, 4> bindings{};
  bindings[DS_BINDING_CHUNKS] = &*chunks;
  bindings[DS_BINDING_BLOCKS] = &*blocks;
  bindings[DS_BINDING_BRICKS] = &*bricks;
  bindings[DS_BINDING_COUNT_OUT] = &*out;
  auto submitted = submitAndWait(ctx, "material counts", [&](Commands& cmds) -> Status {
    if (timed) stamps->begin(cmds, 0);
    for (const DispatchRange& part : parts) {
      layout::MaterialCountParams params{};
      params.grid = grid;
      params.firstBrick = static_cast<uint32_t>(part.first);
      params.brickLimit = static_cast<uint32_t>(part.first + part.count);
      if (auto s = pipeline->dispatch(cmds, bindings, params, part.groups); !s) return s;
    }
    if (timed) stamps->end(cmds, 0);
    return Ok{};
  });
  if (!submitted) return submitted.error();

  MaterialTotals totals;
  const auto* words = static_cast<const uint32_t*>(out->mapped());
  for (uint64_t r = 0; r < records; ++r) {
    const uint32_t* rec = words + r * DS_COUNT_OUT_WORDS;
    for (size_t m = 0; m < DS_MATERIAL_COUNT; ++m) {
      totals.fill_sum[m] += rec[m];
      totals.voxels[m] += rec[DS_MATERIAL_COUNT + m];
    }
  }

  if (timing) {
    timing->dispatches = static_cast<uint32_t>(parts.size());
    timing->workgroups = records;
    timing->timestamps = false;
    timing->timestamp_note = note;
    if (timed) {
      auto ns = stamps->elapsedNs(0);
      if (ns) {
        timing->timestamps = true;
        timing->kernel_ns = *ns;
      } else {
        timing->timestamp_note = ns.message();
      }
    }
  }
  return totals;
}

}  // namespace dentsim::gpu
