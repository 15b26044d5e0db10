#pragma once
// File-system-safe names for approaches ("A* Oracle" -> "A_Oracle").

#include <string>
#include <string_view>

namespace dynapath::view {

// Letters, digits, '.', '-' and '_' are kept; every run of other characters
// becomes one '_'; leading '.' and '_' and trailing '_' are dropped;
// "approach" if nothing is left.
inline std::string SafeName(std::string_view name) {
  std::string safe;
  for (char c : name) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '.' || c == '-' || c == '_';
    if (keep) {
      safe += c;
    } else if (!safe.empty() && safe.back() != '_') {
      safe += '_';
    }
  }
  while (!safe.empty() && safe.back() == '_') safe.pop_back();
  // No hidden names, no "." or "..".
  const size_t first = safe.find_first_not_of("._");
  if (first == std::string::npos) return "approach";
  safe.erase(0, first);
  return safe;
}

}  // namespace dynapath::view
