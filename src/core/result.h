// Result<T>: a value or a readable one-line error, returned wherever the environment can fail.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

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

inline Error makeError(std::string where, const std::string& what) {
  return Error{where.empty() ? what : std::move(where) + ": " + what};
}

}  // namespace dentsim
