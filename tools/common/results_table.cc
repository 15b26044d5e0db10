#include "tools/common/results_table.h"

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "dynapath/text_util.h"

namespace dynapath::cli {
namespace {

bool IsNumber(const std::string& text) {
  if (text.empty()) return false;
  char* end = nullptr;
  (void)std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

}  // namespace

std::string ResultsTable(const std::string& csv) {
  std::vector<std::vector<std::string>> rows;
  for (std::string line : Split(csv, '\n')) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) rows.push_back(Split(line, ','));
  }
  if (rows.empty()) return "";
  size_t columns = 0;
  for (const auto& row : rows) columns = std::max(columns, row.size());
  std::vector<size_t> widths(columns, 0);
  // A column is numeric when every value below the header is a number.
  std::vector<bool> numeric(columns, rows.size() > 1);
  for (size_t r = 0; r < rows.size(); ++r) {
    for (size_t c = 0; c < rows[r].size(); ++c) {
      widths[c] = std::max(widths[c], rows[r][c].size());
      if (r > 0 && !IsNumber(rows[r][c])) numeric[c] = false;
    }
  }
  std::string table;
  auto add_row = [&](const std::vector<std::string>& row) {
    std::string line;
    for (size_t c = 0; c < columns; ++c) {
      const std::string cell = c < row.size() ? row[c] : "";
      const std::string pad(widths[c] - cell.size(), ' ');
      line += (c == 0 ? "" : "  ") + (numeric[c] ? pad + cell : cell + pad);
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    table += line + "\n";
  };
  add_row(rows[0]);
  std::vector<std::string> rule;
  for (size_t c = 0; c < columns; ++c) rule.push_back(std::string(widths[c], '-'));
  add_row(rule);
  for (size_t r = 1; r < rows.size(); ++r) add_row(rows[r]);
  return table;
}

}  // namespace dynapath::cli
