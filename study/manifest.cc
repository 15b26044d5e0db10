#include "study/manifest.h"

#include <sys/utsname.h>
#include <unistd.h>

#include <cmath>
#include <ctime>
#include <fstream>
#include <thread>

#include "dynapath/text_file.h"
#include "dynapath/text_util.h"

namespace dynapath::study {
namespace {

std::string CpuModel() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = Trim(line.substr(0, colon));
    // x86: "model name"; some ARM kernels: "Processor" or "Hardware".
    if (key == "model name" || key == "Processor" || key == "Hardware") {
      return Trim(line.substr(colon + 1));
    }
  }
  return "unknown";
}

long long MemoryBytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  long long kilobytes = 0;
  while (meminfo >> key >> kilobytes) {
    if (key == "MemTotal:") return kilobytes * 1024;
    meminfo.ignore(1 << 16, '\n');
  }
  return 0;
}

Json MachineJson(const MachineInfo& machine) {
  Json json = Json::object();
  json["hostname"] = machine.hostname;
  json["cpu_model"] = machine.cpu_model;
  json["cores"] = machine.cores;
  json["memory_bytes"] = machine.memory_bytes;
  json["os"] = machine.os;
  return json;
}

Json OptionalString(const std::string& text) { return text.empty() ? Json() : Json(text); }

// Reads member `key` of `object`: a string (or null: "") / number / bool.
bool GetString(const Json& object, const std::string& key, std::string& out, bool required) {
  const Json* value = Member(object, key);
  if (value == nullptr || value->is_null()) return !required;
  if (!value->is_string()) return false;
  out = value->get<std::string>();
  return true;
}

// The number `value` holds, or `fallback` (missing, or not a number).
long long IntOr(const Json* value, long long fallback) {
  return value != nullptr && value->is_number() ? value->get<long long>() : fallback;
}
double NumberOr(const Json* value, double fallback) {
  return value != nullptr && value->is_number() ? value->get<double>() : fallback;
}

}  // namespace

ConfigurationRecord FreshRecord(const StudyConfiguration& configuration) {
  ConfigurationRecord record;
  record.name = configuration.Name();
  record.directory = configuration.Directory();
  record.size = configuration.size;
  record.difficulty = configuration.DifficultyText();
  record.seed = configuration.seed;
  record.steps = configuration.steps;
  record.edge_case = configuration.edge_case;
  return record;
}

MachineInfo CollectMachineInfo() {
  MachineInfo machine;
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) == 0) machine.hostname = host;
  machine.cpu_model = CpuModel();
  machine.cores = static_cast<int>(std::thread::hardware_concurrency());
  machine.memory_bytes = MemoryBytes();
  struct utsname name {};
  if (uname(&name) == 0) {
    machine.os = std::string(name.sysname) + " " + name.release + " " + name.machine;
  }
  // The distribution, when it says.
  std::ifstream release("/etc/os-release");
  std::string line;
  while (std::getline(release, line)) {
    if (line.rfind("PRETTY_NAME=", 0) == 0) {
      std::string pretty = line.substr(12);
      if (pretty.size() >= 2 && pretty.front() == '"') pretty = pretty.substr(1, pretty.size() - 2);
      machine.os += " (" + pretty + ")";
    }
  }
  return machine;
}

ConfigurationRecord* Manifest::Find(const std::string& name) {
  for (ConfigurationRecord& record : configurations) {
    if (record.name == name) return &record;
  }
  return nullptr;
}

Json ManifestToJson(const Manifest& manifest) {
  Json json = Json::object();
  json["dynapath_version"] = manifest.version;
  json["git_commit"] = manifest.git_commit;
  json["git_commit_source"] = OptionalString(manifest.git_commit_source);
  json["status"] = manifest.status;
  json["created"] = OptionalString(manifest.created);
  json["started"] = OptionalString(manifest.started);
  json["ended"] = OptionalString(manifest.ended);
  json["sessions"] = manifest.sessions;
  Json& options = json["options"] = Json::object();
  options["study"] = manifest.study;
  options["execution"] = manifest.execution;
  json["machine"] = MachineJson(manifest.machine);
  Json& configurations = json["configurations"] = Json::array();
  for (const ConfigurationRecord& record : manifest.configurations) {
    Json entry = Json::object();
    entry["name"] = record.name;
    entry["directory"] = record.directory;
    entry["size"] = record.size;
    entry["difficulty"] = record.difficulty;
    entry["seed"] = record.seed;
    entry["steps"] = record.steps;
    entry["edge_case"] = record.edge_case;
    entry["status"] = record.status;
    entry["mode"] = OptionalString(record.mode);
    entry["started"] = OptionalString(record.started);
    entry["ended"] = OptionalString(record.ended);
    entry["wall_seconds"] =
        record.wall_seconds < 0 ? Json() : Json(std::round(record.wall_seconds * 1000) / 1000);
    entry["error"] = OptionalString(record.error);
    configurations.push_back(std::move(entry));
  }
  return json;
}

Result<Manifest> ManifestFromJson(const Json& json) {
  if (!json.is_object()) return Error::Corrupt("the manifest is not a JSON object");
  Manifest manifest;
  auto bad = [](const std::string& what) {
    return Error{"manifest: missing or bad " + what, Error::Code::kCorrupt, what};
  };
  if (!GetString(json, "dynapath_version", manifest.version, true)) return bad("dynapath_version");
  if (!GetString(json, "git_commit", manifest.git_commit, false)) return bad("git_commit");
  if (!GetString(json, "git_commit_source", manifest.git_commit_source, false)) {
    return bad("git_commit_source");
  }
  if (!GetString(json, "status", manifest.status, true)) return bad("status");
  for (auto [key, field] :
       {std::pair{"created", &manifest.created}, std::pair{"started", &manifest.started},
        std::pair{"ended", &manifest.ended}}) {
    if (!GetString(json, key, *field, false)) return bad(key);
  }
  manifest.sessions = static_cast<int>(IntOr(Member(json, "sessions"), 1));
  const Json* options = Member(json, "options");
  if (options == nullptr || !options->is_object()) return bad("options");
  const Json* study = Member(*options, "study");
  if (study == nullptr || !study->is_object()) return bad("options.study");
  manifest.study = *study;
  if (const Json* execution = Member(*options, "execution")) manifest.execution = *execution;
  if (const Json* machine = Member(json, "machine"); machine != nullptr && machine->is_object()) {
    GetString(*machine, "hostname", manifest.machine.hostname, false);
    GetString(*machine, "cpu_model", manifest.machine.cpu_model, false);
    GetString(*machine, "os", manifest.machine.os, false);
    manifest.machine.cores = static_cast<int>(IntOr(Member(*machine, "cores"), 0));
    manifest.machine.memory_bytes = IntOr(Member(*machine, "memory_bytes"), 0);
  }
  const Json* configurations = Member(json, "configurations");
  if (configurations == nullptr || !configurations->is_array()) return bad("configurations");
  for (const Json& entry : *configurations) {
    if (!entry.is_object()) return bad("configuration entry");
    ConfigurationRecord record;
    if (!GetString(entry, "name", record.name, true)) return bad("configuration name");
    if (!GetString(entry, "status", record.status, true)) return bad("configuration status");
    GetString(entry, "directory", record.directory, false);
    GetString(entry, "difficulty", record.difficulty, false);
    GetString(entry, "mode", record.mode, false);
    GetString(entry, "started", record.started, false);
    GetString(entry, "ended", record.ended, false);
    GetString(entry, "error", record.error, false);
    record.size = static_cast<int>(IntOr(Member(entry, "size"), 0));
    record.seed = static_cast<unsigned>(IntOr(Member(entry, "seed"), 0));
    record.steps = static_cast<int>(IntOr(Member(entry, "steps"), 0));
    const Json* edge = Member(entry, "edge_case");
    record.edge_case = edge != nullptr && edge->is_boolean() && edge->get<bool>();
    record.wall_seconds = NumberOr(Member(entry, "wall_seconds"), -1);
    manifest.configurations.push_back(std::move(record));
  }
  return manifest;
}

Status WriteManifest(const Manifest& manifest, const std::string& path) {
  return WriteTextFileAtomically(path, DumpJson(ManifestToJson(manifest)));
}

Result<Manifest> ReadManifest(const std::string& path) {
  Result<std::string> text = ReadTextFile(path);
  if (!text) return text.error();
  Result<Json> json = ParseJson(*text);
  if (!json) return json.error().Prefixed(path + ": not valid JSON: ");
  Result<Manifest> manifest = ManifestFromJson(*json);
  if (!manifest) return manifest.error().Prefixed(path + ": ");
  return manifest;
}

std::string NowIso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char stamp[40];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S%z", &local);
  // %z gives +0100; ISO 8601 extended wants +01:00.
  const std::string text = stamp;
  if (text.size() < 5) return text;
  return text.substr(0, text.size() - 2) + std::string(":") + text.substr(text.size() - 2);
}

}  // namespace dynapath::study
