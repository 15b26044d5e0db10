#pragma once
// The result files of a study: whether a configuration's own files are
// complete, and the study-wide files merged from them.

#include <cstdint>
#include <string>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/result.h"

namespace dynapath::study {

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

// One finished repeat of a configuration: its directory (holding
// results.csv), its repeat number, maze seed and learner seed.
struct RepeatFiles {
  std::string directory;
  int repeat = 1;
  uint64_t seed = 0;
  uint64_t learner_seed = 0;
};

// The header of repeats.csv: Repeat, Seed, LearnerSeed, then results.csv's.
std::string RepeatsCsvHeader();
// Writes OUT/<prefix>repeats.csv (every repeat's results.csv rows, after
// its repeat, maze seed and learner seed) and OUT/<prefix>summary.csv (its
// statistics, SummaryCsv) atomically; summary.csv only `with_summary`
// (its bootstrap takes about a second for a large study).
Status WriteRepeatFiles(const std::vector<RepeatFiles>& repeats, const std::string& out_dir,
                        const std::string& prefix, bool with_summary = true);

// summary.csv of a repeats.csv text: for every configuration (Size,
// Difficulty) and approach, in first-seen order, and each of the metrics
// AvgSuccessRate, AvgPathLength, InitialTime and AdaptTimePerStep: the
// number of repeats, mean, standard deviation, median, interquartile mean
// and the 95% bootstrap intervals of the mean and of the IQM
// (repeat_statistics.h); then, per approach, the same over every
// configuration pooled (Size and Difficulty "all"; the bootstrap stratified
// by configuration). Numbers as in results.csv (%.10g); the bootstrap's
// resamples and seed end every row. An error names the line of a
// malformed row.
Result<std::string> SummaryCsv(const std::string& repeats_csv);

// One point of a sweep's grid: its parameters' values (as text, in the
// order of the names) and its repeats done.
struct SweepPoint {
  std::vector<std::string> values;
  std::vector<RepeatFiles> repeats;
};
// Writes OUT/<prefix>sweep.csv (the swept parameters' columns `names`,
// then repeats.csv's, for every point and repeat) and
// OUT/<prefix>sweep_summary.csv (the same columns before summary.csv's,
// each point's summary; points without a repeat done are left out; only
// `with_summary`).
Status WriteSweepFiles(const std::vector<std::string>& names, const std::vector<SweepPoint>& points,
                       const std::string& out_dir, const std::string& prefix,
                       bool with_summary = true);

// `dynapath compare`: the paired differences A - B of two approaches over
// the repeats of a repeats.csv text (repeat k of A against repeat k of B:
// the same maze, change sequence and learner seed), per configuration and
// metric, then over all configurations (bootstrap stratified by
// configuration): pairs, mean, standard deviation, median and IQM of the
// differences, the 95% bootstrap interval of the mean difference, and the
// share of pairs where A's value is greater (ties count half). An error when
// an approach is missing, A is B, or no repeat has both.
Result<std::string> CompareCsv(const std::string& repeats_csv, const std::string& a,
                               const std::string& b);

}  // namespace dynapath::study
