#pragma once
// The shape of the schema table lcmtypes/lcm_schema.py generates from the
// .lcm files (build/lcmtypes/gen/dynapath/lcm_schema.h): every field of
// every message type, in encoding order. Read by the bounds check
// (bounds.h) and by the schema test.

#include <cstdint>

namespace dynapath::protocol::schema {

enum class Kind : uint8_t {
  kInt8,
  kInt16,
  kInt32,
  kInt64,
  kFloat,
  kDouble,
  kString,
  kBoolean,
  kByte,
  kStruct,
};

inline constexpr int kMaxDims = 4;

// One array dimension: a constant `size` when `field` < 0, else the value
// of the earlier integer member number `field` of the same struct.
struct Dim {
  int32_t size;
  int16_t field;
};

struct Field {
  const char* name;
  const char* type_name;  // as written in the .lcm file
  Kind kind;
  int16_t struct_type;  // kStruct: index into kTypes
  int8_t num_dims;
  Dim dims[kMaxDims];
};

struct Type {
  const char* name;     // "job_t" (LCM's getTypeName())
  const char* package;  // "dynapath"
  const Field* fields;
  int num_fields;
};

}  // namespace dynapath::protocol::schema
