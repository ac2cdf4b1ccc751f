// The table of embedded asset files that CMake generates from assets/ (embed_assets.cmake); internal to model.
#pragma once

#include <cstddef>

namespace dentsim::embedded {

struct Asset {
  const char* path;           // relative to assets/, '/'-separated; null in the closing entry
  const unsigned char* data;  // the file's bytes
  size_t size;                // [bytes]
};

// Sorted by path, closed by an entry whose path is null.
extern const Asset kAssets[];

}  // namespace dentsim::embedded
