#pragma once
// OUT/manifest.json of a study: what was run (options, configurations and
// their seeds), with which build (version, git commit), on which machine,
// when, and how each configuration went. Written atomically after every
// change of status; read back to resume a study.

#include <string>
#include <vector>

#include "dynapath/result.h"
#include "study/json.h"
#include "study/study_plan.h"

namespace dynapath::study {

struct MachineInfo {
  std::string hostname;
  std::string cpu_model;  // /proc/cpuinfo "model name"
  int cores = 0;          // hardware threads
  long long memory_bytes = 0;
  std::string os;  // uname: "Linux 6.1.0-18-amd64 x86_64"
};
MachineInfo CollectMachineInfo();

// Status of a configuration: "pending", "running", "done", "failed" or
// "interrupted".
struct ConfigurationRecord {
  std::string name;  // "20_easy_50"
  std::string directory;
  int size = 0;
  std::string difficulty;  // "Easy"
  unsigned seed = 0;
  int steps = 0;
  bool edge_case = false;
  std::string status = "pending";
  std::string mode;  // how it ran: "local", "agents" or "embedded"
  std::string started, ended;
  double wall_seconds = -1;  // < 0: not known
  std::string error;
};
// The pending record of a configuration of the plan.
ConfigurationRecord FreshRecord(const StudyConfiguration& configuration);

struct Manifest {
  std::string version;
  std::string git_commit;         // "unknown" when not known
  std::string git_commit_source;  // "build", or "" when unknown
  Json study;                     // StudyIdentityJson: must match to resume
  Json execution;                 // ExecutionJson of the latest session
  MachineInfo machine;
  std::string created;             // first session's start
  std::string started, ended;      // latest session
  std::string status = "running";  // running, finished, failed, interrupted
  int sessions = 1;
  std::vector<ConfigurationRecord> configurations;

  // The record named `name`, or nullptr.
  ConfigurationRecord* Find(const std::string& name);
};

Json ManifestToJson(const Manifest& manifest);
// Fails when a key field is missing or has the wrong type.
Result<Manifest> ManifestFromJson(const Json& json);
Status WriteManifest(const Manifest& manifest, const std::string& path);
Result<Manifest> ReadManifest(const std::string& path);

// The current local time, ISO 8601 with the UTC offset
// ("2026-11-22T15:30:12+01:00").
std::string NowIso8601();

}  // namespace dynapath::study
