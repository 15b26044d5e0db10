#include "protocol/bounds.h"

#include <vector>

#include "dynapath/lcm_schema.h"
#include "dynapath/limits.h"

namespace dynapath::protocol {
namespace {

using schema::Field;
using schema::Kind;
using schema::Type;

int64_t PrimitiveSize(Kind kind) {
  switch (kind) {
    case Kind::kInt8:
    case Kind::kBoolean:
    case Kind::kByte:
      return 1;
    case Kind::kInt16:
      return 2;
    case Kind::kInt32:
    case Kind::kFloat:
      return 4;
    case Kind::kInt64:
    case Kind::kDouble:
      return 8;
    case Kind::kString:
      return 5;  // int32 length, then at least the terminating NUL
    case Kind::kStruct:
      return 0;
  }
  return 0;
}

int64_t MinSize(const Type& type, int depth);

int64_t MinFieldSize(const Field& field, int depth) {
  int64_t element = field.kind == Kind::kStruct
                        ? (depth > 16 ? 1 : MinSize(schema::kTypes[field.struct_type], depth + 1))
                        : PrimitiveSize(field.kind);
  for (int d = 0; d < field.num_dims; ++d) {
    if (field.dims[d].field >= 0) return 0;  // a variable dimension may be 0
    element *= field.dims[d].size;
  }
  return element;
}

int64_t MinSize(const Type& type, int depth) {
  int64_t total = 0;
  for (int f = 0; f < type.num_fields; ++f) total += MinFieldSize(type.fields[f], depth);
  return total;
}

int64_t ReadBigEndian(const uint8_t* p, int64_t bytes) {
  uint64_t value = 0;
  for (int64_t i = 0; i < bytes; ++i) value = (value << 8) | p[i];
  // Sign-extend from `bytes` bytes.
  const int shift = static_cast<int>(64 - 8 * bytes);
  return static_cast<int64_t>(value << shift) >> shift;
}

class Walker {
 public:
  Walker(const uint8_t* data, size_t size, const BoundsLimits& limits)
      : data_(data), size_(static_cast<int64_t>(size)), limits_(limits) {}

  bool Struct(const Type& type, int depth) {
    if (depth > limits_.max_depth) return Fail("structs nested too deeply in " + Name(type));
    // Values of this struct's integer members: array dimensions refer to them.
    std::vector<int64_t> values(static_cast<size_t>(type.num_fields), 0);
    for (int f = 0; f < type.num_fields; ++f) {
      const Field& field = type.fields[f];
      if (field.num_dims == 0) {
        if (!Value(type, field, depth, &values[static_cast<size_t>(f)])) return false;
        continue;
      }
      int64_t count = 1;
      for (int d = 0; d < field.num_dims; ++d) {
        const schema::Dim& dim = field.dims[d];
        const int64_t n = dim.field >= 0 ? values[static_cast<size_t>(dim.field)] : dim.size;
        if (n < 0) {
          return Fail(Name(type) + "." + field.name + ": negative count " + std::to_string(n));
        }
        if (n > limits_.max_array_elements || (n > 0 && count > limits_.max_array_elements / n)) {
          return Fail(Name(type) + "." + field.name + ": count " + std::to_string(count * n) +
                      " above the protocol's limit of " +
                      std::to_string(limits_.max_array_elements));
        }
        count *= n;
      }
      // Every element takes at least this many bytes: a count the remaining
      // bytes cannot hold is rejected before walking (or allocating) anything.
      const int64_t least = MinFieldElement(field, depth);
      if (least > 0 && count > (size_ - pos_) / least) {
        return Fail(Name(type) + "." + field.name + ": count " + std::to_string(count) +
                    " needs at least " + std::to_string(count * least) + " bytes, " +
                    std::to_string(size_ - pos_) + " remain");
      }
      if (field.kind != Kind::kString && field.kind != Kind::kStruct) {
        pos_ += count * least;
        continue;
      }
      for (int64_t i = 0; i < count; ++i) {
        if (!Value(type, field, depth, nullptr)) return false;
      }
    }
    return true;
  }

  int64_t pos() const { return pos_; }
  const std::string& error() const { return error_; }

 private:
  static std::string Name(const Type& type) { return type.name; }

  int64_t MinFieldElement(const Field& field, int depth) const {
    if (field.kind == Kind::kStruct) return MinSize(schema::kTypes[field.struct_type], depth + 1);
    return PrimitiveSize(field.kind);
  }

  // One value (not an array) of `field`; integers are stored in `value`.
  bool Value(const Type& type, const Field& field, int depth, int64_t* value) {
    if (field.kind == Kind::kStruct) return Struct(schema::kTypes[field.struct_type], depth + 1);
    if (field.kind == Kind::kString) {
      if (size_ - pos_ < 4) return Fail(Name(type) + "." + field.name + ": truncated length");
      const int64_t length = ReadBigEndian(data_ + pos_, 4);
      pos_ += 4;
      // LCM's length counts the terminating NUL: 0 or less would make the
      // generated decode assign (size_t)-1 characters.
      if (length < 1 || length - 1 > limits_.max_string_bytes) {
        return Fail(Name(type) + "." + field.name + ": bad string length " +
                    std::to_string(length));
      }
      if (length > size_ - pos_) {
        return Fail(Name(type) + "." + field.name + ": string of " + std::to_string(length) +
                    " bytes, " + std::to_string(size_ - pos_) + " remain");
      }
      if (data_[pos_ + length - 1] != 0) {
        return Fail(Name(type) + "." + field.name + ": string without its NUL");
      }
      pos_ += length;
      return true;
    }
    const int64_t bytes = PrimitiveSize(field.kind);
    if (size_ - pos_ < bytes) return Fail(Name(type) + "." + field.name + ": truncated");
    if (value != nullptr) *value = ReadBigEndian(data_ + pos_, bytes);
    pos_ += bytes;
    return true;
  }

  bool Fail(std::string why) {
    error_ = why + " (at byte " + std::to_string(pos_) + ")";
    return false;
  }

  const uint8_t* data_;
  int64_t size_;
  const BoundsLimits& limits_;
  int64_t pos_ = 8;  // after the fingerprint
  std::string error_;
};

}  // namespace

BoundsLimits::BoundsLimits()
    : max_array_elements(static_cast<int64_t>(kMaxGridSide) * kMaxGridSide * 8) {}

const schema::Type* FindSchemaType(std::string_view name) {
  for (const Type& type : schema::kTypes) {
    if (name == type.name) return &type;
  }
  return nullptr;
}

const schema::Type* SchemaTypes() { return schema::kTypes; }
int SchemaTypeCount() { return schema::kNumTypes; }

int64_t MinEncodedSize(const schema::Type& type) { return MinSize(type, 0); }

std::string CheckEncoding(const schema::Type& type, const uint8_t* data, size_t size,
                          const BoundsLimits& limits) {
  if (size < 8) return "shorter than a fingerprint (" + std::to_string(size) + " bytes)";
  Walker walker(data, size, limits);
  if (!walker.Struct(type, 0)) return walker.error();
  if (walker.pos() != static_cast<int64_t>(size)) {
    return std::to_string(static_cast<int64_t>(size) - walker.pos()) + " bytes after the end of " +
           std::string(type.name);
  }
  return {};
}

}  // namespace dynapath::protocol
