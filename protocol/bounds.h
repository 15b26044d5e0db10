#pragma once
// The bounds check every received message passes before LCM's generated
// decode runs on it. The generated decoders trust the counts they read:
// they resize vectors to an announced count before checking that the bytes
// are there (0x7fffffff jobs: gigabytes allocated), and compute
// sizeof(T) * count in int (2^29 floats wrap negative and pass the length
// check: out-of-bounds read). This check walks the encoding with the schema
// generated from the .lcm files (lcmtypes/lcm_schema.py) and verifies every
// array count and string length against the bytes that remain and against
// the protocol's limits, in 64-bit arithmetic, without allocating. A message
// that passes decodes with allocations of at most a few times its own size:
// every element of an array of N announced elements takes at least one byte
// of the message.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "protocol/schema_types.h"

namespace dynapath::protocol {

struct BoundsLimits {
  // Longest string (run ids, labels, a coordinator's failure message).
  int64_t max_string_bytes = 64 * 1024;
  // Most elements of one array: the largest table the protocol carries (a
  // grid of kMaxGridSide x kMaxGridSide cells, 8 actions each).
  int64_t max_array_elements;
  // Deepest nesting of struct types.
  int max_depth = 8;
  BoundsLimits();
};

// The schema of LCM type `name` ("job_t", as getTypeName() says), or null.
const schema::Type* FindSchemaType(std::string_view name);
// All types of the schema (the .lcm files), for tests.
const schema::Type* SchemaTypes();
int SchemaTypeCount();

// "" when data[0, size) is exactly one encoded message of `type` (8-byte
// fingerprint, then the fields) within `limits`; else what is wrong and at
// which byte offset. The fingerprint itself is left to LCM's decode.
std::string CheckEncoding(const schema::Type& type, const uint8_t* data, size_t size,
                          const BoundsLimits& limits = BoundsLimits());

// The least number of bytes one encoded value of `type` takes (without the
// fingerprint): what every element of an array of it costs at least.
int64_t MinEncodedSize(const schema::Type& type);

}  // namespace dynapath::protocol
