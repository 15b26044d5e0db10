#include "tools/common/study_config.h"

#include <toml++/toml.h>

#include <algorithm>

#include "dynapath/text_file.h"

namespace dynapath::cli {
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
      return FailAt(
          name, value.line,
          "'" + key + "' is a table: study options are 'key = value' lines at the top level");
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
    file.entries.push_back(ConfigEntry{std::string(key.str()), std::move(*value), line});
  }
  // toml++ keeps keys sorted; the file's order reads better in messages.
  std::stable_sort(file.entries.begin(), file.entries.end(),
                   [](const ConfigEntry& a, const ConfigEntry& b) { return a.line < b.line; });
  return file;
}

Result<ConfigFile> ReadConfigFile(const std::string& path) {
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  return ParseConfigText(*text, path);
}

}  // namespace dynapath::cli
