#pragma once
// Run-time errors (bad files, bad options) come back as values and are turned
// into one clear message at the boundary; exceptions and aborts are kept for
// broken invariants.

#include <string>
#include <utility>
#include <variant>

namespace dynapath {

struct Error {
  std::string message;
};

// Either a value or an Error. A minimal stand-in for C++23 std::expected;
// [[nodiscard]]: ignoring a returned Result (an unchecked failure) warns.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::move(value)) {}      // NOLINT: implicit by design
  Result(Error error) : state_(std::move(error)) {}  // NOLINT

  bool ok() const { return std::holds_alternative<T>(state_); }
  explicit operator bool() const { return ok(); }

  const T& value() const& { return std::get<T>(state_); }
  T& value() & { return std::get<T>(state_); }
  T&& value() && { return std::get<T>(std::move(state_)); }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

  const Error& error() const { return std::get<Error>(state_); }

 private:
  std::variant<T, Error> state_;
};

// For operations that return nothing but may fail.
struct Ok {};
using Status = Result<Ok>;

}  // namespace dynapath
