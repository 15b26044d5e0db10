// dynapath-render: draws the POLICY messages of an LCM log (a run recorded
// with `dynapath run --log FILE`) as one PNG per time step and an animated
// GIF per approach. Run directly or as `dynapath render`.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "dynapath/text_file.h"
#include "protocol/channels.h"
#include "runtime/option_group.h"
#include "runtime/output_check.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"
#include "tools/view/gif_writer.h"
#include "tools/view/png_writer.h"
#include "tools/view/policy_drawing.h"
#include "tools/view/policy_stream.h"
#include "tools/view/safe_name.h"
#include "tools/view/view_options.h"

namespace {

using namespace dynapath;
namespace fs = std::filesystem;

constexpr const char* kProgram = "dynapath-render";
constexpr int kExitFailure = 1;

// One approach of one run: where its pictures go and the animation so far.
struct Output {
  std::string run, approach;
  fs::path dir;
  int rows = 0, cols = 0;
  std::set<int> steps;  // time steps written
  std::unique_ptr<view::GifEncoder> gif;
  int first_step = -1, last_step = -1;
};

std::string Kilobytes(uintmax_t bytes) { return std::to_string((bytes + 1023) / 1024) + " KB"; }

int Run(const std::vector<std::string>& args) {
  CLI::App app(
      "Draws the policy of every time step of a logged run (dynapath run --log LOG) as PNG\n"
      "frames, OUT/<approach>/step_0000.png ..., and an animated OUT/<approach>/policy.gif.\n"
      "With several runs in the log (and no --run-id): OUT/<run>/<approach>/...\n"
      "Free cells light, obstacles dark (moving ones purple), stations green, cells whose\n"
      "policy fails red, arrows for the greedy actions, retrained regions outlined in\n"
      "orange; a legend below the grid names the colours (--no-legend: none).",
      "dynapath render");
  std::string log_path;
  app.add_option("LOG", log_path, "the LCM log of a run (dynapath run --log LOG)");
  runtime::OptionGroup group(app);
  std::optional<std::string> out;
  group.Option("--out", out, "DIR", "directory for the pictures", "required");
  view::ShowOptions show;
  view::DeclareShowOptions(group, show);
  long long delay_given = 250;
  group.Option("--delay", delay_given, "MS", "GIF frame delay in milliseconds (20-60000)");
  bool no_gif = false;
  group.Flag("--no-gif", no_gif, "write the PNG frames only");
  bool no_legend = false;
  group.Flag("--no-legend", no_legend, "no legend of the colours below the grid");
  runtime::LogOptions log;
  runtime::DeclareLogOptions(group, log);

  if (int code = runtime::ParseCommandLine(app, args, kProgram); code >= 0) return code;
  if (Status status = runtime::ApplyLogLevel(log); !status) {
    return runtime::ProcessError(kProgram, status.error().message);
  }
  if (log_path.empty()) {
    return runtime::ProcessError(kProgram, "missing LOG (usage: dynapath render LOG --out DIR)");
  }
  if (!out || out->empty()) {
    return runtime::ProcessError(kProgram, "option --out DIR is required");
  }
  const fs::path out_dir = *out;
  // The pictures' directory checked (and made) before the log is read.
  if (Status status = runtime::PrepareOutputDirectory(*out, "out"); !status) {
    return runtime::ProcessError(kProgram, status.error().message);
  }
  if (Status status = view::CheckShowOptions(show); !status) {
    return runtime::ProcessError(kProgram, status.error().message);
  }
  Result<int> cell = view::ResolveCellOption(show.cell_px);
  if (!cell) return runtime::ProcessError(kProgram, cell.error().message);
  Result<long long> delay = runtime::InRange("delay", delay_given, 0, 20, 60000);
  if (!delay) return runtime::ProcessError(kProgram, delay.error().message);
  const std::string run_filter = show.run_id.value_or("");
  const std::string approach_filter = show.approach.value_or("");
  const bool want_gif = !no_gif;
  view::DrawOptions draw;
  draw.cell_px = static_cast<int>(*cell);
  draw.legend = !no_legend;

  // Pass 1: which runs and approaches the log holds.
  std::vector<std::pair<std::string, std::string>> keys;  // (run, approach), first seen first
  std::set<std::pair<std::string, std::string>> seen;
  // Where each run's obstacles move, to draw them apart from the walls.
  std::map<std::string, view::MovingCells> moving;
  Result<view::PolicyLogSummary> scan =
      view::ReadPolicyLog(log_path, run_filter, [&](const policy_t& policy) {
        if (seen.insert({policy.run_id, policy.approach}).second) {
          keys.emplace_back(policy.run_id, policy.approach);
        }
        moving[policy.run_id].Add(policy);
      });
  if (!scan) return runtime::ProcessError(kProgram, scan.error().message, kExitFailure);
  if (keys.empty()) {
    std::string message = "log " + log_path + " holds no POLICY messages";
    if (!run_filter.empty()) message += " of run " + run_filter;
    if (scan->counters.dropped > 0) {
      message += " (" + std::to_string(scan->counters.dropped) + " invalid ones skipped)";
    } else {
      message += " (record a distributed run: dynapath run --agents N --log FILE)";
    }
    return runtime::ProcessError(kProgram, message, kExitFailure);
  }
  if (!approach_filter.empty()) {
    std::vector<std::pair<std::string, std::string>> kept;
    std::string names;
    std::set<std::string> listed;
    for (const auto& key : keys) {
      if (key.second == approach_filter || view::SafeName(key.second) == approach_filter) {
        kept.push_back(key);
      }
      if (listed.insert(key.second).second)
        names += (names.empty() ? "'" : ", '") + key.second + "'";
    }
    if (kept.empty()) {
      return runtime::ProcessError(kProgram,
                                   "log " + log_path + " holds no policy of approach '" +
                                       approach_filter + "' (it holds " + names + ")",
                                   kExitFailure);
    }
    keys = std::move(kept);
  }
  std::set<std::string> runs;
  for (const auto& key : keys) runs.insert(key.first);

  // Where each approach's pictures go.
  std::map<std::pair<std::string, std::string>, Output> outputs;
  std::set<fs::path> used_dirs;
  for (const auto& key : keys) {
    Output output;
    output.run = key.first;
    output.approach = key.second;
    fs::path base = runs.size() > 1 ? out_dir / key.first : out_dir;
    fs::path dir = base / view::SafeName(key.second);
    for (int n = 2; used_dirs.count(dir); ++n) {
      dir = base / (view::SafeName(key.second) + "_" + std::to_string(n));
    }
    used_dirs.insert(dir);
    std::error_code error;
    fs::create_directories(dir, error);
    if (error) {
      return runtime::ProcessError(
          kProgram, "cannot create " + dir.string() + ": " + error.message(), kExitFailure);
    }
    output.dir = dir;
    outputs.emplace(key, std::move(output));
  }

  // Pass 2: draw.
  int64_t frames = 0, duplicates = 0, inconsistent = 0;
  std::string failure;
  const auto start = std::chrono::steady_clock::now();
  auto last_progress = start;
  Output* current = nullptr;
  Result<view::PolicyLogSummary> pass =
      view::ReadPolicyLog(log_path, run_filter, [&](const policy_t& policy) {
        if (!failure.empty()) return;
        auto it = outputs.find({policy.run_id, policy.approach});
        if (it == outputs.end()) return;
        Output& output = it->second;
        if (output.steps.empty()) {
          output.rows = policy.rows;
          output.cols = policy.cols;
        } else if (policy.rows != output.rows || policy.cols != output.cols) {
          ++inconsistent;
          return;
        }
        if (!output.steps.insert(policy.time_step).second) {
          ++duplicates;  // a message heard twice
          return;
        }
        if (current != &output) {
          spdlog::info("render: {} ({}x{}) -> {}", policy.approach, policy.rows, policy.cols,
                       output.dir.string());
          current = &output;
        }
        draw.moving = &moving[policy.run_id].cells();
        const view::RgbImage image = view::DrawPolicy(policy, draw);
        char name[32];
        std::snprintf(name, sizeof name, "step_%04d.png", policy.time_step);
        if (Status status = view::WritePng((output.dir / name).string(), image); !status) {
          failure = status.error().message;
          return;
        }
        if (want_gif) {
          if (!output.gif) {
            output.gif = std::make_unique<view::GifEncoder>(image.width(), image.height(),
                                                            view::DrawingPalette());
          }
          if (Status status = output.gif->AddFrame(image, static_cast<int>(*delay)); !status) {
            ++inconsistent;
          }
        }
        output.first_step = output.first_step < 0 ? policy.time_step
                                                  : std::min(output.first_step, policy.time_step);
        output.last_step = std::max(output.last_step, policy.time_step);
        ++frames;
        const auto now = std::chrono::steady_clock::now();
        if (now - last_progress >= std::chrono::seconds(2)) {
          spdlog::info("render: {} frames so far ({}: step {})", frames, policy.approach,
                       policy.time_step);
          last_progress = now;
        }
      });
  if (!pass) return runtime::ProcessError(kProgram, pass.error().message, kExitFailure);
  if (!failure.empty()) return runtime::ProcessError(kProgram, failure, kExitFailure);

  for (const auto& key : keys) {
    Output& output = outputs.at(key);
    std::string gif_text;
    if (output.gif) {
      const fs::path gif_path = output.dir / "policy.gif";
      const std::vector<uint8_t> bytes = output.gif->Finish();
      if (Status status = WriteFileAtomically(gif_path.string(), bytes); !status) {
        return runtime::ProcessError(kProgram, status.error().message, kExitFailure);
      }
      gif_text = " and policy.gif (" + std::to_string(output.gif->frames()) + " frames, " +
                 Kilobytes(bytes.size()) + ")";
    }
    char range[64];
    std::snprintf(range, sizeof range, "step_%04d.png..step_%04d.png", output.first_step,
                  output.last_step);
    spdlog::info("render: {}{}: {} PNG frames ({}){} in {}", output.approach,
                 runs.size() > 1 ? " of run " + output.run : "", output.steps.size(), range,
                 gif_text, output.dir.string());
  }
  const view::PolicyStreamCounters& counters = pass->counters;
  const int64_t skipped = counters.dropped + inconsistent;
  if (skipped > 0 || pass->incomplete > 0 || counters.expired > 0) {
    spdlog::warn(
        "render: skipped {} invalid or undecodable POLICY message(s); {} fragmented "
        "message(s) incomplete",
        skipped, pass->incomplete + counters.expired);
  }
  if (duplicates > 0) spdlog::info("render: ignored {} repeated time step(s)", duplicates);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  spdlog::info("render: {} frames of {} approach(es) in {:.2f} s", frames, keys.size(), seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  dynapath::runtime::InitProcessLogging(kProgram);
  try {
    return Run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const std::exception& error) {
    return dynapath::runtime::ProcessError(kProgram, error.what(), kExitFailure);
  }
}
