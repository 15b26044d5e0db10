#include "study/study_config.h"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>

#include "dynapath/text_file.h"

namespace dynapath::study {
namespace {

int LineOf(const toml::node& node) { return static_cast<int>(node.source().begin.line); }

Error FailAt(const std::string& name, int line, const std::string& message) {
  return Error::Corrupt(name + ":" + std::to_string(line) + ": " + message);
}

// A scalar or an array of scalars of one kind; anything else is refused.
Result<ConfigValue> Convert(const toml::node& node, const std::string& key, const std::string& name,
                            bool in_array) {
  ConfigValue value;
  value.line = LineOf(node);
  switch (node.type()) {
    case toml::node_type::string:
      value.kind = ConfigValue::Kind::kString;
      value.string = node.as_string()->get();
      return value;
    case toml::node_type::integer:
      value.kind = ConfigValue::Kind::kInteger;
      value.integer = node.as_integer()->get();
      return value;
    case toml::node_type::floating_point:
      value.kind = ConfigValue::Kind::kFloat;
      value.number = node.as_floating_point()->get();
      return value;
    case toml::node_type::boolean:
      value.kind = ConfigValue::Kind::kBoolean;
      value.boolean = node.as_boolean()->get();
      return value;
    case toml::node_type::array: {
      if (in_array) return FailAt(name, value.line, "'" + key + "': nested arrays are not options");
      value.kind = ConfigValue::Kind::kArray;
      for (const toml::node& item : *node.as_array()) {
        Result<ConfigValue> converted = Convert(item, key, name, true);
        if (!converted) return converted.error();
        if (!value.items.empty() && value.items.front().kind != converted->kind) {
          return FailAt(name, converted->line,
                        "'" + key + "': an array mixes " + value.items.front().KindName() +
                            "s and " + converted->KindName() + "s");
        }
        value.items.push_back(std::move(*converted));
      }
      return value;
    }
    case toml::node_type::table:
      return FailAt(name, value.line,
                    "'" + key + "' is a table: options are 'key = value' lines at the top level");
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time:
      return FailAt(name, value.line, "'" + key + "': dates and times are not options");
    case toml::node_type::none:
      break;
  }
  return FailAt(name, value.line, "'" + key + "': unsupported value");
}

}  // namespace

std::string ConfigValue::KindName() const {
  switch (kind) {
    case Kind::kString:
      return "string";
    case Kind::kInteger:
      return "integer";
    case Kind::kFloat:
      return "float";
    case Kind::kBoolean:
      return "boolean";
    case Kind::kArray:
      return "array";
  }
  return "?";
}

std::string ConfigValue::Text() const {
  switch (kind) {
    case Kind::kString:
      return string;
    case Kind::kInteger:
      return std::to_string(integer);
    case Kind::kFloat: {
      char text[32];  // shortest round-trip form, whatever the locale
      const auto end = std::to_chars(text, text + sizeof text, number).ptr;
      return std::string(text, end);
    }
    case Kind::kBoolean:
      return boolean ? "true" : "false";
    case Kind::kArray: {
      std::string joined;
      for (const ConfigValue& item : items) joined += (joined.empty() ? "" : ",") + item.Text();
      return joined;
    }
  }
  return "";
}

Result<ConfigFile> ParseConfigText(std::string_view text, const std::string& name) {
  ConfigFile file;
  file.name = name;
  toml::table table;
  try {
    table = toml::parse(text, name);
  } catch (const toml::parse_error& error) {
    return FailAt(name, static_cast<int>(error.source().begin.line),
                  std::string(error.description()));
  }
  for (const auto& [key, node] : table) {
    Result<ConfigValue> value = Convert(node, std::string(key.str()), name, false);
    if (!value) return value.error();
    const int line = static_cast<int>(key.source().begin.line);
    std::string written(key.str());
    std::string dashed = written;
    std::replace(dashed.begin(), dashed.end(), '_', '-');
    file.entries.push_back(ConfigEntry{dashed, written, std::move(*value), line});
  }
  // toml++ keeps keys sorted; the file's order reads better in messages.
  std::stable_sort(file.entries.begin(), file.entries.end(),
                   [](const ConfigEntry& a, const ConfigEntry& b) { return a.line < b.line; });
  // toml++ refuses a key written twice alike; two spellings of one option
  // would otherwise both be kept and the last one win unseen.
  std::map<std::string, const ConfigEntry*> first;
  for (const ConfigEntry& entry : file.entries) {
    const auto [earlier, fresh] = first.emplace(entry.key, &entry);
    if (!fresh) {
      return FailAt(name, entry.line,
                    "'" + entry.written + "' gives '" + earlier->second->written + "' of line " +
                        std::to_string(earlier->second->line) +
                        " again (one option, '-' or '_'): keep one");
    }
  }
  return file;
}

Result<ConfigFile> ReadConfigFile(const std::string& path) {
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  return ParseConfigText(*text, path);
}

Status SetOptionFields(const ConfigFile& file, const runtime::OptionFields& fields,
                       const std::function<bool(const std::string& key)>& skip) {
  using Kind = ConfigValue::Kind;
  for (const ConfigEntry& entry : file.entries) {
    if (skip && skip(entry.key)) continue;
    const std::string where = file.name + ":" + std::to_string(entry.line);
    const auto field = fields.find(entry.key);
    if (field == fields.end()) {
      return Error{where + ": unknown key '" + entry.written + "'"};
    }
    const ConfigValue& value = entry.value;
    const std::string origin = where + ": " + entry.key;
    auto wrong = [&](const std::string& expected) {
      const bool an = value.kind == Kind::kArray || value.kind == Kind::kInteger;
      return Error{origin + ": expected " + expected + ", got " + (an ? "an " : "a ") +
                   value.KindName()};
    };
    const runtime::ValueKind kind = field->second.kind;
    // A text option takes any value as its text ("stations = 5", an array's
    // items joined by ','), as CLI11 takes a --config file's values; a list
    // option an array's items, or another value's text as a command line's
    // list.
    const bool text = kind == runtime::ValueKind::kString ||
                      kind == runtime::ValueKind::kIntegerList ||
                      kind == runtime::ValueKind::kStringList;
    if (kind == runtime::ValueKind::kInteger && value.kind != Kind::kInteger) {
      return wrong("an integer");
    }
    if (kind == runtime::ValueKind::kFloat && value.kind != Kind::kFloat &&
        value.kind != Kind::kInteger) {
      return wrong("a number");
    }
    if (kind == runtime::ValueKind::kFloat && !std::isfinite(value.number)) {
      return Error{origin + ": expected a finite number, got " + value.Text()};
    }
    if (kind == runtime::ValueKind::kBoolean && value.kind != Kind::kBoolean) {
      return wrong("a boolean");
    }
    if (text && value.Text().empty()) return Error{origin + ": must not be empty"};
    switch (kind) {
      case runtime::ValueKind::kBoolean:
        runtime::SetOptionBoolean(field->second, value.boolean);
        break;
      case runtime::ValueKind::kInteger:
        runtime::SetOptionInteger(field->second, value.integer);
        break;
      case runtime::ValueKind::kFloat:
        runtime::SetOptionReal(field->second, value.kind == Kind::kFloat
                                                  ? value.number
                                                  : static_cast<double>(value.integer));
        break;
      case runtime::ValueKind::kIntegerList:
      case runtime::ValueKind::kStringList: {
        std::vector<std::string> items;
        if (value.kind == Kind::kArray) {
          for (const ConfigValue& item : value.items) items.push_back(item.Text());
        } else {
          items = runtime::SplitList(value.Text());
        }
        runtime::SetOptionList(field->second, std::move(items));
        break;
      }
      case runtime::ValueKind::kString:
        runtime::SetOptionText(field->second, value.Text());
        break;
    }
  }
  return Ok{};
}

}  // namespace dynapath::study
