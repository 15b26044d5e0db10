#pragma once
// JSON for the study manifest: nlohmann::json (Debian's nlohmann-json3-dev)
// in its ordered form, so members keep their insertion order and manifests
// read and diff well. What we add: a strict parse that refuses duplicate
// keys (nlohmann keeps the last one silently) and reports where the text is
// wrong, and a dump that cannot throw.

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "dynapath/result.h"

namespace dynapath::study {

using Json = nlohmann::ordered_json;

// Parses JSON text (RFC 8259: numbers, escapes and surrogates checked by
// nlohmann). Fails on invalid text (naming the byte), a duplicate key in an
// object, or trailing content.
Result<Json> ParseJson(std::string_view text);

// Indented JSON ending in a newline (indent < 0: one line, no newline).
// Invalid UTF-8 in strings (a file name, say) becomes U+FFFD.
std::string DumpJson(const Json& json, int indent = 2);

// Member `key` of an object, or nullptr (also when `json` is no object).
const Json* Member(const Json& json, const std::string& key);

}  // namespace dynapath::study
