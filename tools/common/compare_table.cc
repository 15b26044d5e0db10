#include "tools/common/compare_table.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "dynapath/text_util.h"

namespace dynapath::cli {
namespace {

// How a metric's differences are shown: times in milliseconds, each with
// the decimals that tell its differences apart.
struct MetricDisplay {
  std::string label;
  double scale;
  int decimals;
};

MetricDisplay DisplayOf(const std::string& metric) {
  if (metric == "AvgSuccessRate") return {"success rate", 1.0, 4};
  if (metric == "AvgPathLength") return {"path length", 1.0, 3};
  if (metric == "InitialTime") return {"initial ms", 1000.0, 3};
  if (metric == "AdaptTimePerStep") return {"adapt ms/step", 1000.0, 4};
  return {metric, 1.0, 4};
}

// `text` scaled, with a sign and fixed decimals; "-0.000" never.
std::string Signed(const std::string& text, const MetricDisplay& display) {
  char* end = nullptr;
  double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str()) return text;
  value *= display.scale;
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%+.*f", display.decimals, value);
  std::string shown = buffer;
  if (shown.find_first_not_of("+-0.") == std::string::npos) shown[0] = ' ';
  return shown;
}

}  // namespace

Result<std::string> CompareTable(const std::string& compare_csv) {
  const std::vector<std::string> lines = Split(compare_csv, '\n');
  if (lines.empty()) return Error{"empty comparison"};
  const std::vector<std::string> header = Split(lines[0], ',');
  auto column = [&](const char* name) -> int {
    const auto found = std::find(header.begin(), header.end(), name);
    return found == header.end() ? -1 : static_cast<int>(found - header.begin());
  };
  const int size = column("Size"), difficulty = column("Difficulty"), metric = column("Metric"),
            pairs = column("Pairs"), mean = column("MeanDifference"), low = column("MeanCILow"),
            high = column("MeanCIHigh"), median = column("Median"), iqm = column("IQM"),
            greater = column("ProbabilityAGreater"), a = column("A"), b = column("B");
  for (const int index :
       {size, difficulty, metric, pairs, mean, low, high, median, iqm, greater, a, b}) {
    if (index < 0) return Error{"not the CSV of dynapath compare (header " + lines[0] + ")"};
  }
  std::vector<std::vector<std::string>> rows{
      {"Configuration", "Metric", "Pairs", "Mean A - B [95% CI]", "Median", "IQM", "P(A > B)"}};
  std::string a_name, b_name;
  for (size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const std::vector<std::string> f = Split(lines[i], ',');
    if (f.size() != header.size()) return Error{"line " + std::to_string(i + 1) + ": ragged row"};
    a_name = f[static_cast<size_t>(a)];
    b_name = f[static_cast<size_t>(b)];
    const auto at = [&](int index) { return f[static_cast<size_t>(index)]; };
    const std::string configuration =
        at(size) == "all" ? "all (stratified)" : at(size) + " " + at(difficulty);
    const MetricDisplay display = DisplayOf(at(metric));
    const double lo = std::strtod(at(low).c_str(), nullptr);
    const double hi = std::strtod(at(high).c_str(), nullptr);
    const bool excludes_zero = lo > 0.0 || hi < 0.0;
    char share[16];
    std::snprintf(share, sizeof share, "%.2f", std::strtod(at(greater).c_str(), nullptr));
    rows.push_back({configuration, display.label, at(pairs),
                    Signed(at(mean), display) + " [" + Signed(at(low), display) + ", " +
                        Signed(at(high), display) + "]" + (excludes_zero ? " *" : "  "),
                    Signed(at(median), display), Signed(at(iqm), display), share});
  }
  std::vector<size_t> width(rows[0].size(), 0);
  for (const auto& row : rows) {
    for (size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  std::string text = "A = " + a_name + ", B = " + b_name +
                     "; paired differences over the repeats (* : the 95% interval excludes 0)\n";
  for (size_t r = 0; r < rows.size(); ++r) {
    std::string line;
    for (size_t c = 0; c < rows[r].size(); ++c) {
      const std::string& cell = rows[r][c];
      const bool right = c >= 2;  // numbers right-aligned
      const std::string pad(width[c] - cell.size(), ' ');
      line += (c ? "  " : "") + (right ? pad + cell : cell + (c + 1 < rows[r].size() ? pad : ""));
    }
    text += line + "\n";
    if (r == 0) {
      std::string rule;
      for (size_t c = 0; c < width.size(); ++c)
        rule += (c ? "  " : "") + std::string(width[c], '-');
      text += rule + "\n";
    }
  }
  return text;
}

}  // namespace dynapath::cli
