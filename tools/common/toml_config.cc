#include "tools/common/toml_config.h"

#include <CLI/CLI.hpp>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "study/study_config.h"

namespace dynapath::cli {
namespace {

class TomlConfig : public CLI::ConfigTOML {
 public:
  explicit TomlConfig(const CLI::App& app) : app_(&app) {}

  std::vector<CLI::ConfigItem> from_config(std::istream& input) const override {
    const std::string text{std::istreambuf_iterator<char>(input), std::istreambuf_iterator<char>()};
    Result<study::ConfigFile> file = study::ParseConfigText(text, FileName());
    if (!file) throw CLI::ConfigError(file.error().message);
    std::vector<CLI::ConfigItem> config_items;
    for (const study::ConfigEntry& entry : file->entries) {
      CLI::ConfigItem item;
      item.name = entry.key;
      item.inputs = {entry.value.Text()};
      config_items.push_back(std::move(item));
    }
    return config_items;
  }

 private:
  // The file as given, for messages ("params.toml:3: ...").
  std::string FileName() const {
    const CLI::Option* option = app_->get_config_ptr();
    if (option != nullptr && !option->results().empty()) return option->results().front();
    return "the --config file";
  }

  const CLI::App* app_;
};

}  // namespace

void ReadConfigAsToml(CLI::App& app) { app.config_formatter(std::make_shared<TomlConfig>(app)); }

}  // namespace dynapath::cli
