#pragma once
// `dynapath compare` on a terminal: its CSV (CompareCsv) as an aligned
// table a person reads, one line per configuration and metric.

#include <string>

#include "dynapath/result.h"

namespace dynapath::cli {

// The table of `compare_csv` (CompareCsv's output): configuration, metric,
// pairs, mean difference A - B with its 95% interval (`*` when the interval
// excludes 0), median, IQM and the share of pairs where A is greater; times
// in milliseconds, every metric with fixed decimals.
Result<std::string> CompareTable(const std::string& compare_csv);

}  // namespace dynapath::cli
