#pragma once
// The dynapath subcommands. Each returns the process exit code.

#include <string>
#include <vector>

namespace dynapath::cli {

int MazeCommand(const std::vector<std::string>& args);
int RunCommand(const std::vector<std::string>& args);
// Runs a whole study (sizes x difficulties, edge case), resumable. With
// --agents it enters a private network namespace, so it must be called
// while the process has a single thread.
int ExperimentCommand(const std::vector<std::string>& args);
// Runs a command in a private network namespace (launch/private_network.h). Must be
// called while the process has a single thread.
int NetnsCommand(const std::vector<std::string>& args);
// Writes a new run secret to a file (mode 600) for processes started by hand.
int SecretCommand(const std::vector<std::string>& args);
// The planning service on the bus and its clients (docs/howto/SERVICE.md).
// serve enters a private network without --lcm-url, so it must be called
// while the process has a single thread.
int ServeCommand(const std::vector<std::string>& args);
int QueryCommand(const std::vector<std::string>& args);
int FeedCommand(const std::vector<std::string>& args);
int RobotsCommand(const std::vector<std::string>& args);
// Lists the learner and strategy parameters (dynapath/parameters.h).
int ParamsCommand(const std::vector<std::string>& args);
// The paired difference of two approaches over the repeats of a study.
int CompareCommand(const std::vector<std::string>& args);
// Trains convQ's model from a seed and writes the model file.
int TrainModelCommand(const std::vector<std::string>& args);
// Replaces this process with the executable `tool` that sits next to the
// dynapath binary (plot, view, render), passing `args`; when it is missing,
// prints one error naming `missing_hint` and returns kExitFailure.
int SiblingCommand(const std::string& tool, const std::vector<std::string>& args,
                   const std::string& missing_hint);
// The same as a child process: runs `tool` with `args`, waits for it and
// returns its exit status (kExitFailure when it is missing or killed).
int RunSibling(const std::string& tool, const std::vector<std::string>& args,
               const std::string& missing_hint);

// True when --approach (`option`) names a Python approach (py:MODULE:CLASS).
bool NamesPythonApproach(const std::vector<std::string>& args, const std::string& option);
// Replaces this process with `python3 -m dynapath COMMAND ARGS` of the
// Python module built alongside (tools/cli/python_handoff.cc); when it was
// not built, one error and kExitUsage.
int PythonCommand(const std::string& command, const std::vector<std::string>& args);

// Exit codes: 0 success, 1 run-time failure, 2 bad usage, 130 interrupted.
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitInterrupted = 130;  // stopped by Ctrl-C or SIGTERM before a result

}  // namespace dynapath::cli
