#pragma once
// A small JSON value for the study manifest: null, booleans, numbers
// (doubles; integers up to 2^53 are exact and written without a decimal
// point), strings, arrays and objects (members keep their insertion order).
// Dump writes indented, valid JSON; Parse reads any JSON text (RFC 8259) and
// reports the line of the first error.

#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/result.h"

namespace dynapath::cli {

class Json {
 public:
  enum class Type { kNull, kBool, kNumber, kString, kArray, kObject };

  Json() = default;
  Json(std::nullptr_t) {}                                 // NOLINT: implicit by design
  Json(bool value) : type_(Type::kBool), bool_(value) {}  // NOLINT
  template <class T, std::enable_if_t<std::is_arithmetic_v<T> && !std::is_same_v<T, bool>, int> = 0>
  Json(T value) : type_(Type::kNumber), number_(static_cast<double>(value)) {}  // NOLINT
  Json(const char* value) : type_(Type::kString), string_(value) {}             // NOLINT
  Json(std::string value) : type_(Type::kString), string_(std::move(value)) {}  // NOLINT

  static Json Array() { return Json(Type::kArray); }
  static Json Object() { return Json(Type::kObject); }

  Type type() const { return type_; }
  bool IsNull() const { return type_ == Type::kNull; }
  bool IsBool() const { return type_ == Type::kBool; }
  bool IsNumber() const { return type_ == Type::kNumber; }
  bool IsString() const { return type_ == Type::kString; }
  bool IsArray() const { return type_ == Type::kArray; }
  bool IsObject() const { return type_ == Type::kObject; }

  // The value, or `fallback` when it has another type.
  bool AsBool(bool fallback = false) const { return IsBool() ? bool_ : fallback; }
  double AsNumber(double fallback = 0.0) const { return IsNumber() ? number_ : fallback; }
  long long AsInt(long long fallback = 0) const;
  std::string AsString(const std::string& fallback = "") const {
    return IsString() ? string_ : fallback;
  }

  // Objects: the member `key`, added (null) when missing. Turns a null value
  // into an object first.
  Json& operator[](const std::string& key);
  // Objects: the member `key`, or nullptr.
  const Json* Find(const std::string& key) const;
  // Arrays: appends (turns a null value into an array first).
  void Push(Json value);

  const std::vector<Json>& items() const { return items_; }
  const std::vector<std::pair<std::string, Json>>& members() const { return members_; }
  size_t size() const { return IsArray() ? items_.size() : members_.size(); }

  // Indented JSON ending in a newline (indent 0: one line, no newline).
  std::string Dump(int indent = 2) const;
  static Result<Json> Parse(std::string_view text);

  bool operator==(const Json& other) const;
  bool operator!=(const Json& other) const { return !(*this == other); }

 private:
  explicit Json(Type type) : type_(type) {}
  void DumpTo(std::string& out, int indent, int depth) const;

  Type type_ = Type::kNull;
  bool bool_ = false;
  double number_ = 0.0;
  std::string string_;
  std::vector<Json> items_;
  std::vector<std::pair<std::string, Json>> members_;
};

// `text` as a JSON string literal, quotes included.
std::string JsonQuote(std::string_view text);

}  // namespace dynapath::cli
