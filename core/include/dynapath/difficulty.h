#pragma once
// The three maze difficulties of SPEC section 1.

#include <optional>
#include <string>

namespace dynapath {

enum class Difficulty { kEasy = 0, kMedium = 1, kHard = 2 };
inline constexpr Difficulty kAllDifficulties[] = {Difficulty::kEasy, Difficulty::kMedium,
                                                  Difficulty::kHard};

struct CellProbabilities {
  double free;
  double obstacle;
  double station;
};

CellProbabilities ProbabilitiesOf(Difficulty difficulty);

// "Easy", "Medium", "Hard": the spelling of the result files.
std::string DifficultyName(Difficulty difficulty);

// Case-insensitive parse of a DifficultyName ("easy", "medium", "hard").
std::optional<Difficulty> ParseDifficulty(const std::string& text);

// The report's seed for a difficulty: 50 + its index (50, 51, 52).
unsigned ReportSeed(Difficulty difficulty);

// The report's edge case: the hard 50x50 maze of seed 102, whose top-left
// quadrant holds no station.
inline constexpr unsigned kEdgeCaseSeed = 102;

}  // namespace dynapath
