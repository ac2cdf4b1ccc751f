// A file's identity: XXH3 (64 bits) of its bytes, read in pieces so that a long session costs no memory.
#pragma once

#include <cstdint>
#include <string>

#include "core/result.h"

namespace dentsim {

// XXH3 of the whole file. Errors name the path.
Result<uint64_t> fileHash(const std::string& path);

}  // namespace dentsim
