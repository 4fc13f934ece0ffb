#include "replay/commands.h"

#include <spdlog/spdlog.h>

#include "core/errors.h"
#include "core/scenario.h"

namespace gi {
namespace {

std::vector<std::uint32_t> parse_frame_list(const std::string& text) {
  std::vector<std::uint32_t> frames;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    const std::string item = text.substr(start, end - start);
    try {
      std::size_t used = 0;
      const unsigned long v = std::stoul(item, &used);
      if (used != item.size() || v > 0xFFFFFFFFul) throw std::invalid_argument(item);
      frames.push_back(static_cast<std::uint32_t>(v));
    } catch (const std::exception&) {
      throw InputError("--capture", "", "expected a comma-separated list of frame numbers, got \"" + item + "\"");
    }
    start = end + 1;
  }
  return frames;
}

}  // namespace

void Commands::add_to(CLI::App& app) {
  run_ = app.add_subcommand("run", "run a scenario on the GPU pipeline");
  run_->add_option("scenario", scenario_path_, "scenario JSON file")->required();
  run_->add_option("--frames", run_options_.frames, "override the frame count");
  run_->add_option("--seed", run_options_.seed, "override the seed");
  run_->add_option("--device", run_options_.device, "Vulkan device index (see 'giharness devices')");
  run_->add_option("--backend", run_options_.backend, "tracing backend")
      ->check(CLI::IsMember({"auto", "rayquery"}));
  run_->add_option("--capture", capture_list_, "frames to capture as EXR, e.g. 10,63");
  run_->add_option("--out", run_options_.out_dir, "output directory")->capture_default_str();

  reference_ = app.add_subcommand("reference", "render a scenario's frame with the Embree reference path tracer");
  reference_->add_option("scenario", reference_options_.scenario, "scenario JSON file")->required();
  reference_->add_option("--spp", reference_options_.spp, "samples per pixel (default: the reference check's, else 1024)");
  reference_->add_option("--frame", reference_options_.frame, "scene state after this frame's events (default: last)");
  reference_->add_option("--threads", reference_options_.threads, "CPU threads (0 = all)");
  reference_->add_option("--out", reference_options_.out_dir, "output directory")->capture_default_str();

  nightly_ = app.add_subcommand("nightly", "run every scenario of a suite and summarise");
  nightly_->add_option("--suite", nightly_options_.suite, "directory of scenario files")->capture_default_str();
  nightly_->add_option("--out", nightly_options_.out_dir, "output directory")->capture_default_str();
  nightly_->add_option("--device", nightly_options_.device, "Vulkan device index");

  devices_ = app.add_subcommand("devices", "list Vulkan devices and their ray-tracing support");
}

int Commands::execute() {
  if (run_->parsed()) {
    run_options_.capture = parse_frame_list(capture_list_);
    const Scenario scenario = load_scenario(scenario_path_);
    return run_scenario(scenario, run_options_).exit_code;
  }
  if (reference_->parsed()) return run_reference_command(reference_options_);
  if (nightly_->parsed()) return run_nightly(nightly_options_);
  if (devices_->parsed()) return list_devices_command();
  return 2;
}

}  // namespace gi
