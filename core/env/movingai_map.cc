#include "dynapath/movingai_map.h"

#include <charconv>

#include "dynapath/limits.h"
#include "dynapath/ros_map.h"
#include "dynapath/text_file.h"

namespace dynapath {
namespace {

constexpr int kMaxSide = kMaxGridSide;

// Lines of the file one at a time, without their "\n" or "\r\n".
class Lines {
 public:
  explicit Lines(std::string_view bytes) : bytes_(bytes) {}
  bool Next(std::string_view& line) {
    if (pos_ >= bytes_.size()) return false;
    const size_t end = bytes_.find('\n', pos_);
    const size_t stop = end == std::string_view::npos ? bytes_.size() : end;
    line = bytes_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = stop + 1;
    ++number_;
    return true;
  }
  int number() const { return number_; }

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
  int number_ = 0;
};

Error LineError(int line, const std::string& message) {
  return Error::Corrupt("line " + std::to_string(line) + ": " + message);
}

// "<key> <number>" with 1 <= number <= kMaxSide.
Result<int> SideLine(Lines& lines, std::string_view key) {
  std::string_view line;
  if (!lines.Next(line)) {
    return Error::Corrupt("the header ends before '" + std::string(key) + " N'");
  }
  const std::string expected =
      "expected '" + std::string(key) + " N' with 1 <= N <= " + std::to_string(kMaxSide);
  if (line.substr(0, key.size()) != key || line.size() <= key.size() + 1 ||
      line[key.size()] != ' ') {
    return LineError(lines.number(), expected);
  }
  const std::string_view digits = line.substr(key.size() + 1);
  int value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error != std::errc{} || end != digits.data() + digits.size() || value < 1 ||
      value > kMaxSide) {
    return LineError(lines.number(), expected);
  }
  return value;
}

}  // namespace

bool LooksLikeMovingAiMap(std::string_view bytes) { return bytes.substr(0, 5) == "type "; }

Result<Grid> ParseMovingAiMap(std::string_view bytes) {
  Lines lines(bytes);
  std::string_view line;
  if (!lines.Next(line) || line != "type octile") {
    return Error::Corrupt("line 1: expected 'type octile' (a MovingAI map)");
  }
  Result<int> height = SideLine(lines, "height");
  if (!height) return height.error();
  Result<int> width = SideLine(lines, "width");
  if (!width) return width.error();
  if (!lines.Next(line) || line != "map") {
    return LineError(lines.number(), "expected 'map'");
  }
  // Every row needs `width` bytes: refuse a short file before allocating.
  if (bytes.size() < static_cast<size_t>(*height) * static_cast<size_t>(*width)) {
    return Error::Corrupt("the file is too short for a " + std::to_string(*height) + "x" +
                          std::to_string(*width) + " map");
  }
  Grid grid(*height, *width);
  for (int r = 0; r < *height; ++r) {
    if (!lines.Next(line)) {
      return Error::Corrupt("the map ends after " + std::to_string(r) + " of its " +
                            std::to_string(*height) + " rows");
    }
    if (line.size() != static_cast<size_t>(*width)) {
      return LineError(lines.number(), "a row of " + std::to_string(line.size()) +
                                           " cells, the header says width " +
                                           std::to_string(*width));
    }
    for (int c = 0; c < *width; ++c) {
      switch (line[static_cast<size_t>(c)]) {
        case '.':
        case 'G':
        case 'S':
          break;  // Grid's fill is kFree
        case '@':
        case 'O':
        case 'T':
        case 'W':
          grid.set(r, c, Cell::kObstacle);
          break;
        default: {
          const unsigned char ch = static_cast<unsigned char>(line[static_cast<size_t>(c)]);
          const std::string shown = ch >= 0x20 && ch < 0x7f
                                        ? "'" + std::string(1, static_cast<char>(ch)) + "'"
                                        : "byte " + std::to_string(ch);
          return LineError(lines.number(), "column " + std::to_string(c + 1) +
                                               ": unknown terrain " + shown +
                                               " (passable: . G S; obstacles: @ O T W)");
        }
      }
    }
  }
  while (lines.Next(line)) {
    if (!line.empty()) return LineError(lines.number(), "unexpected data after the map's rows");
  }
  return grid;
}

Result<Grid> LoadMazeFile(const std::string& path, bool* movingai) {
  if (IsRosMapPath(path)) {
    if (movingai) *movingai = true;  // a map: stations required, its walls still
    return LoadRosMap(path);
  }
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  if (movingai) *movingai = LooksLikeMovingAiMap(*text);
  Result<Grid> grid = LooksLikeMovingAiMap(*text) ? ParseMovingAiMap(*text) : GridFromText(*text);
  if (!grid) return grid.error().Prefixed(path + ": ");
  return grid;
}

}  // namespace dynapath
