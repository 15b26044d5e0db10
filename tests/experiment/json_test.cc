#include "tools/common/json.h"

#include <gtest/gtest.h>

namespace dynapath::cli {
namespace {

TEST(JsonTest, DumpsAndParsesBackEveryType) {
  Json json = Json::Object();
  json["null"] = Json();
  json["yes"] = true;
  json["int"] = 42;
  json["big"] = 4294967295LL;
  json["negative"] = -7;
  json["real"] = 0.1;
  json["text"] = "quote \" backslash \\ newline \n tab \t bell \x07 é";
  Json& list = json["list"] = Json::Array();
  list.Push(1);
  list.Push("two");
  Json nested = Json::Object();
  nested["inner"] = Json::Array();
  list.Push(nested);
  json["empty_object"] = Json::Object();

  for (int indent : {0, 2}) {
    const std::string text = json.Dump(indent);
    Result<Json> parsed = Json::Parse(text);
    ASSERT_TRUE(parsed) << parsed.error().message << "\n" << text;
    EXPECT_EQ(*parsed, json) << text;
  }
  const std::string text = json.Dump(2);
  EXPECT_NE(text.find("\"int\": 42,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"big\": 4294967295,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"real\": 0.1,"), std::string::npos) << text;
  EXPECT_NE(text.find("\\u0007"), std::string::npos) << text;
}

TEST(JsonTest, KeepsMemberOrderAndReadsMembers) {
  Json json = Json::Object();
  json["b"] = 1;
  json["a"] = 2;
  json["b"] = 3;  // replaces, keeps the place
  ASSERT_EQ(json.members().size(), 2u);
  EXPECT_EQ(json.members()[0].first, "b");
  EXPECT_EQ(json.Find("b")->AsInt(), 3);
  EXPECT_EQ(json.Find("missing"), nullptr);
  EXPECT_EQ(Json("x").AsInt(5), 5);
  EXPECT_EQ(Json(2.5).AsInt(5), 5);
  EXPECT_EQ(Json(2.0).AsInt(5), 2);
}

TEST(JsonTest, ParsesEscapesAndSurrogates) {
  Result<Json> parsed = Json::Parse(R"(["\u00e9\ud83d\ude00\/", -1.5e2, false])");
  ASSERT_TRUE(parsed) << parsed.error().message;
  EXPECT_EQ(parsed->items()[0].AsString(), "\xc3\xa9\xf0\x9f\x98\x80/");
  EXPECT_EQ(parsed->items()[1].AsNumber(), -150.0);
  EXPECT_FALSE(parsed->items()[2].AsBool(true));
}

TEST(JsonTest, ReportsTheLineOfAnError) {
  for (const auto& [text, line] :
       {std::pair{"{\n  \"a\": 1,\n  \"b\": nope\n}", "line 3"}, std::pair{"[1, 2", "line 1"},
        std::pair{"{\"a\" 1}", "line 1"}, std::pair{"\n\n\"unterminated", "line 3"},
        std::pair{"[1] 2", "line 1"}, std::pair{"", "line 1"}, std::pair{"[01]", "line 1"}}) {
    Result<Json> parsed = Json::Parse(text);
    ASSERT_FALSE(parsed) << text;
    EXPECT_EQ(parsed.error().message.rfind(line, 0), 0u) << text << ": " << parsed.error().message;
  }
}

}  // namespace
}  // namespace dynapath::cli
