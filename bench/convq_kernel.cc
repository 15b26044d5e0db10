// convQ's settling kernel (core/plan/convq_values.h) alone, timed, and its
// values written out: the C++ side of bench/convq_torch_bench.py, which
// computes the same values with dense torch operations and compares.
//
//   convq_kernel IN OUT REPEATS
//
// IN: a text line "rows cols steps", then steps + 1 grids of rows * cols
// bytes (codes 0 obstacle, 1 free, 2 station), the maze at time steps 0 to
// steps. The model is the shipped one (ShippedConvQModel). Solve on grid 0
// REPEATS times; then Repair with the cells that differ between grid k-1
// and grid k, for k = 1..steps. Prints "solve SECONDS" per repeat and
// "repair CHANGED SECONDS" per step. OUT: the shifted values U of every
// cell (doubles, row-major; 0 off free cells) after the Solve, then after
// the last Repair.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "core/plan/convq_values.h"
#include "dynapath/convq_model.h"
#include "dynapath/grid.h"

namespace {

void WriteValues(std::ofstream& out, const dynapath::ConvQValues& values,
                 const dynapath::Grid& grid) {
  std::vector<double> u(static_cast<size_t>(grid.size()), 0.0);
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (grid.at(cell) == dynapath::Cell::kFree) u[static_cast<size_t>(cell)] = values.Shifted(cell);
  }
  out.write(reinterpret_cast<const char*>(u.data()),
            static_cast<std::streamsize>(u.size() * sizeof(double)));
}

}  // namespace

int main(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  if (argc != 4) {
    std::fprintf(stderr, "usage: convq_kernel IN OUT REPEATS\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "convq_kernel: cannot open %s\n", argv[1]);
    return 2;
  }
  int rows = 0, cols = 0, steps = -1;
  std::string header;
  if (!std::getline(in, header) ||
      std::sscanf(header.c_str(), "%d %d %d", &rows, &cols, &steps) != 3 || rows < 1 || cols < 1 ||
      rows > 8192 || cols > 8192 || steps < 0 || steps > 100000) {
    std::fprintf(stderr, "convq_kernel: %s: bad header\n", argv[1]);
    return 2;
  }
  const int repeats = std::atoi(argv[3]);
  if (repeats < 1) {
    std::fprintf(stderr, "convq_kernel: REPEATS must be at least 1\n");
    return 2;
  }
  const size_t n = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  std::vector<char> codes(n);
  const auto read_grid = [&](dynapath::Grid& grid, std::vector<int>* changed) {
    if (!in.read(codes.data(), static_cast<std::streamsize>(n))) return false;
    for (size_t i = 0; i < n; ++i) {
      if (codes[i] < 0 || codes[i] > 2) return false;
      const auto cell = static_cast<dynapath::Cell>(codes[i]);
      if (changed && grid.at(static_cast<int>(i)) != cell) changed->push_back(static_cast<int>(i));
      grid.set(static_cast<int>(i), cell);
    }
    return true;
  };
  dynapath::Grid grid(rows, cols);
  if (!read_grid(grid, nullptr)) {
    std::fprintf(stderr, "convq_kernel: %s: short file or bad code\n", argv[1]);
    return 2;
  }
  dynapath::ConvQValues values(dynapath::ShippedConvQModel());
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    values.Solve(grid);
    std::printf("solve %.9f\n", std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::ofstream out(argv[2], std::ios::binary);
  WriteValues(out, values, grid);
  std::vector<int> changed;
  for (int k = 1; k <= steps; ++k) {
    changed.clear();
    if (!read_grid(grid, &changed)) {
      std::fprintf(stderr, "convq_kernel: %s: short file or bad code\n", argv[1]);
      return 2;
    }
    const auto start = Clock::now();
    values.Repair(grid, changed);
    std::printf("repair %zu %.9f\n", changed.size(),
                std::chrono::duration<double>(Clock::now() - start).count());
  }
  WriteValues(out, values, grid);
  return out ? 0 : 1;
}
