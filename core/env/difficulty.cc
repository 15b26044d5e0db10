#include "dynapath/difficulty.h"

#include "dynapath/text_util.h"

namespace dynapath {

CellProbabilities ProbabilitiesOf(Difficulty difficulty) {
  switch (difficulty) {
    case Difficulty::kEasy:
      return {0.8, 0.18, 0.02};
    case Difficulty::kMedium:
      return {0.7, 0.29, 0.01};
    case Difficulty::kHard:
      return {0.6, 0.395, 0.005};
  }
  return {0.8, 0.18, 0.02};
}

std::string DifficultyName(Difficulty difficulty) {
  switch (difficulty) {
    case Difficulty::kEasy:
      return "Easy";
    case Difficulty::kMedium:
      return "Medium";
    case Difficulty::kHard:
      return "Hard";
  }
  return "?";
}

std::optional<Difficulty> ParseDifficulty(const std::string& text) {
  const std::string lower = ToLower(text);
  for (Difficulty difficulty : kAllDifficulties) {
    if (ToLower(DifficultyName(difficulty)) == lower) return difficulty;
  }
  return std::nullopt;
}

unsigned ReportSeed(Difficulty difficulty) { return 50u + static_cast<unsigned>(difficulty); }

}  // namespace dynapath
