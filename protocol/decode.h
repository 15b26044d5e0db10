#pragma once
// Decoding a received LCM message without trusting it: every decode of
// bytes from the network or a log goes through DecodeExactly.

#include <exception>
#include <string>

#include "protocol/bounds.h"

namespace dynapath::protocol {

// Decodes `message` from `data`; true only when the `size` bytes are exactly
// one whole T. The bounds check (bounds.h) runs first, so LCM's generated
// decode never sees a count or length the bytes cannot hold; `why` (when not
// null) says what was wrong. The try is a backstop: the check leaves the
// generated decode nothing to throw on.
template <class T>
bool DecodeExactly(const void* data, int size, T& message, std::string* why = nullptr) {
  static const schema::Type* const type = FindSchemaType(T::getTypeName());
  if (type == nullptr || size < 0) {
    if (why != nullptr) *why = "no schema for this type";
    return false;
  }
  if (std::string error =
          CheckEncoding(*type, static_cast<const uint8_t*>(data), static_cast<size_t>(size));
      !error.empty()) {
    if (why != nullptr) *why = std::move(error);
    return false;
  }
  try {
    if (message.decode(data, 0, size) == size) return true;
    if (why != nullptr) *why = "not a " + std::string(T::getTypeName());
  } catch (const std::exception& e) {
    if (why != nullptr) *why = e.what();
  }
  return false;
}

}  // namespace dynapath::protocol
