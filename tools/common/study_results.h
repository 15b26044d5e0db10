#pragma once
// The result files of a study: whether a configuration's own files are
// complete, and the study-wide files merged from them.

#include <string>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/result.h"

namespace dynapath::cli {

// True when DIR/results.csv holds one row per approach of `approaches`, in
// that order, for size label `size_label` and difficulty `difficulty_label`,
// and DIR/results_detailed.csv holds approaches x (steps + 1) rows: the
// configuration ran to its end (`dynapath run` rewrites both files after
// every approach, so an interrupted run leaves fewer rows).
bool ConfigurationComplete(const std::string& directory, const std::vector<Approach>& approaches,
                           const std::string& size_label, const std::string& difficulty_label,
                           int steps);

// Writes OUT/<prefix>results.csv and OUT/<prefix>results_detailed.csv
// (atomically): the header once, then the rows of each directory's files in
// the order given. With no directory, the files hold the header only.
// Both files are tried; the error names each one not written, with the reason.
Status MergeResultFiles(const std::vector<std::string>& directories, const std::string& out_dir,
                        const std::string& prefix);

}  // namespace dynapath::cli
