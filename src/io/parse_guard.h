// guardParse and quoteToken: file parsers' one-line errors, for exhausted memory, stray exceptions and quoted tokens.
#pragma once

#include <cstdint>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <string_view>

#include "core/result.h"
#include "core/text_escape.h"  // escapeControl

namespace dentsim {

// A token from a file, shortened and with unprintable bytes escaped, so a message stays one line.
inline std::string quoteToken(std::string_view token, size_t max_shown = 32) {
  return "\"" + escapeControl(token, max_shown, true) + "\"";
}

// Parsers check sizes before allocating, so this only catches what those checks cannot foresee
// (a machine short of memory); it keeps the promise that a bad file never ends in an abort.
// `what` names what is read ("the mesh", "the pen path").
template <class T, class Parse>
Result<T> guardParse(const std::string& where, size_t bytes, Parse&& parse, const char* what = "the mesh") {
  try {
    return parse();
  } catch (const std::bad_alloc&) {
    return makeError(where, std::string("out of memory while reading ") + what + " (" + std::to_string(bytes) + " bytes)");
  } catch (const std::exception& e) {
    return makeError(where, std::string("failed to read ") + what + ": " + quoteToken(e.what(), 200));
  }
}

}  // namespace dentsim
