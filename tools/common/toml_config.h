#pragma once
// `--config FILE` of the dynapath commands read with the options files' one
// rule (study/study_config.h): TOML by toml++, a key spelled with '-' or '_', a key
// given twice under any spelling refused. CLI11 then converts and checks the
// values as it does a command line's (which overrides them), so a run config,
// a params.toml and a checkpoint's run.toml read as a study file does.

namespace CLI {
class App;
}  // namespace CLI

namespace dynapath::cli {

// Makes `app`'s --config (runtime::AddConfigOption) read its file this way.
void ReadConfigAsToml(CLI::App& app);

}  // namespace dynapath::cli
