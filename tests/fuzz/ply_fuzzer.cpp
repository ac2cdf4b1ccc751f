// libFuzzer entry for the PLY reader: the input is parsed in memory, binary little-endian or ASCII as its header says.
#include <cstdint>
#include <span>

#include "io/ply_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dentsim::PlyReadLimits limits;
  // A forged count must not make the fuzzer run out of memory.
  limits.max_vertices = uint64_t{1} << 20;
  limits.max_triangles = uint64_t{1} << 20;
  (void)dentsim::parsePly(std::span<const uint8_t>(data, size), "fuzz.ply", limits);
  return 0;
}
