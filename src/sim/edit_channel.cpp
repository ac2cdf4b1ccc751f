// EditChannel: a single-producer, single-consumer ring of voxel edits, and their replay into a volume copy.
#include "sim/edit_channel.h"

#include <algorithm>
#include <cassert>

namespace dentsim {

EditChannel::EditChannel(int capacity_log2) : ring_(size_t{1} << capacity_log2), mask_((uint64_t{1} << capacity_log2) - 1) {
  assert(capacity_log2 > 0 && capacity_log2 < 40);
}

size_t EditChannel::freeSlots() const {
  return size_t(ring_.size() - (written_ - consumed_.load(std::memory_order_acquire)));
}

void EditChannel::push(uint64_t edit) {
  assert(freeSlots() > 0);
  ring_[written_ & mask_] = edit;
  ++written_;
}

void EditChannel::publish() { published_.store(written_, std::memory_order_release); }

size_t EditChannel::drain(std::vector<uint64_t>* out) {
  const uint64_t end = published_.load(std::memory_order_acquire);
  uint64_t at = consumed_.load(std::memory_order_relaxed);
  const size_t n = size_t(end - at);
  for (; at != end; ++at) out->push_back(ring_[at & mask_]);
  consumed_.store(end, std::memory_order_release);
  return n;
}

void applyVoxelEdits(BrickVolume& volume, const std::vector<uint64_t>& edits, std::vector<BrickCoord>* dirty) {
  const uint64_t dim = volume.dim();
  std::vector<uint64_t> bricks;
  bricks.reserve(edits.size() / 8 + 1);
  for (uint64_t e : edits) {
    const uint64_t i = e >> 8;
    const auto x = uint32_t(i % dim), y = uint32_t((i / dim) % dim), z = uint32_t(i / dim / dim);
    volume.setVoxel(x, y, z, Voxel(e & 0xffu));
    const uint64_t bd = volume.brickDim();
    bricks.push_back(((uint64_t(z) >> DS_BRICK_LOG2) * bd + (y >> DS_BRICK_LOG2)) * bd + (x >> DS_BRICK_LOG2));
  }
  if (dirty == nullptr) return;
  std::sort(bricks.begin(), bricks.end());
  bricks.erase(std::unique(bricks.begin(), bricks.end()), bricks.end());
  const uint64_t bd = volume.brickDim();
  for (uint64_t b : bricks) dirty->push_back(BrickCoord{uint32_t(b % bd), uint32_t((b / bd) % bd), uint32_t(b / bd / bd)});
}

}  // namespace dentsim
