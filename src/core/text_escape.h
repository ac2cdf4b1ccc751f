// escapeControl: text from outside (a file's name, a header line, a URL) made safe to echo inside a one-line message.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace dentsim {

// Text with its control bytes escaped as \xNN (with `high`, bytes 0x80 and up too), shortened to
// max_shown bytes: what user input may be echoed as inside a one-line error. A name typed by the
// user keeps its UTF-8; a token from a binary file does not. A newline cannot end the line early
// and an ESC cannot start a terminal escape. The output holds no control bytes, so escaping it
// again changes nothing: a name escaped once by a reader and again by makeError reads the same.
inline std::string escapeControl(std::string_view text, size_t max_shown = 200, bool high = false) {
  std::string out;
  out.reserve(text.size() < max_shown ? text.size() : max_shown);
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

// A path as a message shows it: escaped, never shortened (the user must recognise the whole name).
inline std::string shownPath(std::string_view path) { return escapeControl(path, path.size()); }

// RFC 3986 percent-encoding: every byte but the unreserved ones (letters, digits, - . _ ~) and
// those in `keep` as %XX. A URL's query value keeps none; a file: URL's path keeps '/'.
inline std::string percentEncoded(std::string_view text, std::string_view keep = {}) {
  std::string out;
  for (unsigned char c : text) {
    const bool unreserved = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' ||
                            c == '.' || c == '_' || c == '~';
    if (unreserved || keep.find(char(c)) != std::string_view::npos) {
      out += char(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out;
}

}  // namespace dentsim
