#include "dynapath/change_sequence.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "dynapath/text_file.h"

namespace dynapath {
namespace {

constexpr int kVersion = 2;

std::string StepText(long long t) { return "time step " + std::to_string(t); }

// "cell 417 (row 8, column 17)".
std::string CellText(const Grid& grid, int cell) {
  return "cell " + std::to_string(cell) + " (row " + std::to_string(grid.RowOf(cell)) +
         ", column " + std::to_string(grid.ColOf(cell)) + ")";
}

std::optional<uint64_t> ParseFingerprint(const std::string& text) {
  if (text.size() != 16) return std::nullopt;
  uint64_t value = 0;
  for (char c : text) {
    int digit = 0;
    if (c >= '0' && c <= '9') {
      digit = c - '0';
    } else if (c >= 'a' && c <= 'f') {
      digit = c - 'a' + 10;
    } else if (c >= 'A' && c <= 'F') {
      digit = c - 'A' + 10;
    } else {
      return std::nullopt;
    }
    value = value << 4 | static_cast<uint64_t>(digit);
  }
  return value;
}

}  // namespace

void ApplyChanges(const ChangeStep& step, Grid& grid) {
  for (const CellChange& change : step.changes) grid.set(change.cell, change.code);
}

uint64_t MazeFingerprint(const Grid& grid) {
  uint64_t hash = 0xcbf29ce484222325ULL;  // FNV-1a 64
  auto add = [&hash](uint8_t byte) {
    hash ^= byte;
    hash *= 0x100000001b3ULL;
  };
  for (const int side : {grid.rows(), grid.cols()}) {
    const uint32_t value = static_cast<uint32_t>(side);
    for (int shift = 0; shift < 32; shift += 8) add(static_cast<uint8_t>(value >> shift));
  }
  for (uint8_t code : grid.codes()) add(code);
  return hash;
}

std::string FingerprintText(uint64_t fingerprint) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(fingerprint));
  return text;
}

std::string ChangesToText(const ChangeSequence& sequence, const Grid& initial) {
  std::ostringstream out;
  out << "dynapath-changes " << kVersion << ' ' << initial.rows() << ' ' << initial.cols() << ' '
      << sequence.steps.size() << ' ' << FingerprintText(MazeFingerprint(initial)) << '\n';
  for (const ChangeStep& step : sequence.steps) {
    out << step.requested_moves << ' ' << step.changes.size();
    for (const CellChange& change : step.changes) {
      out << ' ' << change.cell << ' ' << static_cast<int>(change.code);
    }
    out << '\n';
  }
  return out.str();
}

Result<ChangeSequence> ChangesFromText(const std::string& text, int rows, int cols,
                                       ChangeFileHeader* header) {
  std::istringstream in(text);
  std::string magic;
  int version = 0;
  long long file_rows = 0, file_cols = 0, steps = 0;
  if (!(in >> magic >> version >> file_rows >> file_cols >> steps) || magic != "dynapath-changes") {
    return Error::Corrupt(
        "not a change file (expected a 'dynapath-changes 2 <rows> <cols> <steps> <fingerprint>' "
        "header)");
  }
  if (version != 1 && version != kVersion) {
    return Error::Corrupt("unsupported change-file version " + std::to_string(version) +
                          " (this build reads 1 and 2)");
  }
  std::optional<uint64_t> fingerprint;
  if (version >= 2) {
    std::string word;
    in >> word;
    fingerprint = ParseFingerprint(word);
    if (!fingerprint) {
      return Error::Corrupt("bad maze fingerprint '" + word.substr(0, 40) +
                            "' in the header (16 hex digits)");
    }
  }
  if (file_rows != rows || file_cols != cols) {
    return Error::Corrupt("the change file is for a " + std::to_string(file_rows) + "x" +
                          std::to_string(file_cols) + " maze, the maze is " + std::to_string(rows) +
                          "x" + std::to_string(cols));
  }
  constexpr long long kMaxSteps = 1'000'000;
  if (steps < 0 || steps > kMaxSteps)
    return Error::Corrupt("bad number of time steps " + std::to_string(steps));
  // Every step takes at least 4 bytes ("0 0\n") and every change 4 (" 1 0"):
  // what is reserved up front never exceeds what the text can hold.
  const size_t most = text.size() / 4 + 1;
  const long long cells = static_cast<long long>(rows) * cols;
  ChangeSequence sequence;
  sequence.steps.reserve(std::min(static_cast<size_t>(steps), most));
  for (long long t = 0; t < steps; ++t) {
    ChangeStep& step = sequence.steps.emplace_back();
    long long count = 0;
    if (!(in >> step.requested_moves >> count)) {
      return Error::Corrupt(StepText(t + 1) + ": missing or bad counts");
    }
    if (step.requested_moves < 0 || count < 0 || count > 2 * cells) {
      return Error::Corrupt(StepText(t + 1) + ": bad counts");
    }
    step.changes.reserve(std::min(static_cast<size_t>(count), most));
    for (long long k = 0; k < count; ++k) {
      long long cell = 0;
      int code = 0;
      if (!(in >> cell >> code)) return Error::Corrupt(StepText(t + 1) + ": truncated");
      if (cell < 0 || cell >= cells) {
        return Error::Corrupt(StepText(t + 1) + ": cell " + std::to_string(cell) +
                              " outside the maze");
      }
      if (code < 0 || code > 2) {
        return Error::Corrupt(StepText(t + 1) + ": bad cell code " + std::to_string(code));
      }
      step.changes.push_back({static_cast<int>(cell), static_cast<Cell>(code)});
    }
  }
  std::string trailing;
  if (in >> trailing) return Error::Corrupt("unexpected data after the last time step");
  if (header != nullptr) {
    *header = ChangeFileHeader{version, rows, cols, fingerprint};
  }
  return sequence;
}

Status CheckChangesFit(const ChangeSequence& sequence, const Grid& initial) {
  Grid grid = initial;
  for (size_t t = 0; t < sequence.steps.size(); ++t) {
    const std::vector<CellChange>& changes = sequence.steps[t].changes;
    for (size_t k = 0; k < changes.size(); ++k) {
      const CellChange& change = changes[k];
      if (change.cell < 0 || change.cell >= grid.size()) {
        return Error::Corrupt(StepText(static_cast<long long>(t) + 1) + ", change " +
                              std::to_string(k + 1) + ": cell " + std::to_string(change.cell) +
                              " outside the maze");
      }
      const Cell now = grid.at(change.cell);
      const char* wrong = nullptr;
      if (now == Cell::kStation) {
        wrong = "would remove the station there";
      } else if (change.code == Cell::kStation) {
        wrong = "would create a station";
      } else if (change.code == Cell::kFree && now != Cell::kObstacle) {
        wrong = "moves an obstacle away from a cell that holds none";
      } else if (change.code == Cell::kObstacle && now != Cell::kFree) {
        wrong = "puts an obstacle on a cell that holds one already";
      }
      if (wrong != nullptr) {
        return Error::Corrupt(StepText(static_cast<long long>(t) + 1) + ", change " +
                              std::to_string(k + 1) + " at " + CellText(grid, change.cell) + ": " +
                              wrong + " (is the change file made for this maze?)");
      }
      grid.set(change.cell, change.code);
    }
  }
  return Ok{};
}

Status SaveChanges(const ChangeSequence& sequence, const Grid& initial, const std::string& path) {
  return WriteTextFileAtomically(path, ChangesToText(sequence, initial));
}

Result<ChangeSequence> LoadChanges(const std::string& path, int rows, int cols,
                                   ChangeFileHeader* header) {
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  Result<ChangeSequence> sequence = ChangesFromText(*text, rows, cols, header);
  if (!sequence) return sequence.error().Prefixed(path + ": ");
  return sequence;
}

}  // namespace dynapath
