// Stamp: a payload for the lock-free channel tests whose three words all derive from one number, so a torn copy shows.
#pragma once

#include <cstdint>

namespace dentsim::test {

// A reader that saw parts of two values, or a slot overwritten while it was read, finds the words
// disagree. fill() writes them one by one, as a producer filling a slot in place does.
struct Stamp {
  uint64_t n = 0;
  uint64_t hash = 0;  // n * 2654435761
  uint64_t inv = 0;   // ~n
};

inline Stamp stampOf(uint64_t n) { return Stamp{n, n * 2654435761u, ~n}; }

inline void fill(Stamp* slot, uint64_t n) {
  slot->n = n;
  slot->hash = n * 2654435761u;
  slot->inv = ~n;
}

inline bool whole(const Stamp& s) { return s.hash == s.n * 2654435761u && s.inv == ~s.n; }

}  // namespace dentsim::test
