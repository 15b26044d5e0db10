#pragma once
// The file of `dynapath experiment --config FILE`: TOML (v1.0, parsed by
// toml++, Debian's libtomlplusplus-dev) with the study's options as
// top-level keys:
//
//   # a comment
//   sizes = [20, 50]                 # integers, arrays (may span lines)
//   difficulties = ["easy", "hard"]  # strings
//   edge-case = false                # booleans
//
// Tables, dates and times, nested arrays and arrays that mix kinds are
// refused with an error naming the line: no option takes them. A key
// may be spelled with '-' or '_' (`epsilon-start`, `epsilon_start`), as the
// options' names are; a key given twice under any spelling is refused,
// naming both lines. This is the one reading rule of every options file:
// study files, `dynapath run --config FILE` and a checkpoint's run.toml
// (tools/common/toml_config.h). This module parses, and sets a file's values
// into declared option fields (SetOptionFields); which keys exist is the
// caller's business (study_plan.h, CLI11's options, the fields given).

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "dynapath/result.h"
#include "runtime/option_group.h"

namespace dynapath::study {

struct ConfigValue {
  enum class Kind { kString, kInteger, kFloat, kBoolean, kArray };
  Kind kind = Kind::kString;
  std::string string;
  long long integer = 0;
  double number = 0.0;  // kFloat
  bool boolean = false;
  std::vector<ConfigValue> items;  // kArray: strings, integers or booleans
  int line = 0;

  // "string", "integer", "float", "boolean" or "array".
  std::string KindName() const;
  // A scalar as an option's text: "true"/"false", decimal integers, the
  // shortest round-trip form of a float; an array's items joined by ','.
  std::string Text() const;
};

struct ConfigEntry {
  std::string key;      // with '-': "epsilon-start"
  std::string written;  // as the file spells it: "epsilon_start"

  ConfigValue value;
  int line = 0;
};

struct ConfigFile {
  std::string name;  // as given, for messages
  std::vector<ConfigEntry> entries;
};

// Parses `text`; errors read "NAME:LINE: what is wrong".
Result<ConfigFile> ParseConfigText(std::string_view text, const std::string& name);
// Reads and parses the file at `path`.
Result<ConfigFile> ReadConfigFile(const std::string& path);

// Sets the options `fields` holds (runtime::OptionGroup(OptionFields&)) to
// the file's values, each checked against its option's kind as CLI11 would
// take it from a --config file: a text or list option takes any value as
// its text (an array's items joined by ','), a float option an integer too,
// an integer option an integer, a flag a boolean.
// An entry whose key `skip` accepts is left out (an option given
// otherwise). Errors read "NAME:LINE: ...": a key no option has, a value of
// another kind, an empty string.
Status SetOptionFields(const ConfigFile& file, const runtime::OptionFields& fields,
                       const std::function<bool(const std::string& key)>& skip);

}  // namespace dynapath::study
