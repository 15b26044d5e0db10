#include "study/study_results.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iterator>

#include "dynapath/results_csv.h"
#include "dynapath/text_file.h"
#include "dynapath/text_util.h"
#include "study/repeat_statistics.h"

namespace dynapath::study {
namespace {

// The lines of a file without their newlines (an empty last line dropped);
// CRLF line ends (a file saved by a Windows editor or spreadsheet) read as
// LF ones.
std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const size_t length = end - start - (end > start && text[end - 1] == '\r' ? 1 : 0);
    lines.push_back(text.substr(start, length));
    start = end + 1;
  }
  return lines;
}

std::string Header(const std::string& csv) { return csv.substr(0, csv.find('\n')); }

}  // namespace

bool ConfigurationComplete(const std::string& directory, const std::vector<Approach>& approaches,
                           const std::string& size_label, const std::string& difficulty_label,
                           int steps) {
  Result<std::string> summary = ReadTextFile(directory + "/results.csv");
  Result<std::string> detailed = ReadTextFile(directory + "/results_detailed.csv");
  if (!summary || !detailed) return false;
  const std::vector<std::string> rows = Lines(*summary);
  if (rows.size() != approaches.size() + 1 || rows[0] != Header(SummaryResultsCsv({}))) {
    return false;
  }
  for (size_t i = 0; i < approaches.size(); ++i) {
    const std::vector<std::string> fields = Split(rows[i + 1], ',');
    if (fields.size() != 7 || fields[0] != ApproachName(approaches[i]) || fields[1] != size_label ||
        fields[2] != difficulty_label) {
      return false;
    }
  }
  const std::vector<std::string> detail_rows = Lines(*detailed);
  return detail_rows.size() == approaches.size() * static_cast<size_t>(steps + 1) + 1 &&
         detail_rows[0] == Header(DetailedResultsCsv({}));
}

Status MergeResultFiles(const std::vector<std::string>& directories, const std::string& out_dir,
                        const std::string& prefix) {
  // Both files are tried; the error names every one not written.
  std::string failures;
  auto failed = [&](const Error& error) {
    failures += (failures.empty() ? "" : "; ") + error.message;
  };
  for (const auto& [file, header] :
       {std::pair<std::string, std::string>{"results.csv", SummaryResultsCsv({})},
        std::pair<std::string, std::string>{"results_detailed.csv", DetailedResultsCsv({})}}) {
    std::string merged = header;
    bool read = true;
    for (const std::string& directory : directories) {
      Result<std::string> text = ReadTextFile(directory + "/" + file);
      if (!text) {
        failed(text.error().Prefixed(out_dir + "/" + prefix + file + " not written: "));
        read = false;
        break;
      }
      const size_t body = text->find('\n');
      if (body != std::string::npos) merged += text->substr(body + 1);
    }
    if (!read) continue;
    if (Status status = WriteTextFileAtomically(out_dir + "/" + prefix + file, merged); !status) {
      failed(status.error());
    }
  }
  if (!failures.empty()) return Error::Io(failures);
  return Ok{};
}

}  // namespace dynapath::study

namespace dynapath::study {
namespace {

std::string Number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

// The metrics of summary.csv, each a column of results.csv.
struct Metric {
  const char* name;
  int column;  // in a repeats.csv row
};
constexpr Metric kMetrics[] = {
    {"AvgSuccessRate", 8}, {"AvgPathLength", 9}, {"InitialTime", 6}, {"AdaptTimePerStep", 7}};
constexpr int kRepeatsColumns = 10;

}  // namespace

std::string RepeatsCsvHeader() {
  return "Repeat,Seed,LearnerSeed," + Header(SummaryResultsCsv({}));
}

namespace {

// repeats.csv's text of `repeats`; an error names `file`.
Result<std::string> RepeatsCsv(const std::vector<RepeatFiles>& repeats, const std::string& file) {
  std::string csv = RepeatsCsvHeader() + "\n";
  for (const RepeatFiles& repeat : repeats) {
    Result<std::string> text = ReadTextFile(repeat.directory + "/results.csv");
    if (!text) return text.error().Prefixed(file + " not written: ");
    const std::vector<std::string> lines = Lines(*text);
    for (size_t i = 1; i < lines.size(); ++i) {
      csv += std::to_string(repeat.repeat) + "," + std::to_string(repeat.seed) + "," +
             std::to_string(repeat.learner_seed) + "," + lines[i] + "\n";
    }
  }
  return csv;
}

// Every line of `csv` after the first, each after `prefix`.
std::string PrefixedRows(const std::string& csv, const std::string& prefix) {
  std::string rows;
  const std::vector<std::string> lines = Lines(csv);
  for (size_t i = 1; i < lines.size(); ++i) rows += prefix + lines[i] + "\n";
  return rows;
}

}  // namespace

Status WriteSweepFiles(const std::vector<std::string>& names, const std::vector<SweepPoint>& points,
                       const std::string& out_dir, const std::string& prefix, bool with_summary) {
  std::string columns;
  for (const std::string& name : names) columns += name + ",";
  std::string sweep = columns + RepeatsCsvHeader() + "\n";
  Result<std::string> empty_summary = SummaryCsv(RepeatsCsvHeader() + "\n");
  if (!empty_summary) return empty_summary.error();
  std::string summaries = columns + Lines(*empty_summary)[0] + "\n";
  const std::string file = out_dir + "/" + prefix + "sweep.csv";
  for (const SweepPoint& point : points) {
    if (point.repeats.empty()) continue;
    std::string values;
    for (const std::string& value : point.values) values += value + ",";
    Result<std::string> csv = RepeatsCsv(point.repeats, file);
    if (!csv) return csv.error();
    sweep += PrefixedRows(*csv, values);
    if (!with_summary) continue;
    Result<std::string> summary = SummaryCsv(*csv);
    if (!summary) return summary.error().Prefixed(out_dir + "/" + prefix + "sweep_summary.csv: ");
    summaries += PrefixedRows(*summary, values);
  }
  if (Status status = WriteTextFileAtomically(file, sweep); !status) return status;
  if (!with_summary) return Ok{};
  return WriteTextFileAtomically(out_dir + "/" + prefix + "sweep_summary.csv", summaries);
}

Status WriteRepeatFiles(const std::vector<RepeatFiles>& repeats, const std::string& out_dir,
                        const std::string& prefix, bool with_summary) {
  Result<std::string> repeats_csv = RepeatsCsv(repeats, out_dir + "/" + prefix + "repeats.csv");
  if (!repeats_csv) return repeats_csv.error();
  const std::string& csv = *repeats_csv;
  if (!with_summary) return WriteTextFileAtomically(out_dir + "/" + prefix + "repeats.csv", csv);
  Result<std::string> summary = SummaryCsv(csv);
  if (!summary) return summary.error().Prefixed(out_dir + "/" + prefix + "summary.csv: ");
  if (Status status = WriteTextFileAtomically(out_dir + "/" + prefix + "repeats.csv", csv);
      !status) {
    return status;
  }
  return WriteTextFileAtomically(out_dir + "/" + prefix + "summary.csv", *summary);
}

namespace {

// (configuration, approach) -> the metrics' values over repeats, in order,
// with the repeat numbers.
struct Group {
  std::string size, difficulty, approach;
  std::vector<std::vector<double>> values = std::vector<std::vector<double>>(4);
  std::vector<long long> repeats;
};

struct RepeatsTable {
  std::vector<Group> groups;
  std::vector<std::string> approaches;  // first-seen order
};

Result<RepeatsTable> ParseRepeats(const std::string& repeats_csv) {
  const std::vector<std::string> lines = Lines(repeats_csv);
  if (lines.empty() || lines[0] != RepeatsCsvHeader()) {
    return Error{"line 1: expected the header " + RepeatsCsvHeader()};
  }
  RepeatsTable table;
  std::vector<Group>& groups = table.groups;
  std::vector<std::string>& approaches = table.approaches;
  for (size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> fields = Split(lines[i], ',');
    const std::string where = "line " + std::to_string(i + 1) + ": ";
    if (fields.size() != kRepeatsColumns) {
      return Error{where + "expected " + std::to_string(kRepeatsColumns) + " fields, got " +
                   std::to_string(fields.size())};
    }
    const std::string& approach = fields[3];
    auto group = std::find_if(groups.begin(), groups.end(), [&](const Group& g) {
      return g.approach == approach && g.size == fields[4] && g.difficulty == fields[5];
    });
    if (group == groups.end()) {
      Group added;
      added.size = fields[4];
      added.difficulty = fields[5];
      added.approach = approach;
      groups.push_back(std::move(added));
      group = groups.end() - 1;
    }
    if (std::find(approaches.begin(), approaches.end(), approach) == approaches.end()) {
      approaches.push_back(approach);
    }
    char* end = nullptr;
    const long long repeat = std::strtoll(fields[0].c_str(), &end, 10);
    if (fields[0].empty() || end != fields[0].c_str() + fields[0].size() || repeat < 1) {
      return Error{where + "Repeat: not a repeat number: '" + fields[0] + "'"};
    }
    if (std::find(group->repeats.begin(), group->repeats.end(), repeat) != group->repeats.end()) {
      return Error{where + "repeat " + fields[0] + " of " + approach + " on " + fields[4] + " " +
                   fields[5] + " is there twice"};
    }
    group->repeats.push_back(repeat);
    for (size_t m = 0; m < std::size(kMetrics); ++m) {
      const std::string& text = fields[static_cast<size_t>(kMetrics[m].column)];
      const double value = std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size()) {
        return Error{where + kMetrics[m].name + ": not a number: '" + text + "'"};
      }
      group->values[m].push_back(value);
    }
  }
  return table;
}

}  // namespace

Result<std::string> SummaryCsv(const std::string& repeats_csv) {
  Result<RepeatsTable> table = ParseRepeats(repeats_csv);
  if (!table) return table.error();
  const std::vector<Group>& groups = table->groups;
  const std::vector<std::string>& approaches = table->approaches;
  std::string csv =
      "Approach,Size,Difficulty,Metric,Repeats,Mean,Std,Median,IQM,MeanCILow,MeanCIHigh,"
      "IQMCILow,IQMCIHigh,Resamples,BootstrapSeed\n";
  auto row = [&](const std::string& approach, const std::string& size,
                 const std::string& difficulty, const char* metric,
                 const std::vector<std::vector<double>>& strata) {
    const SampleSummary s = Summarize(strata);
    csv += approach + "," + size + "," + difficulty + "," + metric + "," + std::to_string(s.count) +
           "," + Number(s.mean) + "," + Number(s.std) + "," + Number(s.median) + "," +
           Number(s.iqm) + "," + Number(s.mean_ci.low) + "," + Number(s.mean_ci.high) + "," +
           Number(s.iqm_ci.low) + "," + Number(s.iqm_ci.high) + "," +
           std::to_string(kBootstrapResamples) + "," + std::to_string(kBootstrapSeed) + "\n";
  };
  for (const Group& group : groups) {
    for (size_t m = 0; m < std::size(kMetrics); ++m) {
      row(group.approach, group.size, group.difficulty, kMetrics[m].name, {group.values[m]});
    }
  }
  // Over all configurations: one stratum per configuration.
  for (const std::string& approach : approaches) {
    for (size_t m = 0; m < std::size(kMetrics); ++m) {
      std::vector<std::vector<double>> strata;
      for (const Group& group : groups) {
        if (group.approach == approach) strata.push_back(group.values[m]);
      }
      if (strata.size() > 1) row(approach, "all", "all", kMetrics[m].name, strata);
    }
  }
  return csv;
}

Result<std::string> CompareCsv(const std::string& repeats_csv, const std::string& a,
                               const std::string& b) {
  if (a == b) return Error{"compare two different approaches, not " + a + " with itself"};
  Result<RepeatsTable> table = ParseRepeats(repeats_csv);
  if (!table) return table.error();
  for (const std::string& name : {a, b}) {
    if (std::find(table->approaches.begin(), table->approaches.end(), name) ==
        table->approaches.end()) {
      std::string known;
      for (const std::string& approach : table->approaches) {
        known += (known.empty() ? "" : ", ") + approach;
      }
      return Error{"approach '" + name + "' has no repeats here (there are: " + known + ")"};
    }
  }
  // Per configuration (in first-seen order) and metric: the differences of
  // the repeats both approaches have, in A's order.
  struct Pairs {
    std::string size, difficulty;
    std::vector<std::vector<double>> differences = std::vector<std::vector<double>>(4);
    std::vector<std::vector<double>> greater = std::vector<std::vector<double>>(4);
  };
  std::vector<Pairs> configurations;
  for (const Group& x : table->groups) {
    if (x.approach != a) continue;
    const auto y = std::find_if(table->groups.begin(), table->groups.end(), [&](const Group& g) {
      return g.approach == b && g.size == x.size && g.difficulty == x.difficulty;
    });
    if (y == table->groups.end()) continue;
    Pairs pairs;
    pairs.size = x.size;
    pairs.difficulty = x.difficulty;
    for (size_t i = 0; i < x.repeats.size(); ++i) {
      const auto j = std::find(y->repeats.begin(), y->repeats.end(), x.repeats[i]);
      if (j == y->repeats.end()) continue;
      const size_t k = static_cast<size_t>(j - y->repeats.begin());
      for (size_t m = 0; m < std::size(kMetrics); ++m) {
        const double va = x.values[m][i], vb = y->values[m][k];
        pairs.differences[m].push_back(va - vb);
        pairs.greater[m].push_back(va > vb ? 1.0 : va == vb ? 0.5 : 0.0);
      }
    }
    if (!pairs.differences[0].empty()) configurations.push_back(std::move(pairs));
  }
  if (configurations.empty()) {
    return Error{"no repeat of " + a + " has a repeat of " + b + " on the same maze to pair with"};
  }
  std::string csv =
      "A,B,Size,Difficulty,Metric,Pairs,MeanDifference,Std,Median,IQM,MeanCILow,MeanCIHigh,"
      "ProbabilityAGreater,Resamples,BootstrapSeed\n";
  auto row = [&](const std::string& size, const std::string& difficulty, const char* metric,
                 const std::vector<std::vector<double>>& strata,
                 const std::vector<double>& greater) {
    const SampleSummary s = Summarize(strata);
    csv += a + "," + b + "," + size + "," + difficulty + "," + metric + "," +
           std::to_string(s.count) + "," + Number(s.mean) + "," + Number(s.std) + "," +
           Number(s.median) + "," + Number(s.iqm) + "," + Number(s.mean_ci.low) + "," +
           Number(s.mean_ci.high) + "," + Number(Mean(greater)) + "," +
           std::to_string(kBootstrapResamples) + "," + std::to_string(kBootstrapSeed) + "\n";
  };
  for (const Pairs& pairs : configurations) {
    for (size_t m = 0; m < std::size(kMetrics); ++m) {
      row(pairs.size, pairs.difficulty, kMetrics[m].name, {pairs.differences[m]}, pairs.greater[m]);
    }
  }
  if (configurations.size() > 1) {
    for (size_t m = 0; m < std::size(kMetrics); ++m) {
      std::vector<std::vector<double>> strata;
      std::vector<double> greater;
      for (const Pairs& pairs : configurations) {
        strata.push_back(pairs.differences[m]);
        greater.insert(greater.end(), pairs.greater[m].begin(), pairs.greater[m].end());
      }
      row("all", "all", kMetrics[m].name, strata, greater);
    }
  }
  return csv;
}

}  // namespace dynapath::study
