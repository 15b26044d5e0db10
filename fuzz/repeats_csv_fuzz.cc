// libFuzzer target: the reader of a study's repeats.csv (dynapath compare
// STUDY A B and summary.csv's statistics, study/study_results.h).
// The first byte picks summary.csv or the comparison of approaches X and Y.
// Inputs are capped at 4 KiB: each group's bootstrap draws 10000 resamples.

#include <cstdint>
#include <string>

#include "study/study_results.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > 4096) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  if (data[0] % 2 == 0) {
    (void)dynapath::study::SummaryCsv(text);
  } else {
    (void)dynapath::study::CompareCsv(text, "X", "Y");
  }
  return 0;
}
