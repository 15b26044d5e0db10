#pragma once
// The summary table `dynapath run` prints to stdout, the same in every mode
// (--local, --embedded, --agents): a result file's CSV (results.csv, or
// summary.csv with --repeats) as aligned columns, numbers to the right,
// under a header and a rule. The values are the file's, unrounded.

#include <string>

namespace dynapath::cli {

// `csv` (one header line, comma-separated fields without quotes) as a table;
// CRLF line ends read as LF.
std::string ResultsTable(const std::string& csv);

}  // namespace dynapath::cli
