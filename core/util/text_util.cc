#include "dynapath/text_util.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace dynapath {

std::string ToLower(std::string_view text) {
  std::string lower(text);
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return lower;
}

std::string Trim(std::string_view text) {
  size_t begin = 0;
  size_t end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  return std::string(text.substr(begin, end - begin));
}

std::vector<std::string> SplitAsWritten(std::string_view text, char separator) {
  std::vector<std::string> pieces;
  size_t start = 0;
  while (true) {
    const size_t end = text.find(separator, start);
    pieces.emplace_back(text.substr(start, end == std::string_view::npos ? end : end - start));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return pieces;
}

std::vector<std::string> Split(std::string_view text, char separator) {
  std::vector<std::string> pieces = SplitAsWritten(text, separator);
  for (std::string& piece : pieces) piece = Trim(piece);
  return pieces;
}

std::string FormatDuration(double seconds) {
  const long long total = std::llround(std::max(0.0, seconds));
  char buffer[32];
  if (seconds < 9.95) {
    std::snprintf(buffer, sizeof buffer, "%.1f s", std::max(0.0, seconds));
  } else if (total < 60) {
    std::snprintf(buffer, sizeof buffer, "%lld s", total);
  } else if (total < 3600) {
    std::snprintf(buffer, sizeof buffer, "%lld:%02lld", total / 60, total % 60);
  } else {
    std::snprintf(buffer, sizeof buffer, "%lld:%02lld:%02lld", total / 3600, total / 60 % 60,
                  total % 60);
  }
  return buffer;
}

}  // namespace dynapath
