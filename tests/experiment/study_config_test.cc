#include "study/study_config.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/temp_path.h"

namespace dynapath::study {
namespace {

TEST(StudyConfigTest, ParsesTheSubset) {
  const char* text =
      "# A study\n"
      "sizes = [20, 50,\n"
      "         100]   # trailing comment\n"
      "\n"
      "difficulties = [\"easy\", 'hard',]\n"
      "approaches = \"BFS Oracle\"\n"
      "edge-case = false\n"
      "edge_case2 = true\n"
      "steps = 1_000\n"
      "seed = -3\n"
      "out = \"a \\\"quoted\\\" dir\\\\x\"\n"
      "path = 'C:\\raw'\n"
      "  indented = 1\n";
  Result<ConfigFile> file = ParseConfigText(text, "study.toml");
  ASSERT_TRUE(file) << file.error().message;
  const std::vector<ConfigEntry>& e = file->entries;
  ASSERT_EQ(e.size(), 10u);
  EXPECT_EQ(e[0].key, "sizes");
  EXPECT_EQ(e[0].line, 2);
  ASSERT_EQ(e[0].value.kind, ConfigValue::Kind::kArray);
  ASSERT_EQ(e[0].value.items.size(), 3u);
  EXPECT_EQ(e[0].value.items[2].integer, 100);
  EXPECT_EQ(e[0].value.items[2].line, 3);
  EXPECT_EQ(e[1].key, "difficulties");
  EXPECT_EQ(e[1].line, 5);
  ASSERT_EQ(e[1].value.items.size(), 2u);
  EXPECT_EQ(e[1].value.items[1].string, "hard");
  EXPECT_EQ(e[2].value.kind, ConfigValue::Kind::kString);
  EXPECT_EQ(e[2].value.string, "BFS Oracle");
  EXPECT_EQ(e[3].key, "edge-case");
  EXPECT_EQ(e[3].value.kind, ConfigValue::Kind::kBoolean);
  EXPECT_FALSE(e[3].value.boolean);
  EXPECT_TRUE(e[4].value.boolean);
  EXPECT_EQ(e[5].value.integer, 1000);
  EXPECT_EQ(e[6].value.integer, -3);
  EXPECT_EQ(e[7].value.string, "a \"quoted\" dir\\x");
  EXPECT_EQ(e[8].value.string, "C:\\raw");
  EXPECT_EQ(e[9].key, "indented");
  EXPECT_EQ(e[9].line, 13);
}

// Either spelling names one option; one option given twice under two
// spellings is refused with both lines, not the last one silently winning.
TEST(StudyConfigTest, KeysTakeEitherSpellingOnce) {
  Result<ConfigFile> file = ParseConfigText("epsilon_start = 0.5\nedge-case = false\n", "f");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_EQ(file->entries[0].key, "epsilon-start");
  EXPECT_EQ(file->entries[0].written, "epsilon_start");
  EXPECT_EQ(file->entries[1].key, "edge-case");
  file = ParseConfigText("epsilon-start = 0.5\n# between\nepsilon_start = 0.6\n", "s.toml");
  ASSERT_FALSE(file);
  EXPECT_EQ(file.error().message,
            "s.toml:3: 'epsilon_start' gives 'epsilon-start' of line 1 again (one option, '-' or "
            "'_'): keep one");
  file = ParseConfigText("edge_case = true\nedge-case = false\n", "s.toml");
  ASSERT_FALSE(file);
  EXPECT_EQ(file.error().message.rfind("s.toml:2: 'edge-case' gives 'edge_case' of line 1", 0), 0u)
      << file.error().message;
}

TEST(StudyConfigTest, EmptyFileAndEmptyArray) {
  Result<ConfigFile> file = ParseConfigText("# nothing\n\n", "f");
  ASSERT_TRUE(file);
  EXPECT_TRUE(file->entries.empty());
  file = ParseConfigText("sizes = []", "f");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_TRUE(file->entries[0].value.items.empty());
}

// Every error names the file and the line (toml++'s own description, or
// what a study cannot take).
TEST(StudyConfigTest, ErrorsNameTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"sizes = [20]\n[study]\n", "f.toml:2: 'study' is a table"},
      {"a = 1\nout = \"unterminated\n", "f.toml:2: Error while parsing string"},
      {"\nsizes = [20,\n 50\n", "f.toml:3: Error while parsing array: encountered end-of-file"},
      {"\n\nbootstrap = in-grid\n", "f.toml:3: Error while parsing"},
      {"seed = 1\nsteps = 2\nseed = 3\n",
       "f.toml:3: Error while parsing key-value pair: cannot "
       "redefine existing integer 'seed'"},
      {"steps =\n", "f.toml:1: Error while parsing key-value pair: expected value"},
      {"sizes = [[20]]\n", "f.toml:1: 'sizes': nested arrays"},
      {"sizes = [20,\n \"fifty\"]\n", "f.toml:2: 'sizes': an array mixes integers and strings"},
      {"steps = 10 20\n", "f.toml:1: Error while parsing key-value pair"},
      {"a.b = 1\n", "f.toml:1: 'a' is a table"},
      {"sizes [20]\n", "f.toml:1: Error while parsing key-value pair: expected '='"},
      {"x = {a = 1}\n", "f.toml:1: 'x' is a table"},
      {"x = \"\\q\"\n", "f.toml:1: Error while parsing string: unknown escape sequence"},
      {"x = 99999999999999999999\n", "f.toml:1: Error while parsing decimal integer"},
      {"x = 007\n", "f.toml:1: Error while parsing decimal integer: leading zeroes"},
      {"d = 1979-05-27\n", "f.toml:1: 'd': dates and times are not options"},
      {"= 3\n", "f.toml:1: Error while parsing root table"},
  };
  for (const auto& [text, expected] : cases) {
    Result<ConfigFile> file = ParseConfigText(text, "f.toml");
    ASSERT_FALSE(file) << text;
    EXPECT_EQ(file.error().message.rfind(expected, 0), 0u)
        << "for:\n"
        << text << "got: " << file.error().message;
  }
}

// Real TOML: what the former hand-written subset refused is read.
TEST(StudyConfigTest, ReadsFloatsQuotedKeysAndMultiLineStrings) {
  Result<ConfigFile> file =
      ParseConfigText("fraction = 0.5\n\"quoted key\" = 1\nnote = \"\"\"two\nlines\"\"\"\n", "f");
  ASSERT_TRUE(file) << file.error().message;
  ASSERT_EQ(file->entries.size(), 3u);
  EXPECT_EQ(file->entries[0].value.kind, ConfigValue::Kind::kFloat);
  EXPECT_EQ(file->entries[0].value.number, 0.5);
  EXPECT_EQ(file->entries[1].key, "quoted key");
  EXPECT_EQ(file->entries[2].value.string, "two\nlines");
}

TEST(StudyConfigTest, ReadsAFileAndReportsAMissingOne) {
  const std::string path = test_paths::UniqueTempPath("study_config_test.toml");
  {
    std::ofstream out(path);
    out << "sizes = [20]\n";
  }
  Result<ConfigFile> file = ReadConfigFile(path);
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_EQ(file->name, path);
  Result<ConfigFile> missing = ReadConfigFile(path + ".missing");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find(".missing"), std::string::npos);
}

// A file's values set into declared option fields (what `run --resume`
// reads a checkpoint's run.toml with): each of its option's kind, text
// options taking any value as text, skipped keys left alone.
TEST(StudyConfigTest, SetsDeclaredOptionFields) {
  std::string name = "default";
  std::optional<std::vector<std::string>> list, words;
  std::optional<long long> size;
  std::optional<double> rate;
  double alpha = 0.0;
  bool flag = false;
  runtime::OptionFields fields;
  runtime::OptionGroup group(fields);
  group.Option("--name", name, "TEXT", "");
  group.List("--list", list, runtime::ValueKind::kIntegerList, "LIST", "", "");
  group.List("--words", words, runtime::ValueKind::kStringList, "LIST", "", "");
  group.Option("--size", size, "N", "");
  group.Option("--rate", rate, "X", "");
  group.Option("--alpha", alpha, "X", "");
  group.Flag("--flag", flag, "");
  Result<ConfigFile> file = ParseConfigText(
      "name = 5\nlist = [1, 2]\nwords = 'a,b'\nsize = 12\nrate = 2\nalpha = 0.25\nflag = true\n",
      "run.toml");
  ASSERT_TRUE(file) << file.error().message;
  ASSERT_TRUE(SetOptionFields(*file, fields, [](const std::string& key) { return key == "size"; }));
  EXPECT_EQ(name, "5");
  EXPECT_EQ(list, (std::vector<std::string>{"1", "2"}));
  EXPECT_EQ(words, (std::vector<std::string>{"a", "b"}));  // as a command line's list
  EXPECT_FALSE(size);  // skipped
  EXPECT_EQ(rate, 2.0);
  EXPECT_EQ(alpha, 0.25);
  EXPECT_TRUE(flag);

  const std::pair<const char*, const char*> bad[] = {
      {"size = 'x'\n", "run.toml:1: size: expected an integer, got a string"},
      {"rate = true\n", "run.toml:1: rate: expected a number, got a boolean"},
      {"alpha = inf\n", "run.toml:1: alpha: expected a finite number, got inf"},
      {"flag = 1\n", "run.toml:1: flag: expected a boolean, got an integer"},
      {"name = ''\n", "run.toml:1: name: must not be empty"},
      {"\nnot_there = 1\n", "run.toml:2: unknown key 'not_there'"}};
  for (const auto& [text, message] : bad) {
    Result<ConfigFile> parsed = ParseConfigText(text, "run.toml");
    ASSERT_TRUE(parsed) << text;
    Status set = SetOptionFields(*parsed, fields, nullptr);
    ASSERT_FALSE(set) << text;
    EXPECT_EQ(set.error().message, message);
  }
}

}  // namespace
}  // namespace dynapath::study
