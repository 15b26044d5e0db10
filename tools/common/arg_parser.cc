#include "tools/common/arg_parser.h"

#include <cerrno>
#include <cstdlib>

namespace dynapath::cli {

ArgParser::ArgParser(std::string usage, std::string summary)
    : usage_(std::move(usage)), summary_(std::move(summary)) {
  AddFlag("help", "show this help and exit");
}

void ArgParser::AddOption(const std::string& name, const std::string& value_name,
                          const std::string& help, const std::string& default_text) {
  specs_.push_back({name, value_name, help, default_text, true});
}

void ArgParser::AddFlag(const std::string& name, const std::string& help) {
  specs_.push_back({name, "", help, "", false});
}

const ArgParser::Spec* ArgParser::Find(const std::string& name) const {
  for (const Spec& spec : specs_) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

Status ArgParser::Parse(const std::vector<std::string>& args) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "-h") {
      values_["help"] = "";
      continue;
    }
    if (arg.rfind("--", 0) != 0 || arg.size() == 2) {
      return Error{"unexpected argument '" + arg + "' (see --help)"};
    }
    std::string name = arg.substr(2);
    std::optional<std::string> value;
    if (const size_t equals = name.find('='); equals != std::string::npos) {
      value = name.substr(equals + 1);
      name = name.substr(0, equals);
    }
    const Spec* spec = Find(name);
    if (!spec) return Error{"unknown option --" + name + " (see --help)"};
    if (spec->takes_value) {
      if (!value) {
        if (i + 1 >= args.size()) return Error{"option --" + name + " needs a value"};
        value = args[++i];
      }
      values_[name] = *value;
    } else {
      if (value) return Error{"option --" + name + " takes no value"};
      values_[name] = "";
    }
  }
  return Ok{};
}

std::string ArgParser::Get(const std::string& name, const std::string& fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

Result<long long> ArgParser::GetInt(const std::string& name, long long fallback, long long min,
                                    long long max) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  const std::string& text = it->second;
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE) {
    return Error{"option --" + name + " needs an integer, got '" + text + "'"};
  }
  if (value < min || value > max) {
    return Error{"option --" + name + " must be between " + std::to_string(min) + " and " +
                 std::to_string(max) + ", got " + text};
  }
  return value;
}

std::string ArgParser::Help() const {
  std::string help = "Usage: " + usage_ + "\n\n" + summary_ + "\n\nOptions:\n";
  for (const Spec& spec : specs_) {
    std::string left = "  --" + spec.name + (spec.takes_value ? " " + spec.value_name : "");
    if (left.size() < 28)
      left.resize(28, ' ');
    else
      left += "\n" + std::string(28, ' ');
    help += left + spec.help;
    if (!spec.default_text.empty()) help += " (default: " + spec.default_text + ")";
    help += "\n";
  }
  return help;
}

std::vector<std::string> ArgParser::Forward(const std::vector<std::string>& names) const {
  std::vector<std::string> args;
  for (const std::string& name : names) {
    auto it = values_.find(name);
    if (it == values_.end()) continue;
    args.push_back("--" + name);
    const Spec* spec = Find(name);
    if (spec != nullptr && spec->takes_value) args.push_back(it->second);
  }
  return args;
}

}  // namespace dynapath::cli
