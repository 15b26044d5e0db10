#include "study/json.h"

#include <set>
#include <vector>

namespace dynapath::study {

Result<Json> ParseJson(std::string_view text) {
  // The keys seen in each open object, innermost last.
  std::vector<std::set<std::string>> open_objects;
  std::string duplicate;
  auto check_keys = [&](int /*depth*/, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
        open_objects.emplace_back();
        break;
      case Json::parse_event_t::object_end:
        if (!open_objects.empty()) open_objects.pop_back();
        break;
      case Json::parse_event_t::key:
        if (!open_objects.empty() &&
            !open_objects.back().insert(parsed.get<std::string>()).second && duplicate.empty()) {
          duplicate = parsed.get<std::string>();
        }
        break;
      default:
        break;
    }
    return true;
  };
  try {
    Json json = Json::parse(text.begin(), text.end(), check_keys);
    if (!duplicate.empty()) return Error::Corrupt("duplicate key \"" + duplicate + "\"");
    return json;
  } catch (const Json::parse_error& error) {
    // nlohmann's message names the line, column and what was expected, after
    // a prefix meant for developers: "[json.exception.parse_error.101] parse
    // error at ".
    std::string message = error.what();
    const size_t at = message.find(" at line ");
    if (at != std::string::npos) message = message.substr(at + 4);
    return Error::Corrupt(message);
  }
}

std::string DumpJson(const Json& json, int indent) {
  std::string text = json.dump(indent, ' ', false, Json::error_handler_t::replace);
  if (indent >= 0) text += '\n';
  return text;
}

const Json* Member(const Json& json, const std::string& key) {
  if (!json.is_object()) return nullptr;
  const auto found = json.find(key);
  return found == json.end() ? nullptr : &*found;
}

}  // namespace dynapath::study
