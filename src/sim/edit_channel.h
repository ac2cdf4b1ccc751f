// EditChannel: the lock-free queue that carries the haptic thread's voxel edits to the thread that updates the GPU mirror.
//
// The haptic thread owns one copy of the voxels and edits it at once, so the student never feels
// removed material; every edit it makes is also pushed here, as (voxel index, new byte). The
// consumer replays the edits into its own copy and re-meshes the bricks they touch. Replaying
// every edit in order makes the two copies equal whenever the channel is empty.
//
// Single producer, single consumer. The producer reserves room for a whole step before it edits
// (freeSlots), pushes, then publishes the step at once, so the consumer only ever sees whole steps.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "volume/brick_volume.h"

namespace dentsim {

// One voxel edit: linear voxel index (x + dim * (y + dim * z)) in bits 8..63, the new byte in 0..7.
inline uint64_t packVoxelEdit(uint64_t linear_index, Voxel value) { return (linear_index << 8) | value; }

class EditChannel {
 public:
  // Room for 2^capacity_log2 edits.
  explicit EditChannel(int capacity_log2 = 20);
  size_t capacity() const { return ring_.size(); }  // edits the channel holds at most

  // ---- producer (the haptic thread) ----
  size_t freeSlots() const;              // edits that can be pushed before the next publish
  void push(uint64_t edit);              // precondition: freeSlots() > 0 (asserted)
  void publish();                        // makes every pushed edit visible at once

  // ---- consumer ----
  // Pops every published edit into out (appended); returns how many.
  size_t drain(std::vector<uint64_t>* out);

 private:
  std::vector<uint64_t> ring_;
  uint64_t mask_;
  alignas(64) std::atomic<uint64_t> published_{0};  // producer's count, visible to the consumer
  uint64_t written_ = 0;                            // producer's private count, >= published_
  alignas(64) std::atomic<uint64_t> consumed_{0};   // consumer's count
};

// Applies drained edits to a copy of the volume and lists the bricks they touched (sorted, unique).
void applyVoxelEdits(BrickVolume& volume, const std::vector<uint64_t>& edits, std::vector<BrickCoord>* dirty);

}  // namespace dentsim
