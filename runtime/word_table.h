#pragma once
// The words an enum option accepts, written once: one table per
// enum maps each word to its value, and the option's help text, its check
// ("must be a, b or c, got 'x'"), its parse and the word of its default are
// all read from the table, so adding or renaming a value is one line.

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dynapath/result.h"
#include "dynapath/text_util.h"

namespace dynapath::runtime {

template <typename Value>
class WordTable {
 public:
  struct Word {
    std::string word;
    Value value;
    // False for a spelling that is accepted but not offered (an alias):
    // lists, and Name, show only the listed words.
    bool listed = true;
  };
  enum class Case { kExact, kIgnored };

  explicit WordTable(std::vector<Word> words, Case letter_case = Case::kExact)
      : words_(std::move(words)), case_(letter_case) {}

  // "a, b or c": the listed words, for help texts and errors.
  std::string List() const {
    std::vector<std::string> listed;
    for (const Word& word : words_) {
      if (word.listed) listed.push_back(word.word);
    }
    std::string text;
    for (size_t i = 0; i < listed.size(); ++i) {
      if (i > 0) text += i + 1 == listed.size() ? " or " : ", ";
      text += listed[i];
    }
    return text;
  }

  std::optional<Value> Parse(const std::string& text) const {
    const std::string key = case_ == Case::kIgnored ? ToLower(text) : text;
    for (const Word& word : words_) {
      if (word.word == key) return word.value;
    }
    return std::nullopt;
  }

  // "must be LIST, got 'TEXT'" unless `text` is a word; without the
  // option's name, which callers add (an option, a study file's key).
  Status Check(const std::string& text) const {
    if (Parse(text)) return Ok{};
    return Error{"must be " + List() + ", got '" + text + "'"};
  }

  // The value of option --NAME given as `text`, or the error "option --NAME
  // must be LIST, got 'TEXT'".
  Result<Value> ParseOption(const std::string& name, const std::string& text) const {
    if (std::optional<Value> value = Parse(text)) return *value;
    return Error::Option(name, Check(text).error().message);
  }

  // The first listed word of `value` (the word of a default).
  std::string Name(Value value) const {
    for (const Word& word : words_) {
      if (word.listed && word.value == value) return word.word;
    }
    return "?";
  }

 private:
  std::vector<Word> words_;
  Case case_;
};

}  // namespace dynapath::runtime
