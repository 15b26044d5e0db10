#include "study/manifest.h"

#include <gtest/gtest.h>

#include <regex>

#include "dynapath/text_file.h"
#include "study/study_plan.h"
#include "tests/temp_path.h"

namespace dynapath::study {
namespace {

Manifest Example() {
  Manifest manifest;
  manifest.version = "0.1.0";
  manifest.git_commit = "abc1234-dirty";
  manifest.git_commit_source = "build";
  Result<StudyOptions> options = ResolveStudyOptions({}, 2);
  manifest.study = StudyIdentityJson(*options);
  manifest.execution = ExecutionJson(*options);
  manifest.machine = CollectMachineInfo();
  manifest.created = "2026-11-22T10:00:00+01:00";
  manifest.started = "2026-11-22T11:00:00+01:00";
  manifest.ended = "";
  manifest.status = "interrupted";
  manifest.sessions = 2;
  for (const StudyConfiguration& configuration : MakeStudyPlan(*options)) {
    manifest.configurations.push_back(FreshRecord(configuration));
  }
  manifest.configurations[0].status = "done";
  manifest.configurations[0].mode = "agents";
  manifest.configurations[0].wall_seconds = 12.3456;
  manifest.configurations[0].started = "2026-11-22T11:00:01+01:00";
  manifest.configurations[1].status = "failed";
  manifest.configurations[1].error = "the run failed (exit status 1); see \"study.log\"";
  return manifest;
}

TEST(ManifestTest, RoundTripsThroughValidJson) {
  const Manifest manifest = Example();
  const std::string path = test_paths::UniqueTempPath("manifest_test.json");
  ASSERT_TRUE(WriteManifest(manifest, path));
  // Valid JSON with the documented top-level keys.
  Result<std::string> text = ReadTextFile(path);
  ASSERT_TRUE(text);
  Result<Json> json = ParseJson(*text);
  ASSERT_TRUE(json) << json.error().message;
  for (const char* key : {"dynapath_version", "git_commit", "status", "created", "started", "ended",
                          "options", "machine", "configurations"}) {
    EXPECT_NE(Member(*json, key), nullptr) << key;
  }
  EXPECT_TRUE((*json)["ended"].is_null());
  EXPECT_EQ((*json)["configurations"][0]["wall_seconds"].get<double>(), 12.346);
  EXPECT_TRUE((*json)["configurations"][2]["wall_seconds"].is_null());

  Result<Manifest> read = ReadManifest(path);
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(read->version, manifest.version);
  EXPECT_EQ(read->git_commit, manifest.git_commit);
  EXPECT_EQ(read->git_commit_source, "build");
  EXPECT_EQ(read->study, manifest.study);
  EXPECT_EQ(read->execution, manifest.execution);
  EXPECT_EQ(read->status, "interrupted");
  EXPECT_EQ(read->created, manifest.created);
  EXPECT_EQ(read->ended, "");
  EXPECT_EQ(read->sessions, 2);
  EXPECT_EQ(read->machine.hostname, manifest.machine.hostname);
  EXPECT_EQ(read->machine.cpu_model, manifest.machine.cpu_model);
  EXPECT_EQ(read->machine.cores, manifest.machine.cores);
  EXPECT_EQ(read->machine.memory_bytes, manifest.machine.memory_bytes);
  ASSERT_EQ(read->configurations.size(), manifest.configurations.size());
  for (size_t i = 0; i < manifest.configurations.size(); ++i) {
    const ConfigurationRecord& a = manifest.configurations[i];
    const ConfigurationRecord& b = read->configurations[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.directory, b.directory);
    EXPECT_EQ(a.size, b.size);
    EXPECT_EQ(a.difficulty, b.difficulty);
    EXPECT_EQ(a.seed, b.seed);
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(a.edge_case, b.edge_case);
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.mode, b.mode);
    EXPECT_EQ(a.error, b.error);
    EXPECT_NEAR(a.wall_seconds, b.wall_seconds, 1e-3);
  }
  EXPECT_EQ(read->Find("edge_50_hard_102")->seed, 102u);
  EXPECT_EQ(read->Find("nothing"), nullptr);
}

TEST(ManifestTest, RejectsBrokenManifests) {
  const std::string path = test_paths::UniqueTempPath("manifest_test_bad.json");
  ASSERT_TRUE(WriteTextFileAtomically(path, "{\"dynapath_version\": \"0.1.0\",\n \"status\": "));
  Result<Manifest> read = ReadManifest(path);
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().message.find("not valid JSON: line 2"), std::string::npos)
      << read.error().message;

  Json json = ManifestToJson(Example());
  json["options"] = "none";
  read = ManifestFromJson(json);
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().message.find("options"), std::string::npos);
  EXPECT_FALSE(ManifestFromJson(Json::array()));
}

TEST(ManifestTest, MachineAndTime) {
  const MachineInfo machine = CollectMachineInfo();
  EXPECT_FALSE(machine.hostname.empty());
  EXPECT_FALSE(machine.cpu_model.empty());
  EXPECT_GT(machine.cores, 0);
  EXPECT_GT(machine.memory_bytes, 0);
  EXPECT_EQ(machine.os.rfind("Linux", 0), 0u) << machine.os;
  EXPECT_TRUE(
      std::regex_match(NowIso8601(), std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d[+-]\d\d:\d\d)")))
      << NowIso8601();
}

}  // namespace
}  // namespace dynapath::study
