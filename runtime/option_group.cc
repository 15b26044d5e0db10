#include "runtime/option_group.h"

#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "dynapath/text_util.h"

namespace dynapath::runtime {
namespace {

// "--name" -> "name", the key of a config file.
std::string Key(const std::string& name) { return name.substr(name.find_first_not_of('-')); }

constexpr const char* kEmptyValueText = "must not be empty";

// A TOML string both readers of these files take back unchanged: CLI11's
// (the processes' --config) and toml++ (`dynapath run`, which reads a
// checkpoint's run.toml): literal quotes ('...'), which neither unescapes,
// else basic ("...") ones for text without a backslash (toml++ would read
// one as an escape). Other text (a line break; ' with " or \) cannot be
// written; Put records that.
std::optional<std::string> Quote(const std::string& text) {
  if (text.find_first_of("\n\r") != std::string::npos) return std::nullopt;
  if (text.find('\'') == std::string::npos) return "'" + text + "'";
  if (text.find_first_of("\"\\") == std::string::npos) return "\"" + text + "\"";
  return std::nullopt;
}

}  // namespace

void ConfigWriter::Put(const std::string& key, const std::string& toml_value) {
  text_ += key + "=" + toml_value + "\n";
}

Status ConfigWriter::status() const {
  if (!unwritable_.empty()) {
    return Error{"option --" + unwritable_ +
                     ": a value holding ' with \" or \\, or a line break, cannot be recorded "
                     "or handed to a child process",
                 Error::Code::kInvalidArgument, unwritable_};
  }
  return Ok{};
}

void ConfigWriter::PutText(const std::string& key, const std::string& text) {
  std::optional<std::string> quoted = Quote(text);
  if (!quoted) {
    if (unwritable_.empty()) unwritable_ = key;
    return;
  }
  Put(key, *quoted);
}

// A size, a seed or a step count typed with a leading zero means the
// decimal number. A number too large for a long long is out of range as
// typed (CLI11 alone would clamp it, and a check would echo the clamped
// value, which the user never typed).
const CLI::Validator& DecimalInteger() {
  static const CLI::Validator validator(
      [](std::string& text) -> std::string {
        if (text.empty()) return kEmptyValueText;  // as every option's (CLI11 runs this first)
        const size_t digits = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
        if (digits == text.size() ||
            text.find_first_not_of("0123456789", digits) != std::string::npos) {
          return "needs a decimal number, got '" + text + "'";
        }
        const size_t first = text.find_first_not_of('0', digits);
        const std::string typed = text;
        text = text.substr(0, digits) + (first == std::string::npos ? "0" : text.substr(first));
        errno = 0;
        (void)std::strtoll(text.c_str(), nullptr, 10);
        if (errno == ERANGE) return "is out of range, got '" + typed + "'";
        return {};
      },
      "");
  return validator;
}

namespace {

// A real number too large for a double (1e400) is out of range as typed,
// not "inf".
const CLI::Validator& FiniteReal() {
  static const CLI::Validator validator(
      [](std::string& text) -> std::string {
        errno = 0;
        const double value = std::strtod(text.c_str(), nullptr);
        if (errno == ERANGE && std::isinf(value)) return "is out of range, got '" + text + "'";
        return {};
      },
      "");
  return validator;
}

// An empty value ("--save-policy ''", `checkpoint = ""` in a config file)
// is refused for every option taking one: a struct member's "" or unset
// means "not given", so without this rule the option would be silently
// ignored.
const CLI::Validator& NonEmptyValue() {
  static const CLI::Validator validator(
      [](std::string& text) -> std::string { return text.empty() ? kEmptyValueText : ""; }, "");
  return validator;
}

}  // namespace

void OptionGroup::Record(const std::string& name, ValueKind kind) {
  if (kinds_ != nullptr) (*kinds_)[Key(name)] = kind;
}

template <typename T>
bool OptionGroup::Bind(const std::string& name, ValueKind kind, T& value) {
  if (fields_ == nullptr) return false;
  (*fields_)[Key(name)] = OptionField{kind, &value};
  return true;
}

void CopyOptionField(const OptionField& from, const OptionField& to) {
  std::visit(
      [&](auto* source) {
        using Pointer = decltype(source);
        if (auto* const* target = std::get_if<Pointer>(&to.value)) **target = *source;
      },
      from.value);
}

void SetOptionText(const OptionField& field, const std::string& text) {
  if (auto* const* value = std::get_if<std::string*>(&field.value)) **value = text;
  if (auto* const* value = std::get_if<std::optional<std::string>*>(&field.value)) **value = text;
}
void SetOptionList(const OptionField& field, std::vector<std::string> items) {
  if (auto* const* value = std::get_if<std::optional<std::vector<std::string>>*>(&field.value)) {
    **value = std::move(items);
  }
}
void SetOptionInteger(const OptionField& field, long long integer) {
  if (auto* const* value = std::get_if<long long*>(&field.value)) **value = integer;
  if (auto* const* value = std::get_if<std::optional<long long>*>(&field.value)) **value = integer;
}
void SetOptionReal(const OptionField& field, double real) {
  if (auto* const* value = std::get_if<double*>(&field.value)) **value = real;
  if (auto* const* value = std::get_if<std::optional<double>*>(&field.value)) **value = real;
}
void SetOptionBoolean(const OptionField& field, bool value) {
  if (auto* const* target = std::get_if<bool*>(&field.value)) **target = value;
}

void OptionGroup::Option(const std::string& name, std::string& value, const std::string& value_name,
                         const std::string& help) {
  if (Bind(name, ValueKind::kString, value)) return;
  if (writer_ != nullptr) {
    if (!value.empty()) writer_->PutText(Key(name), value);  // "": not given
    return;
  }
  Record(name, ValueKind::kString);
  app_->add_option(name, value, help)
      ->type_name(value_name)
      ->capture_default_str()
      ->check(NonEmptyValue());
}

void OptionGroup::Option(const std::string& name, std::optional<std::string>& value,
                         const std::string& value_name, const std::string& help,
                         const std::string& default_text) {
  if (Bind(name, ValueKind::kString, value)) return;
  if (writer_ != nullptr) {
    if (value) writer_->PutText(Key(name), *value);
    return;
  }
  Record(name, ValueKind::kString);
  CLI::Option* option =
      app_->add_option(name, value, help)->type_name(value_name)->check(NonEmptyValue());
  if (!default_text.empty()) option->default_str(default_text);
}

void OptionGroup::Option(const std::string& name, std::optional<long long>& value,
                         const std::string& value_name, const std::string& help,
                         const std::string& default_text) {
  if (Bind(name, ValueKind::kInteger, value)) return;
  if (writer_ != nullptr) {
    if (value) writer_->Put(Key(name), std::to_string(*value));
    return;
  }
  Record(name, ValueKind::kInteger);
  CLI::Option* option = app_->add_option(name, value, help)
                            ->type_name(value_name)
                            ->check(NonEmptyValue())
                            ->transform(DecimalInteger());
  if (!default_text.empty()) option->default_str(default_text);
}

void OptionGroup::Option(const std::string& name, std::optional<double>& value,
                         const std::string& value_name, const std::string& help,
                         const std::string& default_text) {
  if (Bind(name, ValueKind::kFloat, value)) return;
  if (writer_ != nullptr) {
    if (value) writer_->Put(Key(name), fmt::format("{}", *value));
    return;
  }
  Record(name, ValueKind::kFloat);
  CLI::Option* option = app_->add_option(name, value, help)
                            ->type_name(value_name)
                            ->check(NonEmptyValue())
                            ->check(FiniteReal());
  if (!default_text.empty()) option->default_str(default_text);
}

void OptionGroup::Option(const std::string& name, long long& value, const std::string& value_name,
                         const std::string& help) {
  if (Bind(name, ValueKind::kInteger, value)) return;
  if (writer_ != nullptr) return writer_->Put(Key(name), std::to_string(value));
  Record(name, ValueKind::kInteger);
  app_->add_option(name, value, help)
      ->type_name(value_name)
      ->capture_default_str()
      ->check(NonEmptyValue())
      ->transform(DecimalInteger());
}

void OptionGroup::Option(const std::string& name, double& value, const std::string& value_name,
                         const std::string& help) {
  // {} is the shortest text that reads back as the same double.
  if (Bind(name, ValueKind::kFloat, value)) return;
  if (writer_ != nullptr) return writer_->Put(Key(name), fmt::format("{}", value));
  Record(name, ValueKind::kFloat);
  app_->add_option(name, value, help)
      ->type_name(value_name)
      ->capture_default_str()
      ->check(NonEmptyValue())
      ->check(FiniteReal());
}

void OptionGroup::Flag(const std::string& name, bool& value, const std::string& help) {
  if (Bind(name, ValueKind::kBoolean, value)) return;
  if (writer_ != nullptr) {
    if (value) writer_->Put(Key(name), "true");
    return;
  }
  Record(name, ValueKind::kBoolean);
  app_->add_flag(name, value, help);
}

std::vector<std::string> SplitList(const std::string& text) { return SplitAsWritten(text, ','); }

std::string JoinList(const std::vector<std::string>& items) {
  std::string text;
  for (size_t i = 0; i < items.size(); ++i) text += (i == 0 ? "" : ",") + items[i];
  return text;
}

void OptionGroup::List(const std::string& name, std::optional<std::vector<std::string>>& items,
                       ValueKind kind, const std::string& value_name, const std::string& help,
                       const std::string& default_text) {
  if (Bind(name, kind, items)) return;
  if (writer_ != nullptr) {
    if (items) writer_->PutText(Key(name), JoinList(*items));
    return;
  }
  Record(name, kind);
  CLI::Option* option =
      app_->add_option_function<std::string>(
              name, [&items](const std::string& text) { items = SplitList(text); }, help)
          ->type_name(value_name)
          ->check(NonEmptyValue());
  if (!default_text.empty()) option->default_str(default_text);
}

Result<long long> InRange(const std::string& name, std::optional<long long> value,
                          long long fallback, long long min, long long max) {
  if (!value) return fallback;  // a default is right by construction
  const long long given = *value;
  if (given < min || given > max) {
    return Error::Option(name, "must be between " + std::to_string(min) + " and " +
                                   std::to_string(max) + ", got " + std::to_string(given));
  }
  return given;
}

Status ParseArguments(CLI::App& app, std::vector<std::string> args) {
  auto usage_error = [](const std::string& message) -> Status { return Error(message); };
  std::reverse(args.begin(), args.end());  // CLI11 takes them last first
  try {
    app.parse(args);
  } catch (const CLI::CallForHelp&) {
    throw;  // a ParseError too: ParseCommandLine prints the help
  } catch (const CLI::ExtrasError&) {
    const std::vector<std::string> extras = app.remaining();
    for (const std::string& extra : extras) {
      if (extra.rfind("-", 0) == 0 && extra.size() > 1) {
        return usage_error("unknown option " + extra.substr(0, extra.find('=')) + " (see --help)");
      }
    }
    return usage_error("unexpected argument '" + (extras.empty() ? "" : extras.front()) +
                       "' (see --help)");
  } catch (const CLI::ArgumentMismatch& error) {
    // CLI11: "--out: 1 required TEXT missing".
    const std::string what = error.what();
    const size_t colon = what.find(':');
    if (what.rfind("--", 0) == 0 && colon != std::string::npos &&
        what.find("missing") != std::string::npos) {
      return usage_error("option " + what.substr(0, colon) + " needs a value");
    }
    return usage_error(what);
  } catch (const CLI::ConversionError& error) {
    // CLI11: "Could not convert: --size = abc".
    const std::string what = error.what();
    const size_t name = what.find("--");
    const size_t equals = what.find(" = ", name == std::string::npos ? 0 : name);
    if (name != std::string::npos && equals != std::string::npos) {
      return usage_error("option " + what.substr(name, equals - name) + " needs a number, got '" +
                         what.substr(equals + 3) + "'");
    }
    return usage_error(what);
  } catch (const CLI::ValidationError& error) {
    // CLI11: "--size: needs a decimal number, got '0x10'" (DecimalInteger),
    // "--seed: is out of range, got '99999999999999999999'" (DecimalInteger,
    // FiniteReal) or "--out: must not be empty" (NonEmptyValue), worded like
    // a conversion error; other validators' text (a Range's "Value 9 not in
    // range 0 to 5") as CLI11 gives it.
    const std::string what = error.what();
    const size_t colon = what.find(": ");
    const std::string_view detail =
        colon == std::string::npos ? std::string_view() : std::string_view(what).substr(colon + 2);
    if (what.rfind("--", 0) == 0 &&
        (detail.rfind("needs a decimal number", 0) == 0 ||
         detail.rfind("is out of range", 0) == 0 || detail == kEmptyValueText)) {
      return usage_error("option " + what.substr(0, colon) + " " + what.substr(colon + 2));
    }
    return usage_error(what);
  } catch (const CLI::ConfigError& error) {
    // CLI11: "INI was not able to parse KEY" for a key no option has.
    const std::string what = error.what();
    const std::string prefix = "INI was not able to parse ";
    if (what.rfind(prefix, 0) == 0) {
      return usage_error("unknown key '" + what.substr(prefix.size()) + "' in the --config file");
    }
    return usage_error(what);
  } catch (const CLI::ParseError& error) {
    return usage_error(error.what());
  }
  return Ok{};
}

int ParseCommandLine(CLI::App& app, std::vector<std::string> args, const std::string& program) {
  try {
    if (Status parsed = ParseArguments(app, std::move(args)); !parsed) {
      std::fprintf(stderr, "%s: %s\n", program.c_str(), parsed.error().message.c_str());
      return 2;
    }
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    return 0;
  }
  return -1;
}

int ParseCommandLine(const std::string& program, const std::string& name,
                     const std::string& description,
                     const std::function<void(OptionGroup&)>& declare,
                     std::vector<std::string> args) {
  CLI::App app(description, name);
  OptionGroup group(app);
  declare(group);
  return ParseCommandLine(app, std::move(args), program);
}

void CloseInheritedFd(const std::string& path) {
  if (path.rfind("/dev/fd/", 0) != 0) return;
  char* end = nullptr;
  const long fd = std::strtol(path.c_str() + 8, &end, 10);
  if (end != path.c_str() + 8 && *end == '\0' && fd > STDERR_FILENO) close(static_cast<int>(fd));
}

void AddConfigOption(CLI::App& app) {
  // A key no option has is a mistake, as an unknown option is.
  app.allow_config_extras(CLI::config_extras_mode::error);
  app.set_config("--config", "",
                 "read options from FILE (CLI11 TOML, key = value with the options' names); "
                 "the command line overrides it")
      ->type_name("FILE");
}

}  // namespace dynapath::runtime
