// Tests of what tools/common/json adds to nlohmann::json: the strict parse
// (duplicate keys, error positions), the dump that cannot throw, Member.

#include "study/json.h"

#include <gtest/gtest.h>

namespace dynapath::study {
namespace {

TEST(JsonTest, RoundTripsAndKeepsMemberOrder) {
  Json json = Json::object();
  json["b"] = 1;
  json["a"] = Json::array({1, "two", nullptr, 0.1, 4294967295LL});
  json["b"] = 3;  // replaces, keeps the place
  const std::string text = DumpJson(json);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_LT(text.find("\"b\""), text.find("\"a\""));
  EXPECT_NE(text.find("4294967295"), std::string::npos);
  EXPECT_NE(text.find("0.1"), std::string::npos);
  Result<Json> parsed = ParseJson(text);
  ASSERT_TRUE(parsed) << parsed.error().message;
  EXPECT_EQ(*parsed, json);
  EXPECT_EQ(DumpJson(json, -1), R"({"b":3,"a":[1,"two",null,0.1,4294967295]})");
}

TEST(JsonTest, RefusesDuplicateKeysAtAnyDepth) {
  for (const char* text : {R"({"a": 1, "a": 2})", R"({"x": {"k": 1, "k": 1}})",
                           R"([{"k": 1}, {"k": 2, "j": 0, "k": 3}])"}) {
    Result<Json> parsed = ParseJson(text);
    ASSERT_FALSE(parsed) << text;
    EXPECT_NE(parsed.error().message.find("duplicate key"), std::string::npos);
  }
  // The same key in sibling objects is fine.
  EXPECT_TRUE(ParseJson(R"([{"k": 1}, {"k": 2}, {"o": {"k": 3}, "k": 4}])"));
}

TEST(JsonTest, ParsesEscapesAndRefusesLoneSurrogates) {
  Result<Json> parsed = ParseJson(R"(["\u00e9\ud83d\ude00\/", -1.5e2, false])");
  ASSERT_TRUE(parsed) << parsed.error().message;
  EXPECT_EQ((*parsed)[0].get<std::string>(), "\xc3\xa9\xf0\x9f\x98\x80/");
  EXPECT_EQ((*parsed)[1].get<double>(), -150.0);
  EXPECT_FALSE(ParseJson(R"(["\ud83d"])"));
  EXPECT_FALSE(ParseJson(R"(["\ude00x"])"));
}

TEST(JsonTest, ReportsWhereTheTextIsWrong) {
  for (const auto& [text, line] :
       {std::pair{"{\n  \"a\": 1,\n  \"b\": nope\n}", "line 3"}, std::pair{"[1, 2", "line 1"},
        std::pair{"{\"a\" 1}", "line 1"}, std::pair{"\n\n\"unterminated", "line 3"},
        std::pair{"[1] 2", "line 1"}, std::pair{"", "line 1"}, std::pair{"[01]", "line 1"}}) {
    Result<Json> parsed = ParseJson(text);
    ASSERT_FALSE(parsed) << text;
    EXPECT_EQ(parsed.error().message.rfind(line, 0), 0u) << text << ": " << parsed.error().message;
  }
}

TEST(JsonTest, DumpReplacesInvalidUtf8) {
  Json json = Json::object();
  json["path"] = std::string("bad\xff name");
  const std::string text = DumpJson(json, -1);
  EXPECT_EQ(text, "{\"path\":\"bad\xef\xbf\xbd name\"}");
  EXPECT_TRUE(ParseJson(text));
}

TEST(JsonTest, MemberFindsObjectMembersOnly) {
  const Json json = {{"a", 1}};
  ASSERT_NE(Member(json, "a"), nullptr);
  EXPECT_EQ(Member(json, "a")->get<int>(), 1);
  EXPECT_EQ(Member(json, "b"), nullptr);
  EXPECT_EQ(Member(Json::array({1}), "a"), nullptr);
}

}  // namespace
}  // namespace dynapath::study
