#pragma once
// Test support: encodes messages of any type of the schema (the .lcm files)
// byte by byte, with chosen array counts, string lengths and random field
// values. The bounds test checks with it that the schema matches LCM's
// generated code (every such message decodes and re-encodes to the same
// bytes) and crafts a huge count or length for every field of every type.

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "protocol/bounds.h"

namespace dynapath::protocol::testing {

// A place in a message: field `field` of the first value of type `type`
// the encoder writes (nested types included).
struct Target {
  const schema::Type* type = nullptr;
  int field = -1;
  int64_t value = 0;  // the count (the dimension's member) or string length to write
};

class SchemaEncoder {
 public:
  explicit SchemaEncoder(uint64_t seed) : random_(seed) {}

  // A message of `type` with its fingerprint (`hash`). Variable counts are 0
  // to `max_count` (at least 1 on the way to `target`). With a target, its
  // count or length is target.value whatever the bytes that follow.
  std::vector<uint8_t> Encode(const schema::Type& type, int64_t hash, int max_count,
                              const Target& target = {}) {
    bytes_.clear();
    target_ = target;
    target_done_ = false;
    max_count_ = max_count;
    Put(static_cast<uint64_t>(hash), 8);
    Struct(type, 0);
    return bytes_;
  }

  // Does `type` contain `target.type` (itself or nested)?
  static bool Contains(const schema::Type& type, const schema::Type* target, int depth = 0) {
    if (&type == target) return true;
    if (depth > 8) return false;
    for (int f = 0; f < type.num_fields; ++f) {
      const schema::Field& field = type.fields[f];
      if (field.kind == schema::Kind::kStruct &&
          Contains(schema_types()[field.struct_type], target, depth + 1)) {
        return true;
      }
    }
    return false;
  }

 private:
  static const schema::Type* schema_types() { return SchemaTypes(); }

  void Put(uint64_t value, int bytes) {
    for (int i = bytes - 1; i >= 0; --i) bytes_.push_back(static_cast<uint8_t>(value >> (8 * i)));
  }

  // The count field `f` of `type` must hold (it is a dimension of a later
  // field), or -1 when it is no dimension.
  int64_t CountFor(const schema::Type& type, int f) {
    bool is_dim = false;
    bool leads_to_target = false;
    for (int g = f + 1; g < type.num_fields; ++g) {
      const schema::Field& later = type.fields[g];
      for (int d = 0; d < later.num_dims; ++d) {
        if (later.dims[d].field != f) continue;
        is_dim = true;
        if (!target_done_ && later.kind == schema::Kind::kStruct && target_.type != nullptr &&
            Contains(schema_types()[later.struct_type], target_.type)) {
          leads_to_target = true;
        }
        if (!target_done_ && &type == target_.type && g == target_.field) return -2;
      }
    }
    if (!is_dim) return -1;
    const int64_t count = static_cast<int64_t>(random_() % (max_count_ + 1));
    return leads_to_target ? std::max<int64_t>(1, count) : count;
  }

  void Struct(const schema::Type& type, int depth) {
    std::vector<int64_t> values(static_cast<size_t>(type.num_fields), 0);
    for (int f = 0; f < type.num_fields; ++f) {
      const schema::Field& field = type.fields[f];
      const bool is_target = !target_done_ && &type == target_.type && f == target_.field;
      if (field.num_dims == 0) {
        values[static_cast<size_t>(f)] = Scalar(type, f, field, depth, is_target);
        continue;
      }
      int64_t count = 1;
      for (int d = 0; d < field.num_dims; ++d) {
        count *= field.dims[d].field >= 0 ? values[static_cast<size_t>(field.dims[d].field)]
                                          : field.dims[d].size;
      }
      if (is_target) target_done_ = true;
      // A crafted (huge or negative) count is followed by a few elements at most.
      const int64_t written = count < 0 ? 0 : count > 1000 ? 3 : count;
      for (int64_t i = 0; i < written; ++i) {
        Scalar(type, f, field, depth, false);
      }
    }
  }

  int64_t Scalar(const schema::Type& type, int f, const schema::Field& field, int depth,
                 bool is_target) {
    using schema::Kind;
    switch (field.kind) {
      case Kind::kStruct:
        Struct(schema_types()[field.struct_type], depth + 1);
        return 0;
      case Kind::kString: {
        if (is_target) {
          target_done_ = true;
          Put(static_cast<uint64_t>(target_.value), 4);
          for (int i = 0; i < 3; ++i) bytes_.push_back('x');
          return 0;
        }
        const int length = static_cast<int>(random_() % 6);
        Put(static_cast<uint64_t>(length + 1), 4);
        for (int i = 0; i < length; ++i)
          bytes_.push_back(static_cast<uint8_t>('a' + random_() % 26));
        bytes_.push_back(0);
        return 0;
      }
      default:
        break;
    }
    int bytes = 1;
    switch (field.kind) {
      case Kind::kInt16:
        bytes = 2;
        break;
      case Kind::kInt32:
      case Kind::kFloat:
        bytes = 4;
        break;
      case Kind::kInt64:
      case Kind::kDouble:
        bytes = 8;
        break;
      default:
        bytes = 1;
    }
    int64_t value = CountFor(type, f);
    if (value == -2) {  // the dimension of the target
      value = target_.value;
    } else if (value < 0) {
      value = static_cast<int64_t>(random_());
    }
    Put(static_cast<uint64_t>(value), bytes);
    return value;
  }

  std::mt19937_64 random_;
  std::vector<uint8_t> bytes_;
  Target target_;
  bool target_done_ = false;
  int max_count_ = 3;
};

}  // namespace dynapath::protocol::testing
