#pragma once
// Decoding a received LCM message without trusting it.

#include <exception>

namespace dynapath::protocol {

// Decodes `message` from `data`; true only when the `size` bytes are exactly
// one whole T. LCM's generated decode throws (bad_alloc, length_error) on
// the absurd array lengths of crafted or corrupt bytes: that is false too.
template <class T>
bool DecodeExactly(const void* data, int size, T& message) {
  try {
    return message.decode(data, 0, size) == size;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace dynapath::protocol
