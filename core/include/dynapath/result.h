#pragma once
// Run-time errors (bad files, bad options) come back as values and are turned
// into one clear message at the boundary; exceptions and aborts are kept for
// broken invariants.

#include <cerrno>
#include <string>
#include <utility>
#include <variant>

namespace dynapath {

// What went wrong, as leveldb's Status tells it: a code callers branch on
// (IsNotFound(), IsCancelled(), ...) and the message the user reads. The
// code never changes the message. `Error{"text"}` is a bad argument.
struct Error {
  enum class Code {
    kInvalidArgument,  // a bad option, value or request
    kNotFound,         // a file (or process) that does not exist
    kCorrupt,          // input that does not parse: a file, a message
    kIo,               // a file or device that cannot be read or written
    kUnavailable,      // a process gone or silent, a timeout
    kCancelled,        // stopped (Ctrl-C, SIGTERM)
    kInternal,         // a broken invariant reported as a value
  };

  Error() = default;
  explicit Error(std::string text, Code kind = Code::kInvalidArgument, std::string about = {})
      : message(std::move(text)), code(kind), subject(std::move(about)) {}

  std::string message;
  Code code = Code::kInvalidArgument;
  // The option (without "--") or field the error concerns; "" if none.
  std::string subject;

  static Error NotFound(std::string text) { return Error(std::move(text), Code::kNotFound); }
  static Error Corrupt(std::string text) { return Error(std::move(text), Code::kCorrupt); }
  static Error Io(std::string text) { return Error(std::move(text), Code::kIo); }
  // A failed system call on a file, `error` its errno: kNotFound when the
  // file does not exist, kIo otherwise.
  static Error File(int error, std::string text) {
    return Error(std::move(text), error == ENOENT ? Code::kNotFound : Code::kIo);
  }
  static Error Unavailable(std::string text) { return Error(std::move(text), Code::kUnavailable); }
  static Error Internal(std::string text) { return Error(std::move(text), Code::kInternal); }
  // The run was stopped; its message is the one users have always seen.
  static Error Cancelled() { return Error("interrupted", Code::kCancelled); }
  // "option --NAME DETAIL", about option NAME.
  static Error Option(const std::string& name, const std::string& detail) {
    return Error("option --" + name + " " + detail, Code::kInvalidArgument, name);
  }

  bool IsInvalidArgument() const { return code == Code::kInvalidArgument; }
  bool IsNotFound() const { return code == Code::kNotFound; }
  bool IsCorrupt() const { return code == Code::kCorrupt; }
  bool IsIo() const { return code == Code::kIo; }
  bool IsUnavailable() const { return code == Code::kUnavailable; }
  bool IsCancelled() const { return code == Code::kCancelled; }
  bool IsInternal() const { return code == Code::kInternal; }

  // The same error with `prefix` put before its message (e.g. the file it
  // came from): code and subject are kept.
  Error Prefixed(const std::string& prefix) const { return Error(prefix + message, code, subject); }
  // The message without the "option --SUBJECT " (or "option --SUBJECT: ")
  // an option's error starts with, so it can be told as "WHERE: DETAIL";
  // the message otherwise.
  std::string Detail() const {
    const std::string prefix = "option --" + subject;
    if (subject.empty() || message.rfind(prefix, 0) != 0) return message;
    const std::string rest = message.substr(prefix.size());
    if (rest.rfind(": ", 0) == 0) return rest.substr(2);
    if (rest.rfind(' ', 0) == 0) return rest.substr(1);
    return message;
  }
};

// "invalid argument", "not found", ... (for logs).
inline const char* CodeName(Error::Code code) {
  switch (code) {
    case Error::Code::kInvalidArgument:
      return "invalid argument";
    case Error::Code::kNotFound:
      return "not found";
    case Error::Code::kCorrupt:
      return "corrupt";
    case Error::Code::kIo:
      return "I/O error";
    case Error::Code::kUnavailable:
      return "unavailable";
    case Error::Code::kCancelled:
      return "cancelled";
    case Error::Code::kInternal:
      return "internal";
  }
  return "?";
}

// Either a value or an Error (or another error type E that says more, such
// as a reason the caller counts beside the Error). A minimal stand-in for
// C++23 std::expected; [[nodiscard]]: ignoring a returned Result (an
// unchecked failure) warns.
template <class T, class E = Error>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::move(value)) {}  // NOLINT: implicit by design
  Result(E error) : state_(std::move(error)) {}  // NOLINT

  bool ok() const { return std::holds_alternative<T>(state_); }
  explicit operator bool() const { return ok(); }

  const T& value() const& { return std::get<T>(state_); }
  T& value() & { return std::get<T>(state_); }
  T&& value() && { return std::get<T>(std::move(state_)); }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

  const E& error() const { return std::get<E>(state_); }

 private:
  std::variant<T, E> state_;
};

// For operations that return nothing but may fail.
struct Ok {};
using Status = Result<Ok>;

}  // namespace dynapath
