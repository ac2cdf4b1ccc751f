// libFuzzer entry for the STL reader: the input is parsed in memory, as binary or ASCII by its size and first word.
#include <cstdint>
#include <span>

#include "io/stl_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dentsim::StlReadLimits limits;
  limits.max_triangles = uint64_t{1} << 20;  // a forged count must not make the fuzzer run out of memory
  (void)dentsim::parseStl(std::span<const uint8_t>(data, size), "fuzz.stl", limits);
  return 0;
}
