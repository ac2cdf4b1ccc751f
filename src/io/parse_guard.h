// guardParse: runs a file parser so that exhausted memory or a stray exception becomes a one-line error naming the file.
#pragma once

#include <exception>
#include <new>
#include <string>

#include "core/result.h"

namespace dentsim {

// Parsers check sizes before allocating, so this only catches what those checks cannot foresee
// (a machine short of memory); it keeps the promise that a bad file never ends in an abort.
template <class T, class Parse>
Result<T> guardParse(const std::string& where, size_t bytes, Parse&& parse) {
  try {
    return parse();
  } catch (const std::bad_alloc&) {
    return makeError(where, "out of memory while reading the mesh (" + std::to_string(bytes) + " bytes)");
  } catch (const std::exception& e) {
    return makeError(where, std::string("failed to read the mesh: ") + e.what());
  }
}

}  // namespace dentsim
