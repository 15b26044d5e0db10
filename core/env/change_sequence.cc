#include "dynapath/change_sequence.h"

#include <sstream>

#include "dynapath/text_file.h"

namespace dynapath {

void ApplyChanges(const ChangeStep& step, Grid& grid) {
  for (const CellChange& change : step.changes) grid.set(change.cell, change.code);
}

std::string ChangesToText(const ChangeSequence& sequence, int rows, int cols) {
  std::ostringstream out;
  out << "dynapath-changes 1 " << rows << ' ' << cols << ' ' << sequence.steps.size() << '\n';
  for (const ChangeStep& step : sequence.steps) {
    out << step.requested_moves << ' ' << step.changes.size();
    for (const CellChange& change : step.changes) {
      out << ' ' << change.cell << ' ' << static_cast<int>(change.code);
    }
    out << '\n';
  }
  return out.str();
}

Result<ChangeSequence> ChangesFromText(const std::string& text, int rows, int cols) {
  std::istringstream in(text);
  std::string magic;
  int version = 0;
  long long file_rows = 0, file_cols = 0, steps = 0;
  if (!(in >> magic >> version >> file_rows >> file_cols >> steps) || magic != "dynapath-changes") {
    return Error::Corrupt(
        "not a change file (expected a 'dynapath-changes 1 <rows> <cols> <steps>' header)");
  }
  if (version != 1)
    return Error::Corrupt("unsupported change-file version " + std::to_string(version));
  if (file_rows != rows || file_cols != cols) {
    return Error::Corrupt("the change file is for a " + std::to_string(file_rows) + "x" +
                          std::to_string(file_cols) + " maze, the maze is " + std::to_string(rows) +
                          "x" + std::to_string(cols));
  }
  constexpr long long kMaxSteps = 1'000'000;
  if (steps < 0 || steps > kMaxSteps)
    return Error::Corrupt("bad number of time steps " + std::to_string(steps));
  const long long cells = static_cast<long long>(rows) * cols;
  ChangeSequence sequence;
  sequence.steps.resize(static_cast<size_t>(steps));
  for (long long t = 0; t < steps; ++t) {
    ChangeStep& step = sequence.steps[static_cast<size_t>(t)];
    long long count = 0;
    if (!(in >> step.requested_moves >> count)) {
      return Error::Corrupt("time step " + std::to_string(t + 1) + ": missing or bad counts");
    }
    if (step.requested_moves < 0 || count < 0 || count > 2 * cells) {
      return Error::Corrupt("time step " + std::to_string(t + 1) + ": bad counts");
    }
    step.changes.resize(static_cast<size_t>(count));
    for (CellChange& change : step.changes) {
      long long cell = 0;
      int code = 0;
      if (!(in >> cell >> code))
        return Error::Corrupt("time step " + std::to_string(t + 1) + ": truncated");
      if (cell < 0 || cell >= cells) {
        return Error::Corrupt("time step " + std::to_string(t + 1) + ": cell " +
                              std::to_string(cell) + " outside the maze");
      }
      if (code < 0 || code > 2) {
        return Error::Corrupt("time step " + std::to_string(t + 1) + ": bad cell code " +
                              std::to_string(code));
      }
      change.cell = static_cast<int>(cell);
      change.code = static_cast<Cell>(code);
    }
  }
  std::string trailing;
  if (in >> trailing) return Error::Corrupt("unexpected data after the last time step");
  return sequence;
}

Status SaveChanges(const ChangeSequence& sequence, int rows, int cols, const std::string& path) {
  return WriteTextFileAtomically(path, ChangesToText(sequence, rows, cols));
}

Result<ChangeSequence> LoadChanges(const std::string& path, int rows, int cols) {
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  Result<ChangeSequence> sequence = ChangesFromText(*text, rows, cols);
  if (!sequence) return sequence.error().Prefixed(path + ": ");
  return sequence;
}

}  // namespace dynapath
