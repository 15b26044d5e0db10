// The bounds check (protocol/bounds.h) against LCM's generated code,
// for every type of the schema: messages the schema encoder writes decode
// with LCM's decoder and re-encode to the same bytes (the schema matches the
// generated code field by field), and a huge, negative or overlong count or
// string length in any variable-length field of any type is rejected by
// DecodeExactly without a large allocation. Its own binary: it replaces the
// global operator new to measure the largest allocation.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <set>

#include "protocol/bounds.h"
#include "tests/protocol/message_types.h"
#include "tests/protocol/schema_encoder.h"

namespace {
std::atomic<size_t> largest_allocation{0};
}  // namespace

// The replacements below pair malloc with free, as they must; GCC 12 at -O1
// inlines them into the callers and then takes their new/delete for a
// mismatch (-Wmismatched-new-delete). Only in this file.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

void* operator new(size_t size) {
  size_t seen = largest_allocation.load(std::memory_order_relaxed);
  while (size > seen && !largest_allocation.compare_exchange_weak(seen, size)) {
  }
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }

namespace dynapath::protocol {
namespace {

using testing::AllMessageTypes;
using testing::MessageType;
using testing::SchemaEncoder;
using testing::Target;

const schema::Type& SchemaOf(const MessageType& type) {
  const schema::Type* found = FindSchemaType(type.name);
  EXPECT_NE(found, nullptr) << type.name;
  return *found;
}

TEST(BoundsCheck, EveryTypeOfTheSchemaHasADecoderHere) {
  std::set<std::string> schema_names, listed;
  for (int i = 0; i < SchemaTypeCount(); ++i) schema_names.insert(SchemaTypes()[i].name);
  for (const MessageType& type : AllMessageTypes()) listed.insert(type.name);
  EXPECT_EQ(schema_names, listed);
  // path_reply_t and the service's others: 14-19; model_round_t, model_shards_t
  EXPECT_EQ(SchemaTypeCount(), 22);
}

// The schema encoder's messages are what LCM's generated code reads and
// writes, byte for byte: field order, sizes, counts and strings agree.
TEST(BoundsCheck, SchemaMatchesTheGeneratedCode) {
  SchemaEncoder encoder(7);
  for (const MessageType& type : AllMessageTypes()) {
    const schema::Type& schema = SchemaOf(type);
    for (int trial = 0; trial < 200; ++trial) {
      const std::vector<uint8_t> bytes = encoder.Encode(schema, type.hash, trial % 4);
      const int size = static_cast<int>(bytes.size());
      std::vector<uint8_t> reencoded;
      ASSERT_TRUE(type.raw_decode(bytes.data(), size, &reencoded)) << type.name;
      EXPECT_EQ(reencoded, bytes) << type.name;
      std::string why;
      EXPECT_TRUE(type.checked_decode(bytes.data(), size, &why)) << type.name << ": " << why;
      // Every truncation and one byte too many are rejected.
      for (int cut = 0; cut < size; cut += 1 + size / 40) {
        EXPECT_FALSE(type.checked_decode(bytes.data(), cut, nullptr)) << type.name << " " << cut;
      }
      std::vector<uint8_t> longer = bytes;
      longer.push_back(0);
      EXPECT_FALSE(type.checked_decode(longer.data(), size + 1, nullptr)) << type.name;
    }
  }
}

struct Crafted {
  std::string where;
  std::string holder;  // "job_t.": the check must blame a field of this type
  std::vector<uint8_t> bytes;
};

// For every variable-length array and every string of every type (nested
// types reached through the types that hold them), messages announcing
// absurd counts or lengths.
std::vector<Crafted> CraftedMessages(const MessageType& type) {
  const schema::Type& top = SchemaOf(type);
  std::vector<Crafted> crafted;
  SchemaEncoder encoder(11);
  const int64_t counts[] = {
      -1, int64_t{1} << 29, int64_t{1} << 30, 0x7fffffff, 0x7ffffff8, -0x7fffffff - 1, 100000};
  // 1000: under the string limit but past the end of any crafted message
  // (each is < 1 KB); a shorter one can end inside a message of many fields
  // after the string (goal_reply_t) on a zero byte taken for its NUL.
  const int64_t lengths[] = {0, -1, 0x7fffffff, 1 << 20, 1000};
  for (int t = 0; t < SchemaTypeCount(); ++t) {
    const schema::Type& holder = SchemaTypes()[t];
    if (!SchemaEncoder::Contains(top, &holder)) continue;
    for (int f = 0; f < holder.num_fields; ++f) {
      const schema::Field& field = holder.fields[f];
      const std::string where = std::string(top.name) + " > " + holder.name + "." + field.name;
      if (field.kind == schema::Kind::kString && field.num_dims == 0) {
        for (int64_t length : lengths) {
          crafted.push_back({where + " length " + std::to_string(length),
                             std::string(holder.name) + "." + field.name,
                             encoder.Encode(top, type.hash, 1, Target{&holder, f, length})});
        }
      }
      bool variable = false;
      for (int d = 0; d < field.num_dims; ++d) variable = variable || field.dims[d].field >= 0;
      if (!variable) continue;
      for (int64_t count : counts) {
        // The first array of the same count is the one blamed.
        std::string blamed = field.name;
        for (int g = 0; g < f; ++g) {
          if (holder.fields[g].num_dims > 0 &&
              holder.fields[g].dims[0].field == field.dims[0].field) {
            blamed = holder.fields[g].name;
            break;
          }
        }
        crafted.push_back({where + " count " + std::to_string(count),
                           std::string(holder.name) + "." + blamed,
                           encoder.Encode(top, type.hash, 1, Target{&holder, f, count})});
      }
    }
  }
  return crafted;
}

TEST(BoundsCheck, HugeCountsAndLengthsAreRejectedWithoutLargeAllocations) {
  int fields_crafted = 0;
  for (const MessageType& type : AllMessageTypes()) {
    for (const Crafted& message : CraftedMessages(type)) {
      ++fields_crafted;
      largest_allocation = 0;
      std::string why;
      EXPECT_FALSE(
          type.checked_decode(message.bytes.data(), static_cast<int>(message.bytes.size()), &why))
          << message.where;
      EXPECT_NE(why.find(message.holder + ":"), std::string::npos) << message.where << ": " << why;
      // The message is < 1 KB: nothing near the announced size is allocated.
      EXPECT_LT(largest_allocation.load(), 64u * 1024) << message.where << ": " << why;
    }
  }
  // 12 types, nested fields counted once per type holding them.
  EXPECT_GT(fields_crafted, 300);
}

// Row 1 of the hostile-network table (docs/RELIABILITY.md): a 61-byte
// job_result_t announcing 2^29 floats made LCM's decoder compute a negative
// byte count and read out of bounds.
TEST(BoundsCheck, TheSixtyOneByteJobResult) {
  const schema::Type& schema = *FindSchemaType("job_result_t");
  int values_field = -1;
  for (int f = 0; f < schema.num_fields; ++f) {
    if (std::string(schema.fields[f].name) == "values") values_field = f;
  }
  ASSERT_GE(values_field, 0);
  SchemaEncoder encoder(3);
  const std::vector<uint8_t> bytes = encoder.Encode(
      schema, job_result_t::getHash(), 0, Target{&schema, values_field, int64_t{1} << 29});
  job_result_t message;
  std::string why;
  EXPECT_FALSE(DecodeExactly(bytes.data(), static_cast<int>(bytes.size()), message, &why));
  EXPECT_NE(why.find("job_result_t.values"), std::string::npos) << why;
}

TEST(BoundsCheck, ArraysAreBoundedByTheProtocolsLimits) {
  BoundsLimits limits;
  limits.max_array_elements = 10;
  const schema::Type& schema = *FindSchemaType("job_result_t");
  job_result_t message{};
  message.run_id = "r";
  message.num_values = 11;
  message.values.assign(11, 1.0f);
  std::vector<uint8_t> bytes(static_cast<size_t>(message.getEncodedSize()));
  message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  EXPECT_NE(CheckEncoding(schema, bytes.data(), bytes.size(), limits).find("limit"),
            std::string::npos);
  EXPECT_EQ(CheckEncoding(schema, bytes.data(), bytes.size()), "");
}

}  // namespace
}  // namespace dynapath::protocol

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
