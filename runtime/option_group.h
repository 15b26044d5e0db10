#pragma once
// Where a group of options is declared once: each group (scenario,
// run plan, process, ...) has one function `DeclareXOptions(OptionGroup&,
// XOptions&)` that names each option with its value name, help text and
// default. The same declaration serves two purposes:
//   * on a CLI11 app: parsing a command line or a config file into the
//     struct, and --help;
//   * on a ConfigWriter: writing the struct's values as a CLI11 config file
//     (TOML key = value lines), which is how the launcher hands a child
//     process its options (`--config /dev/fd/N`), instead of re-spelling
//     them as arguments.
// The default of an option is its struct member's initial value, shown in
// --help from there; options whose default depends on others are
// std::optional, with the rule in `default_text`.
// An option given is never ignored: every option taking a value refuses an
// empty one ("option --NAME must not be empty", also from a config file),
// as "" and unset mean "not given" to the code reading the struct (and a
// ConfigWriter writes no "" string); an option that only means something
// with another is refused without it where the group is resolved.

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "dynapath/result.h"

// CLI11 is header-only and costs seconds to compile per file: only the files
// that build or parse an app include <CLI/CLI.hpp>; the rest see this.
namespace CLI {
class App;
class Validator;
}  // namespace CLI

namespace dynapath::runtime {

// Collects "key=value" lines of the options that are set, as CLI11 reads
// them back.
class ConfigWriter {
 public:
  void Put(const std::string& key, const std::string& toml_value);
  // A quoted string; text CLI11 cannot read back (both quote kinds, a line
  // break) makes status() an error.
  void PutText(const std::string& key, const std::string& text);
  const std::string& Text() const { return text_; }
  Status status() const;

 private:
  std::string text_;
  std::string unwritable_;  // the first key whose value could not be written
};

// What an option's value is, by its config-file key ("leaf-limit"): for a
// config reader that checks values before they reach the parser (the study
// files of `dynapath experiment`).
enum class ValueKind { kString, kInteger, kFloat, kBoolean, kIntegerList, kStringList };
using OptionKinds = std::map<std::string, ValueKind>;

// Where a declared option's value lives in the struct it was declared on,
// with its kind, by its config-file key: for a reader that sets typed values
// itself (a study file, read by toml++) and for taking one struct's given
// options over another's, option by option (CopyOptionField).
struct OptionField {
  ValueKind kind = ValueKind::kString;
  std::variant<std::string*, std::optional<std::string>*, std::optional<long long>*,
               std::optional<double>*, long long*, double*, bool*,
               std::optional<std::vector<std::string>>*>
      value;
};
using OptionFields = std::map<std::string, OptionField>;
// Sets `to`'s value to `from`'s (fields of the same option in two structs).
void CopyOptionField(const OptionField& from, const OptionField& to);
// Set a field from a value of its kind, read from a file: text (a kString
// field), an integer, a real, a flag, a list's items. A value of another
// kind than the field's pointer is not set (check the kind first).
void SetOptionText(const OptionField& field, const std::string& text);
void SetOptionList(const OptionField& field, std::vector<std::string> items);
void SetOptionInteger(const OptionField& field, long long integer);
void SetOptionReal(const OptionField& field, double real);
void SetOptionBoolean(const OptionField& field, bool value);

class OptionGroup {
 public:
  // `kinds`, when given, gets the kind of every option declared.
  explicit OptionGroup(CLI::App& app, OptionKinds* kinds = nullptr) : app_(&app), kinds_(kinds) {}
  explicit OptionGroup(ConfigWriter& writer) : writer_(&writer) {}
  // Records where each option's value lives (nothing is parsed or written).
  explicit OptionGroup(OptionFields& fields) : fields_(&fields) {}

  // An option taking a value, "--name VALUE_NAME". `default_text` is shown
  // in --help for std::optional members (the struct's value otherwise).
  void Option(const std::string& name, std::string& value, const std::string& value_name,
              const std::string& help);
  void Option(const std::string& name, std::optional<std::string>& value,
              const std::string& value_name, const std::string& help,
              const std::string& default_text = "");
  void Option(const std::string& name, std::optional<long long>& value,
              const std::string& value_name, const std::string& help,
              const std::string& default_text = "");
  void Option(const std::string& name, std::optional<double>& value, const std::string& value_name,
              const std::string& help, const std::string& default_text = "");
  void Option(const std::string& name, long long& value, const std::string& value_name,
              const std::string& help);
  void Option(const std::string& name, double& value, const std::string& value_name,
              const std::string& help);
  // A comma-separated list, kept as its items (SplitList, where the command
  // line is read); `kind` is kIntegerList or kStringList.
  void List(const std::string& name, std::optional<std::vector<std::string>>& items, ValueKind kind,
            const std::string& value_name, const std::string& help,
            const std::string& default_text);
  // A flag without a value.
  void Flag(const std::string& name, bool& value, const std::string& help);

 private:
  void Record(const std::string& name, ValueKind kind);
  // With fields_: records the option's field and returns true (declare nothing).
  template <typename T>
  bool Bind(const std::string& name, ValueKind kind, T& value);

  CLI::App* app_ = nullptr;
  OptionKinds* kinds_ = nullptr;
  ConfigWriter* writer_ = nullptr;
  OptionFields* fields_ = nullptr;
};

// A command line's comma-separated list: its items as written, split at
// every comma ("20,,50" has an empty item; none is trimmed), and back.
std::vector<std::string> SplitList(const std::string& text);
std::string JoinList(const std::vector<std::string>& items);

// `fallback` when unset; else `value` when in [min, max], else the error
// "option --NAME must be between MIN and MAX, got VALUE".
Result<long long> InRange(const std::string& name, std::optional<long long> value,
                          long long fallback, long long min, long long max);

// CLI11 alone reads "010" as octal and "0x10" as hexadecimal; this transform
// makes an integer option decimal: digits with an optional sign, leading
// zeros dropped, anything else "needs a decimal number, got 'TEXT'". Every
// integer option of an OptionGroup has it.
const CLI::Validator& DecimalInteger();

// The project's way of parsing a command line on CLI11: --help prints the
// help and returns 0; a bad option prints "PROGRAM: MESSAGE" (one line) and
// returns 2. Returns -1 to go on. `args` excludes the program name.
int ParseCommandLine(CLI::App& app, std::vector<std::string> args, const std::string& program);
// The same on an app made here, named NAME in its --help and described by
// DESCRIPTION, whose options DECLARE puts on the group: a front end whose
// options are all a group's need not include CLI11 (seconds of compilation
// per file).
int ParseCommandLine(const std::string& program, const std::string& name,
                     const std::string& description,
                     const std::function<void(OptionGroup&)>& declare,
                     std::vector<std::string> args);
// The parse alone: a bad option's one-line message as the error (for a
// caller that reports it otherwise, the Python module); --help throws
// CLI::CallForHelp.
Status ParseArguments(CLI::App& app, std::vector<std::string> args);

// Adds --config FILE: options read from a CLI11 config file (TOML), the
// command line overriding it. A file named /dev/fd/N (the launcher's pipe)
// is closed after reading.
void AddConfigOption(CLI::App& app);
// Closes the inherited descriptor of a /dev/fd/N path after it was read, so
// nothing this process starts inherits it.
void CloseInheritedFd(const std::string& path);

}  // namespace dynapath::runtime
