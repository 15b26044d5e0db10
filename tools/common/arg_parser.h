#pragma once
// A small declarative command-line parser: options are declared with their
// help text, parsed from "--name value" or "--name=value", and every error is
// one clear sentence. Shared by the dynapath subcommands.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"

namespace dynapath::cli {

class ArgParser {
 public:
  ArgParser(std::string usage, std::string summary);

  // An option taking a value. `default_text` is shown in --help only.
  void AddOption(const std::string& name, const std::string& value_name, const std::string& help,
                 const std::string& default_text = "");
  // An option without a value.
  void AddFlag(const std::string& name, const std::string& help);

  // Parses `args` (without the program and subcommand names). --help is a
  // flag every parser has.
  Status Parse(const std::vector<std::string>& args);

  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  std::string Get(const std::string& name, const std::string& fallback = "") const;
  // Integer option in [min, max]; `fallback` when absent.
  Result<long long> GetInt(const std::string& name, long long fallback, long long min,
                           long long max) const;
  // The given options that were set, as arguments ("--name", "value") to
  // pass on to another program.
  std::vector<std::string> Forward(const std::vector<std::string>& names) const;
  bool WantsHelp() const { return Has("help"); }
  std::string Help() const;

 private:
  struct Spec {
    std::string name, value_name, help, default_text;
    bool takes_value;
  };
  const Spec* Find(const std::string& name) const;

  std::string usage_, summary_;
  std::vector<Spec> specs_;
  std::map<std::string, std::string> values_;
};

}  // namespace dynapath::cli
