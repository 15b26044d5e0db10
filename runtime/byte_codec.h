#pragma once
// The little-endian byte writer and bounded reader of the project's binary
// files (the policy file, the checkpoint file), their BLAKE2b checksum, and
// a whole-file read that refuses oversized files before reading them.

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "dynapath/result.h"

namespace dynapath::runtime {

class ByteWriter {
 public:
  template <class T>
  void Put(T value) {
    const size_t at = bytes_.size();
    bytes_.resize(at + sizeof(T));
    std::memcpy(bytes_.data() + at, &value, sizeof(T));
  }
  void PutBytes(const void* data, size_t size) {
    const auto* begin = static_cast<const uint8_t*>(data);
    bytes_.insert(bytes_.end(), begin, begin + size);
  }
  // A length (uint32) and the text.
  void PutText(const std::string& text) {
    Put<uint32_t>(static_cast<uint32_t>(text.size()));
    PutBytes(text.data(), text.size());
  }
  std::vector<uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<uint8_t> bytes_;
};

// Reads never past the end: every Get fails instead.
class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}
  template <class T>
  bool Get(T& value) {
    if (left() < sizeof(T)) return false;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return true;
  }
  bool GetView(size_t size, std::string_view& view) {
    if (left() < size) return false;
    view = bytes_.substr(at_, size);
    at_ += size;
    return true;
  }
  // PutText's text, at most `max` bytes long.
  bool GetText(size_t max, std::string& text) {
    uint32_t size = 0;
    std::string_view view;
    if (!Get(size) || size > max || !GetView(size, view)) return false;
    text.assign(view);
    return true;
  }
  size_t left() const { return bytes_.size() - at_; }

 private:
  std::string_view bytes_;
  size_t at_ = 0;
};

inline constexpr size_t kChecksumBytes = 32;  // BLAKE2b-256
// Appends the BLAKE2b of everything written so far.
void AppendChecksum(ByteWriter& out);
// True when the last kChecksumBytes of `bytes` are the BLAKE2b of the rest.
bool ChecksumMatches(std::string_view bytes);

// A 64-bit fingerprint of `bytes` (the first 8 bytes of their BLAKE2b):
// which content a file held, as a checkpoint records it.
uint64_t Fingerprint64(std::string_view bytes);

// The contents of the regular file `path` of at most `max_bytes` bytes;
// errors start with "WHAT PATH: " ("policy file p.pol: not a regular file").
Result<std::string> ReadBoundedFile(const std::string& path, uint64_t max_bytes,
                                    const std::string& what);

}  // namespace dynapath::runtime
