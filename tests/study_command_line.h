#pragma once
// A study's command line in tests: NAME/TEXT pairs parsed by CLI11 with the
// study's declaration, as `dynapath experiment` parses its arguments
// ("--NAME=TEXT", "--NAME" "" for an empty one; a boolean "true" is its flag, edge-case "false"
// --no-edge-case, another "false" nothing), then taken as given options.

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "runtime/option_group.h"
#include "study/study_plan.h"

namespace dynapath::study::test_support {

inline Result<GivenStudyOptions> ParseStudyCommandLine(
    std::initializer_list<std::pair<std::string, std::string>> given) {
  CLI::App app;
  runtime::OptionGroup group(app);
  StudyCommandLine parsed;
  DeclareStudyCommandLine(group, parsed);
  std::vector<std::string> args;
  for (const auto& [name, text] : given) {
    const auto kind = StudyOptionKinds().find(name);
    if (kind != StudyOptionKinds().end() && kind->second == runtime::ValueKind::kBoolean) {
      if (text == "true") args.push_back("--" + name);
      if (text == "false" && name == "edge-case") args.push_back("--no-edge-case");
    } else if (text.empty()) {  // "--out ''"
      args.insert(args.end(), {"--" + name, ""});
    } else {
      args.push_back("--" + name + "=" + text);
    }
  }
  if (Status status = runtime::ParseArguments(app, args); !status) return status.error();
  return CommandLineStudyOptions(app, parsed);
}

}  // namespace dynapath::study::test_support
