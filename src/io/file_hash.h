// A file's identity: XXH3 (64 bits) of its bytes, read in pieces so that a long session costs no memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/result.h"

namespace dentsim {

// XXH3 of the whole file. Errors name the path.
Result<uint64_t> fileHash(const std::string& path);

// XXH3 of `size` bytes in memory: the identity of something made in memory, such as a scripted path.
uint64_t bytesHash(const void* data, size_t size);

}  // namespace dentsim
