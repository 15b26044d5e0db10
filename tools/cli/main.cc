// dynapath: the command-line entry point. Dispatches to a subcommand.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "tools/cli/commands.h"
#include "tools/common/build_info.h"

namespace {

constexpr const char* kUsage =
    "Usage: dynapath <command> [options]\n"
    "\n"
    "Path planning in dynamic mazes with hierarchical multi-agent Q-learning.\n"
    "\n"
    "Commands:\n"
    "  maze        generate or load a maze and print it with its facts\n"
    "  run         run approaches on a maze and its change sequence, write result CSVs\n"
    "  experiment  run a whole study (sizes x difficulties, edge case), resumable\n"
    "  serve       answer path queries over LCM while the map changes (a planning service)\n"
    "  query       ask a service for paths, or measure its query latency\n"
    "  feed        publish a change sequence to a service as live obstacle updates\n"
    "  robots      a simulated robot fleet in closed loop with a service\n"
    "  netns       run a command in a private, loopback-only network (for LCM)\n"
    "  secret      write a new run secret to a file, for processes started by hand\n"
    "  params      list the learner and strategy parameters (defaults, ranges, help)\n"
    "  compare     paired difference of two approaches over a study's repeats, with its interval\n"
    "  train-model train convQ's model from a seed and write the model file\n"
    "  plot        draw the report's figures from a study's result files (PNG)\n"
    "  view        watch a run's policy live in a window\n"
    "  render      draw a logged run's policy as PNG frames and an animated GIF\n"
    "  web         watch a run or a service live in a browser or in Foxglove (one port)\n"
    "  log-to-mcap write an LCM log's run messages as MCAP (Foxglove, Lichtblick)\n"
    "\n"
    "Run 'dynapath <command> --help' for the options of a command.\n";

}  // namespace

int main(int argc, char** argv) {
  // Logs go to stderr so stdout stays clean for results.
  spdlog::set_default_logger(spdlog::stderr_color_mt("dynapath"));
  spdlog::set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return dynapath::cli::kExitUsage;
  }
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  if (command == "--help" || command == "-h" || command == "help") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (command == "--version") {
    std::printf("dynapath %s\n", dynapath::cli::kDynapathVersion);
    return 0;
  }
  if (command == "maze") return dynapath::cli::MazeCommand(args);
  // An approach written in Python: the Python module runs it (python_handoff.cc).
  if ((command == "run" && dynapath::cli::NamesPythonApproach(args, "--approach")) ||
      (command == "experiment" && dynapath::cli::NamesPythonApproach(args, "--approaches"))) {
    return dynapath::cli::PythonCommand(command, args);
  }
  if (command == "run") return dynapath::cli::RunCommand(args);
  // Single-threaded too (--agents enters a private network namespace).
  if (command == "experiment") return dynapath::cli::ExperimentCommand(args);
  // Still single-threaded here, as unshare(CLONE_NEWUSER) requires: the
  // synchronous stderr logger starts no thread.
  if (command == "netns") return dynapath::cli::NetnsCommand(args);
  // Single-threaded too (without --lcm-url it enters a private network).
  if (command == "serve") return dynapath::cli::ServeCommand(args);
  if (command == "query") return dynapath::cli::QueryCommand(args);
  if (command == "feed") return dynapath::cli::FeedCommand(args);
  if (command == "robots") return dynapath::cli::RobotsCommand(args);
  if (command == "secret") return dynapath::cli::SecretCommand(args);
  if (command == "params") return dynapath::cli::ParamsCommand(args);
  if (command == "compare") return dynapath::cli::CompareCommand(args);
  if (command == "train-model") return dynapath::cli::TrainModelCommand(args);
  if (command == "plot") {
    return dynapath::cli::SiblingCommand("dynapath-plot", args,
                                         "it is installed with the build from tools/plot");
  }
  if (command == "view") {
    return dynapath::cli::SiblingCommand("dynapath-view", args,
                                         "it is built only when libsfml-dev is installed");
  }
  if (command == "render") {
    return dynapath::cli::SiblingCommand("dynapath-render", args,
                                         "it is built with the project from tools/view");
  }
  if (command == "web") {
    return dynapath::cli::SiblingCommand("dynapath-web", args,
                                         "it is built only when libwebsocketpp-dev is installed");
  }
  if (command == "log-to-mcap") {
    return dynapath::cli::SiblingCommand("dynapath-log-to-mcap", args,
                                         "it is built only when libwebsocketpp-dev is installed");
  }
  std::fprintf(stderr, "dynapath: unknown command '%s' (see dynapath --help)\n", command.c_str());
  return dynapath::cli::kExitUsage;
}
