// BuddyAllocator: power-of-two slots in one growable range, coalesced on free, so a pool of re-meshed blocks never fragments without bound.
//
// A request is rounded up to a power-of-two multiple of the unit; a freed slot merges with its free
// buddy, level by level. The wasted space is therefore at most the rounding (under half of each
// slot) plus free slots whose buddies are still in use; freeing everything always leaves one free
// range. grow() doubles the range: the old range becomes the lower half, so live offsets stay valid
// and the caller copies nothing inside the pool (only into a larger buffer).
#pragma once

#include <bit>
#include <cassert>
#include <cstdint>
#include <optional>
#include <set>
#include <unordered_map>
#include <vector>

namespace dentsim {

class BuddyAllocator {
 public:
  // A range of `capacity` bytes in slots of at least `unit` bytes; both powers of two, unit <= capacity.
  BuddyAllocator(uint64_t unit, uint64_t capacity) : unit_(unit) {
    assert(std::has_single_bit(unit) && std::has_single_bit(capacity) && unit <= capacity);
    top_order_ = orderOfUnits(capacity / unit);
    free_.resize(size_t(top_order_) + 1);
    free_[size_t(top_order_)].insert(0);
  }

  uint64_t unit() const { return unit_; }
  uint64_t capacity() const { return unit_ << top_order_; }           // [B]
  uint64_t allocatedBytes() const { return allocated_; }             // live slots, rounded [B]
  size_t liveSlots() const { return live_.size(); }
  // Size of the slot a request of `bytes` gets [B].
  uint64_t slotBytes(uint64_t bytes) const { return unit_ << orderFor(bytes); }
  // Size of the live slot at `offset` [B].
  uint64_t slotBytesAt(uint64_t offset) const { return unit_ << live_.at(offset); }
  // The largest free slot [B], 0 when full.
  uint64_t largestFree() const {
    for (uint32_t o = top_order_ + 1; o-- > 0;)
      if (!free_[o].empty()) return unit_ << o;
    return 0;
  }

  // Offset of a free slot of at least `bytes` (> 0), or nothing when no free slot is large enough.
  std::optional<uint64_t> allocate(uint64_t bytes) {
    const uint32_t want = orderFor(bytes);
    if (want > top_order_) return std::nullopt;
    uint32_t o = want;
    while (o <= top_order_ && free_[o].empty()) ++o;
    if (o > top_order_) return std::nullopt;
    // The lowest free offset keeps live slots packed towards the start of the pool.
    const uint64_t offset = *free_[o].begin();
    free_[o].erase(free_[o].begin());
    while (o > want) {  // split, keeping the lower half
      --o;
      free_[o].insert(offset + (unit_ << o));
    }
    live_.emplace(offset, want);
    allocated_ += unit_ << want;
    return offset;
  }

  // Returns the slot at `offset` (from allocate) and merges it with free buddies.
  void release(uint64_t offset) {
    auto it = live_.find(offset);
    assert(it != live_.end() && "release of an offset that is not a live slot");
    uint32_t o = it->second;
    live_.erase(it);
    allocated_ -= unit_ << o;
    uint64_t at = offset;
    while (o < top_order_) {
      const uint64_t buddy = at ^ (unit_ << o);
      auto b = free_[o].find(buddy);
      if (b == free_[o].end()) break;
      free_[o].erase(b);
      at = at < buddy ? at : buddy;
      ++o;
    }
    free_[o].insert(at);
  }

  // Doubles the range; the new upper half is one free slot (merged with a wholly free lower half).
  void grow() {
    ++top_order_;
    free_.resize(size_t(top_order_) + 1);
    const uint32_t half = top_order_ - 1;
    if (free_[half].count(0) != 0) {  // the old range was empty: one free slot of the new size
      free_[half].erase(0);
      free_[top_order_].insert(0);
    } else {
      free_[half].insert(unit_ << half);
    }
  }

 private:
  static uint32_t orderOfUnits(uint64_t units) { return uint32_t(std::countr_zero(units)); }
  uint32_t orderFor(uint64_t bytes) const {
    const uint64_t units = (bytes + unit_ - 1) / unit_;
    return orderOfUnits(std::bit_ceil(units < 1 ? uint64_t{1} : units));
  }

  uint64_t unit_;
  uint32_t top_order_ = 0;
  std::vector<std::set<uint64_t>> free_;          // free slot offsets per order
  std::unordered_map<uint64_t, uint32_t> live_;   // live slot offset -> order
  uint64_t allocated_ = 0;
};

}  // namespace dentsim
