#include "dynapath/ros_map.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <set>

#include "dynapath/limits.h"
#include "dynapath/text_file.h"
#include "dynapath/text_util.h"

namespace dynapath {
namespace {

Error YamlLineError(int line, const std::string& message) {
  return Error::Corrupt("line " + std::to_string(line) + ": " + message);
}

bool IsSpace(char ch) { return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\n'; }

std::string_view TrimView(std::string_view text) {
  while (!text.empty() && IsSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && IsSpace(text.back())) text.remove_suffix(1);
  return text;
}

// A whole finite decimal number (strtod on a bounded copy).
bool ParseNumber(std::string_view text, double& value) {
  text = TrimView(text);
  if (text.empty() || text.size() > 64) return false;
  const std::string copy(text);
  char* end = nullptr;
  value = std::strtod(copy.c_str(), &end);
  return end == copy.c_str() + copy.size() && std::isfinite(value);
}

// Drops a " #..." comment outside quotes.
std::string_view StripComment(std::string_view line) {
  char quote = 0;
  for (size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quote) {
      if (ch == quote) quote = 0;
    } else if (ch == '"' || ch == '\'') {
      quote = ch;
    } else if (ch == '#' && (i == 0 || IsSpace(line[i - 1]))) {
      return line.substr(0, i);
    }
  }
  return line;
}

}  // namespace

Result<RosMapInfo> ParseRosMapYaml(std::string_view bytes) {
  RosMapInfo info;
  std::set<std::string> seen;
  size_t pos = 0;
  int number = 0;
  while (pos < bytes.size()) {
    const size_t end = bytes.find('\n', pos);
    const size_t stop = end == std::string_view::npos ? bytes.size() : end;
    std::string_view line = bytes.substr(pos, stop - pos);
    pos = stop + 1;
    ++number;
    if (number == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
    line = StripComment(line);
    if (TrimView(line).empty() || TrimView(line) == "---") continue;
    if (IsSpace(line.front())) {
      return YamlLineError(number, "indented line: only flat 'key: value' lines are read");
    }
    const size_t colon = line.find(':');
    if (colon == std::string_view::npos) return YamlLineError(number, "expected 'key: value'");
    const std::string key(TrimView(line.substr(0, colon)));
    const std::string_view value = TrimView(line.substr(colon + 1));
    if (!seen.insert(key).second) return YamlLineError(number, "key '" + key + "' given twice");
    if (value.empty()) return YamlLineError(number, "key '" + key + "' has no value");
    const auto number_of = [&](double& out, const char* what) -> Status {
      if (!ParseNumber(value, out)) {
        return YamlLineError(
            number, "'" + key + "' must be " + what + ", got '" + std::string(value) + "'");
      }
      return Ok{};
    };
    if (key == "image") {
      std::string_view name = value;
      if (name.size() >= 2 && (name.front() == '"' || name.front() == '\'') &&
          name.back() == name.front()) {
        name = name.substr(1, name.size() - 2);
      }
      if (name.empty()) return YamlLineError(number, "'image' is empty");
      info.image = std::string(name);
    } else if (key == "resolution") {
      if (Status s = number_of(info.resolution, "a number > 0"); !s) return s.error();
      if (!(info.resolution > 0)) return YamlLineError(number, "'resolution' must be a number > 0");
    } else if (key == "origin") {
      if (value.size() < 2 || value.front() != '[' || value.back() != ']') {
        return YamlLineError(number, "'origin' must be [x, y, yaw]");
      }
      std::string_view rest = value.substr(1, value.size() - 2);
      for (int i = 0; i < 3; ++i) {
        const size_t comma = rest.find(',');
        const bool last = i == 2;
        if (last != (comma == std::string_view::npos) ||
            !ParseNumber(rest.substr(0, comma), info.origin[i])) {
          return YamlLineError(number, "'origin' must be [x, y, yaw]");
        }
        if (!last) rest = rest.substr(comma + 1);
      }
    } else if (key == "occupied_thresh" || key == "free_thresh") {
      double& out = key == "free_thresh" ? info.free_thresh : info.occupied_thresh;
      if (Status s = number_of(out, "a number in 0..1"); !s) return s.error();
      if (out < 0 || out > 1)
        return YamlLineError(number, "'" + key + "' must be a number in 0..1");
    } else if (key == "negate") {
      if (value == "0" || value == "false") {
        info.negate = false;
      } else if (value == "1" || value == "true") {
        info.negate = true;
      } else {
        return YamlLineError(number, "'negate' must be 0 or 1, got '" + std::string(value) + "'");
      }
    } else if (key == "mode") {
      if (value == "trinary") {
        info.mode = RosMapMode::kTrinary;
      } else if (value == "scale") {
        info.mode = RosMapMode::kScale;
      } else if (value == "raw") {
        info.mode = RosMapMode::kRaw;
      } else {
        return YamlLineError(
            number, "'mode' must be trinary, scale or raw, got '" + std::string(value) + "'");
      }
    } else {
      return YamlLineError(number, "unknown key '" + key +
                                       "' (known: image resolution origin occupied_thresh "
                                       "free_thresh negate mode)");
    }
  }
  for (const char* required : {"image", "resolution", "origin", "occupied_thresh", "free_thresh"}) {
    if (!seen.count(required)) return Error::Corrupt(std::string("missing key '") + required + "'");
  }
  if (!(info.free_thresh < info.occupied_thresh)) {
    return Error::Corrupt("free_thresh must be below occupied_thresh");
  }
  return info;
}

namespace {

// PGM header and ascii data: tokens separated by whitespace and "#" comments.
class PgmReader {
 public:
  explicit PgmReader(std::string_view bytes) : bytes_(bytes) {}
  void SkipSpaceAndComments() {
    while (pos_ < bytes_.size()) {
      if (IsSpace(bytes_[pos_])) {
        ++pos_;
      } else if (bytes_[pos_] == '#') {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
  }
  // A decimal number <= limit; false when there is none or it is larger.
  bool Number(int limit, int& value) {
    SkipSpaceAndComments();
    const size_t start = pos_;
    long long v = 0;
    while (pos_ < bytes_.size() && bytes_[pos_] >= '0' && bytes_[pos_] <= '9') {
      v = v * 10 + (bytes_[pos_] - '0');
      ++pos_;
      if (v > limit) return false;
    }
    if (pos_ == start) return false;
    if (pos_ < bytes_.size() && !IsSpace(bytes_[pos_]) && bytes_[pos_] != '#') return false;
    value = static_cast<int>(v);
    return true;
  }
  size_t pos() const { return pos_; }
  void Skip(size_t n) { pos_ += n; }
  bool AtEnd() {
    SkipSpaceAndComments();
    return pos_ >= bytes_.size();
  }

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
};

bool IsObstacle(const RosMapInfo& info, int value, int maxval) {
  double p;
  if (info.mode == RosMapMode::kRaw) {
    if (value > 100) return true;  // unknown
    p = value / 100.0;
  } else {
    const int v = (value * 255 + maxval / 2) / maxval;
    p = info.negate ? v / 255.0 : (255 - v) / 255.0;
  }
  if (p > info.occupied_thresh) return true;
  if (p < info.free_thresh) return false;
  return true;  // unknown (trinary) or partly occupied (scale)
}

}  // namespace

Result<Grid> RosMapGrid(const RosMapInfo& info, std::string_view pgm) {
  if (pgm.size() < 2 || pgm[0] != 'P' || (pgm[1] != '5' && pgm[1] != '2')) {
    return Error::Corrupt("not a PGM image (expected magic P5 or P2)");
  }
  const bool binary = pgm[1] == '5';
  PgmReader reader(pgm);
  reader.Skip(2);
  if (reader.pos() < pgm.size() && !IsSpace(pgm[reader.pos()])) {
    return Error::Corrupt("not a PGM image (expected magic P5 or P2)");
  }
  int width = 0, height = 0, maxval = 0;
  const std::string limit = std::to_string(kMaxGridSide);
  if (!reader.Number(1 << 30, width) || !reader.Number(1 << 30, height)) {
    return Error::Corrupt("PGM header: expected width and height");
  }
  if (width < 1 || height < 1 || width > kMaxGridSide || height > kMaxGridSide) {
    return Error::Corrupt("image of " + std::to_string(width) + "x" + std::to_string(height) +
                          " pixels: each side must be 1.." + limit + " (the grid limit)");
  }
  if (!reader.Number(65535, maxval) || maxval < 1 || maxval > 255) {
    return Error::Corrupt("PGM header: maxval must be 1..255 (8-bit images only)");
  }
  const size_t cells = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (binary) {
    // Exactly one whitespace byte after maxval, then width*height bytes.
    if (reader.pos() >= pgm.size() || !IsSpace(pgm[reader.pos()])) {
      return Error::Corrupt("PGM data truncated: 0 of " + std::to_string(cells) + " pixels");
    }
    const size_t start = reader.pos() + 1;
    if (pgm.size() - start < cells) {
      return Error::Corrupt("PGM data truncated: " + std::to_string(pgm.size() - start) + " of " +
                            std::to_string(cells) + " pixels");
    }
    for (size_t i = start + cells; i < pgm.size(); ++i) {
      if (!IsSpace(pgm[i])) return Error::Corrupt("unexpected data after the PGM's pixels");
    }
    Grid grid(height, width);
    for (size_t i = 0; i < cells; ++i) {
      const int value = static_cast<unsigned char>(pgm[start + i]);
      if (value > maxval) {
        return Error::Corrupt("pixel " + std::to_string(i) + " is " + std::to_string(value) +
                              ", above maxval " + std::to_string(maxval));
      }
      if (IsObstacle(info, value, maxval)) grid.set(static_cast<int>(i), Cell::kObstacle);
    }
    return grid;
  }
  // Every ascii pixel takes at least two bytes: refuse a short file before allocating.
  if (pgm.size() - reader.pos() < cells) {
    return Error::Corrupt("PGM data truncated: the file is too short for " + std::to_string(cells) +
                          " pixels");
  }
  Grid grid(height, width);
  for (size_t i = 0; i < cells; ++i) {
    int value = 0;
    if (reader.AtEnd()) {
      return Error::Corrupt("PGM data truncated: " + std::to_string(i) + " of " +
                            std::to_string(cells) + " pixels");
    }
    if (!reader.Number(maxval, value)) {
      return Error::Corrupt("pixel " + std::to_string(i) + ": expected a number 0.." +
                            std::to_string(maxval));
    }
    if (IsObstacle(info, value, maxval)) grid.set(static_cast<int>(i), Cell::kObstacle);
  }
  if (!reader.AtEnd()) return Error::Corrupt("unexpected data after the PGM's pixels");
  return grid;
}

bool IsRosMapPath(const std::string& path) {
  // Any case: M5.YAML is a ROS map too (not a text maze to misread).
  const std::string lower = ToLower(path);
  const auto ends = [&](const char* suffix) {
    const std::string s(suffix);
    return lower.size() > s.size() && lower.compare(lower.size() - s.size(), s.size(), s) == 0;
  };
  return ends(".yaml") || ends(".yml");
}

Result<Grid> LoadRosMap(const std::string& path) {
  Result<std::string> yaml = ReadTextFile(path);
  if (!yaml) return yaml.error();
  Result<RosMapInfo> info = ParseRosMapYaml(*yaml);
  if (!info) return info.error().Prefixed(path + ": ");
  const size_t slash = path.find_last_of('/');
  const std::string image = info->image.front() == '/' || slash == std::string::npos
                                ? info->image
                                : path.substr(0, slash + 1) + info->image;
  Result<std::string> pgm = ReadTextFile(image);
  if (!pgm) return pgm.error().Prefixed(path + ": image: ");
  Result<Grid> grid = RosMapGrid(*info, *pgm);
  if (!grid) return grid.error().Prefixed(image + ": ");
  return grid;
}

}  // namespace dynapath
