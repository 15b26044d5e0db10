#pragma once
// Small string helpers shared by the parsers.

#include <string>
#include <string_view>
#include <vector>

namespace dynapath {

std::string ToLower(std::string_view text);
std::string Trim(std::string_view text);
// Splits on `separator`; trims every piece; keeps empty pieces.
std::vector<std::string> Split(std::string_view text, char separator);
// The same, every piece as written (not trimmed).
std::vector<std::string> SplitAsWritten(std::string_view text, char separator);
// A duration for people: "4.2 s", "42 s", "12:03", "1:02:03" (negative: "0.0 s").
std::string FormatDuration(double seconds);

}  // namespace dynapath
