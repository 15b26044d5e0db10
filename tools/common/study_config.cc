#include "tools/common/study_config.h"

#include <cerrno>
#include <cstdlib>
#include <map>

#include "core/text_file.h"

namespace dynapath::cli {
namespace {

bool IsBareKeyChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-';
}

class ConfigParser {
 public:
  ConfigParser(std::string_view text, std::string name) : text_(text) { file_.name = name; }

  Result<ConfigFile> Parse() {
    std::map<std::string, int> seen;
    while (true) {
      SkipBlankLinesAndComments();
      if (AtEnd()) break;
      const int line = line_;
      const char c = Peek();
      if (c == '[') {
        return Fail(
            "tables ('[...]') are not supported: write every option as 'key = value' at the top "
            "level");
      }
      if (!IsBareKeyChar(c)) {
        if (c == '"' || c == '\'') return Fail("quoted keys are not supported");
        return Fail(std::string("expected 'key = value', found '") + c + "'");
      }
      std::string key;
      while (!AtEnd() && IsBareKeyChar(Peek())) key += Next();
      SkipSpaces();
      if (!AtEnd() && Peek() == '.') return Fail("dotted keys are not supported");
      if (AtEnd() || Peek() != '=') return Fail("expected '=' after '" + key + "'");
      Next();
      SkipSpaces();
      ConfigValue value;
      if (Status status = Value(value, false); !status) return status.error();
      SkipSpaces();
      if (!AtEnd() && Peek() == '#') SkipComment();
      if (!AtEnd() && Peek() != '\n' && Peek() != '\r') {
        return Fail("unexpected text after the value of '" + key + "'");
      }
      if (auto it = seen.find(key); it != seen.end()) {
        return FailAt(
            line, "'" + key + "' is set twice (first on line " + std::to_string(it->second) + ")");
      }
      seen[key] = line;
      file_.entries.push_back(ConfigEntry{key, std::move(value), line});
    }
    return std::move(file_);
  }

 private:
  bool AtEnd() const { return pos_ >= text_.size(); }
  char Peek() const { return text_[pos_]; }
  char Next() {
    const char c = text_[pos_++];
    if (c == '\n') ++line_;
    return c;
  }

  Error FailAt(int line, const std::string& message) const {
    return Error{file_.name + ":" + std::to_string(line) + ": " + message};
  }
  Error Fail(const std::string& message) const { return FailAt(line_, message); }

  void SkipSpaces() {
    while (!AtEnd() && (Peek() == ' ' || Peek() == '\t')) Next();
  }
  void SkipComment() {
    while (!AtEnd() && Peek() != '\n') Next();
  }
  // Whitespace, newlines and comments.
  void SkipBlankLinesAndComments() {
    while (!AtEnd()) {
      const char c = Peek();
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
        Next();
      } else if (c == '#') {
        SkipComment();
      } else {
        break;
      }
    }
  }

  Status Value(ConfigValue& value, bool in_array) {
    value.line = line_;
    if (AtEnd() || Peek() == '\n' || Peek() == '\r' || Peek() == '#') {
      return Fail("missing value after '='");
    }
    const char c = Peek();
    if (c == '"' || c == '\'') return String(value);
    if (c == '[') {
      if (in_array) return Fail("nested arrays are not supported");
      return Array(value);
    }
    if (c == '{') return Fail("inline tables ('{...}') are not supported");
    // A bare word: boolean or integer.
    std::string word;
    while (!AtEnd() && Peek() != ' ' && Peek() != '\t' && Peek() != '\n' && Peek() != '\r' &&
           Peek() != '#' && Peek() != ',' && Peek() != ']') {
      word += Next();
    }
    if (word == "true" || word == "false") {
      value.kind = ConfigValue::Kind::kBoolean;
      value.boolean = word == "true";
      return Ok{};
    }
    return Integer(word, value);
  }

  Status Integer(const std::string& word, ConfigValue& value) {
    // [+-]digits, with single underscores between digits.
    std::string digits;
    bool ok = !word.empty();
    for (size_t i = 0; i < word.size() && ok; ++i) {
      const char c = word[i];
      if ((c == '+' || c == '-') && i == 0) {
        digits += c;
      } else if (c >= '0' && c <= '9') {
        digits += c;
      } else if (c == '_' && i > 0 && i + 1 < word.size() && word[i - 1] >= '0' &&
                 word[i - 1] <= '9' && word[i + 1] >= '0' && word[i + 1] <= '9') {
        continue;
      } else {
        ok = false;
      }
    }
    const bool has_digit = digits.find_first_of("0123456789") != std::string::npos;
    if (!ok || !has_digit) {
      if (word.find_first_of(".eE") != std::string::npos && has_digit) {
        return Fail("'" + word +
                    "': floating-point values are not supported (no option takes one)");
      }
      return Fail("'" + word +
                  "' is not a value: write strings in quotes, integers in digits, booleans as "
                  "true or false");
    }
    errno = 0;
    char* end = nullptr;
    const long long number = std::strtoll(digits.c_str(), &end, 10);
    if (errno == ERANGE || *end != '\0') return Fail("'" + word + "' is out of range");
    value.kind = ConfigValue::Kind::kInteger;
    value.integer = number;
    return Ok{};
  }

  Status String(ConfigValue& value) {
    const char quote = Next();
    value.kind = ConfigValue::Kind::kString;
    if (text_.substr(pos_, 2) == std::string(2, quote)) {
      return Fail("multi-line strings are not supported");
    }
    while (true) {
      if (AtEnd() || Peek() == '\n') return Fail("unterminated string");
      const char c = Next();
      if (c == quote) return Ok{};
      if (c != '\\' || quote == '\'') {
        value.string += c;
        continue;
      }
      if (AtEnd()) return Fail("unterminated string");
      const char e = Next();
      switch (e) {
        case '"':
        case '\\':
          value.string += e;
          break;
        case 'n':
          value.string += '\n';
          break;
        case 't':
          value.string += '\t';
          break;
        case 'r':
          value.string += '\r';
          break;
        default:
          return Fail(std::string("unsupported escape '\\") + e + "' in a string");
      }
    }
  }

  Status Array(ConfigValue& value) {
    Next();  // '['
    value.kind = ConfigValue::Kind::kArray;
    while (true) {
      SkipBlankLinesAndComments();
      if (AtEnd()) return FailAt(value.line, "unterminated array (missing ']')");
      if (Peek() == ']') {
        Next();
        return Ok{};
      }
      ConfigValue item;
      if (Status status = Value(item, true); !status) return status;
      if (!value.items.empty() && item.kind != value.items.front().kind) {
        return Fail("an array mixes " + value.items.front().KindName() + "s and " +
                    item.KindName() + "s");
      }
      value.items.push_back(std::move(item));
      SkipBlankLinesAndComments();
      if (AtEnd()) return FailAt(value.line, "unterminated array (missing ']')");
      if (Peek() == ',') {
        Next();
      } else if (Peek() != ']') {
        return Fail("expected ',' or ']' in an array");
      }
    }
  }

  std::string_view text_;
  size_t pos_ = 0;
  int line_ = 1;
  ConfigFile file_;
};

}  // namespace

std::string ConfigValue::KindName() const {
  switch (kind) {
    case Kind::kString:
      return "string";
    case Kind::kInteger:
      return "integer";
    case Kind::kBoolean:
      return "boolean";
    case Kind::kArray:
      return "array";
  }
  return "value";
}

Result<ConfigFile> ParseConfigText(std::string_view text, const std::string& name) {
  return ConfigParser(text, name).Parse();
}

Result<ConfigFile> ReadConfigFile(const std::string& path) {
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  return ParseConfigText(*text, path);
}

}  // namespace dynapath::cli
