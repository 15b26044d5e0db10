#include "tools/common/study_results.h"

#include "dynapath/results_csv.h"
#include "dynapath/text_file.h"
#include "dynapath/text_util.h"

namespace dynapath::cli {
namespace {

// The lines of a file without their newlines (an empty last line dropped).
std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    lines.push_back(text.substr(start, end - start));
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

}  // namespace dynapath::cli
