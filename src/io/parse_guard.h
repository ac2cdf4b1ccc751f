// guardParse and quoteToken: file parsers' one-line errors, for exhausted memory, stray exceptions and quoted tokens.
#pragma once

#include <cstdint>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <string_view>

#include "core/result.h"

namespace dentsim {

// Text with its control bytes escaped as \xNN (with `high`, bytes 0x80 and up too), shortened to
// max_shown bytes: what user input may be echoed as inside a one-line error. A name typed by the
// user keeps its UTF-8; a token from a binary file does not.
inline std::string escapeControl(std::string_view text, size_t max_shown = 200, bool high = false) {
  std::string out;
  for (size_t i = 0; i < text.size() && i < max_shown; ++i) {
    const auto c = uint8_t(text[i]);
    if (c < 0x20 || c == 0x7f || (high && c >= 0x80)) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", unsigned(c));
      out += buf;
    } else {
      out += char(c);
    }
  }
  if (text.size() > max_shown) out += "...";
  return out;
}

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
