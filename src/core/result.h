// Result<T>: a value or a readable one-line error, returned wherever the environment can fail.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

#include "core/text_escape.h"

namespace dentsim {

// An error that the user reads: one line naming what failed and where ("tooth.dvol: checksum mismatch").
struct Error {
  std::string message;
};

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}        // NOLINT(google-explicit-constructor)
  Result(Error error) : v_(std::move(error)) {}    // NOLINT(google-explicit-constructor)

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & { assert(ok()); return std::get<0>(v_); }
  const T& value() const& { assert(ok()); return std::get<0>(v_); }
  T&& value() && { assert(ok()); return std::get<0>(std::move(v_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  const Error& error() const { assert(!ok()); return std::get<1>(v_); }
  const std::string& message() const { return error().message; }

 private:
  std::variant<T, Error> v_;
};

// Result for operations that return nothing but can fail.
struct Ok {};
using Status = Result<Ok>;

// `where` is most often a path the user gave or a file named: its control bytes are escaped
// (core/text_escape.h), so a name holding a newline or an ESC cannot break the line or drive the
// terminal. `what` is the caller's to escape where it quotes outside text.
inline Error makeError(const std::string& where, const std::string& what) {
  return Error{where.empty() ? what : shownPath(where) + ": " + what};
}

}  // namespace dentsim
