// A printf-style format into a std::string, for numbers in report lines and tables: one definition for every stage.
#pragma once

#include <cstdarg>
#include <cstdio>
#include <string>

namespace dentsim {

// The compiler checks each call's format against its arguments (the attribute), and the format is a
// literal at every call: no text from a file or a user is ever a format. The result is never
// truncated: the length is measured first.
__attribute__((format(printf, 1, 2))) inline std::string formatted(const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string out(n > 0 ? size_t(n) : 0, '\0');
  if (n > 0) std::vsnprintf(out.data(), out.size() + 1, format, again);
  va_end(again);
  return out;
}

}  // namespace dentsim
