// `giharness replay CAPTURE [--frames N] [--verify] [--out DIR]` (docs/design.md §9,
// §11): rebuilds the capturing run from the manifest (scenario document,
// seed, profile and --set values, backend, device), restores the captured
// state and continues to frame N − 1 (default: the run's last frame).
// --verify compares every frame's buffer hashes, from the restored state on,
// with the capturing run's (run_hashes.jsonl) and names the first divergent
// frame and buffers: exit 0 identical, 1 divergent or nothing to compare.
// Without --verify the exit code is the checks' (judged on the replayed
// frames only).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/check_catalog.h"
#include "core/errors.h"
#include "core/json_input.h"
#include "core/scenario.h"
#include "core/shared/word_hash.h"
#include "replay/capture.h"
#include "checks/determinism_check.h"
#include "app/commands.h"

namespace gi {

namespace {

// A capture of the radiance-cascades pipeline (replay/rc_run.h): its frames
// carry nothing between them, so the replay renders the captured frame again
// and continues; --verify compares each frame's image hash with the run's.
int replay_rc(const ReplayOptions& o, const nlohmann::json& m) {
  const nlohmann::json& run = m.at("run");
  Scenario scenario = parse_scenario(run["scenario"]["document"], run["scenario"]["file"].get<std::string>());
  scenario.capture.clear();
  RunOptions ro;
  ro.frames = o.frames.value_or(run["frames"].get<std::uint32_t>());
  ro.seed = run["seed"].get<std::uint32_t>();
  if (run["profile_option"].is_string()) ro.profile = run["profile_option"].get<std::string>();
  ro.sets = run.value("sets", std::vector<std::string>{});
  ro.backend = run.value("backend", std::string("auto"));
  ro.device = o.device;
  ro.out_dir = o.out_dir;
  ro.resume_from = o.capture;
  const std::uint32_t first = m["frame"].get<std::uint32_t>();
  if (!o.capture_frames.empty())
    throw InputError("--capture", "", "no frame: a radiance-cascades replay writes no captures");
  spdlog::info("replaying {} from frame {} to {} into {}", scenario.name, first, *ro.frames - 1, o.out_dir.string());
  const RunResult result = run_scenario(scenario, ro);
  if (!o.verify) return result.exit_code;
  const nlohmann::json original = read_json_input(o.capture / "run_hashes.json", "the capturing run's frame hashes");
  const nlohmann::json& before = original.at("frame_images");
  const nlohmann::json& after = result.summary["hashes"]["frame_images"];
  nlohmann::json verify = {{"capture", o.capture.string()}, {"first_frame", first}, {"compared", 0}};
  std::optional<std::uint32_t> divergent;
  for (std::size_t i = 0; i < after.size() && first + i < before.size(); ++i) {
    verify["compared"] = verify["compared"].get<int>() + 1;
    if (after[i] != before[first + i] && !divergent) divergent = first + std::uint32_t(i);
  }
  const bool identical = !divergent && verify["compared"].get<int>() > 0;
  verify["verdict"] = identical ? "identical" : divergent ? "divergent" : "nothing_compared";
  verify["message"] = divergent ? fmt::format("frame {}'s image differs from the capturing run's", *divergent)
                                : fmt::format("{} frames from {} bit-identical to the capturing run's",
                                              verify["compared"].get<int>(), first);
  write_json_file(o.out_dir / "verify.json", verify);
  if (identical) spdlog::info("verify: {}", verify["message"].get<std::string>());
  else spdlog::error("verify: {}", verify["message"].get<std::string>());
  return identical ? 0 : 1;
}

}  // namespace

int run_replay_command(const ReplayOptions& o) {
  {
    const nlohmann::json m = read_json_input(o.capture / "manifest.json", "a capture's manifest");
    if (m.value("pipeline", std::string()) == "radiance_cascades") return replay_rc(o, m);
  }
  const Capture capture = read_capture(o.capture);
  const nlohmann::json& m = capture.manifest;
  // This build hashes with WORD_HASH_SCHEME: an older capture's log cannot be compared.
  if (o.verify && capture.hash_scheme != shader::WORD_HASH_SCHEME)
    throw InputError((o.capture / "manifest.json").string(), "/hash_scheme",
                     fmt::format("a capture hashed with {} to --verify against (this one's run_hashes.jsonl holds {} "
                                 "hashes: replay it without --verify, or capture it again with this build)",
                                 shader::WORD_HASH_SCHEME, capture.hash_scheme));
  const std::filesystem::path scenario_file = m["scenario"].value("file", (o.capture / "manifest.json").string());
  Scenario scenario = parse_scenario(m["scenario"]["document"], scenario_file);
  // Replay continues the run; it does not repeat its captures or its determinism repeats.
  scenario.capture.clear();
  drop_rerunning_checks(scenario);

  RunOptions ro;
  ro.frames = o.frames.value_or(m["frames"].get<std::uint32_t>());
  ro.seed = m["seed"].get<std::uint32_t>();
  if (m.contains("profile_option") && m["profile_option"].is_string()) ro.profile = m["profile_option"].get<std::string>();
  ro.sets = m.value("sets", std::vector<std::string>{});
  ro.backend = m.value("backend", std::string("auto"));  // the backend that ran, not the request
  if (o.device) ro.device = o.device;
  else if (m.contains("device_index") && m["device_index"].is_number_integer()) ro.device = m["device_index"].get<int>();
  ro.out_dir = o.out_dir;
  ro.resume_from = o.capture;
  ro.record_hashes = true;
  for (const std::uint32_t f : o.capture_frames)
    if (f <= capture.frame || f >= *ro.frames)
      throw InputError("--capture", "", fmt::format("a frame the replay runs ({} to {}), got {}", capture.frame + 1,
                                                    *ro.frames - 1, f));
  ro.capture = o.capture_frames;
  spdlog::info("replaying {} from frame {} to {} into {}", scenario.name, capture.frame + 1, *ro.frames - 1,
               o.out_dir.string());
  const RunResult run = run_scenario(scenario, ro);
  const std::string captured_on = m["device"].value("name", std::string("?"));
  const std::string replayed_on = run.summary["device"].value("name", std::string("?"));
  if (captured_on != replayed_on)
    spdlog::warn("captured on {}, replayed on {}: bits may differ between devices", captured_on, replayed_on);
  if (!o.verify) return run.exit_code;

  const std::filesystem::path original = capture.dir / m.value("run_hashes", std::string("run_hashes.jsonl"));
  if (!std::filesystem::exists(original))
    throw InputError(original.string(), "", "the capturing run's hashes (written when that run finished)");
  const HashLogComparison cmp = compare_hash_logs(original, o.out_dir / "buffer_hashes.jsonl");
  nlohmann::json verify = cmp.to_json();
  verify["capture"] = o.capture.string();
  verify["message"] = cmp.describe();
  verify["verdict"] = cmp.identical() ? "identical" : cmp.first ? "divergent" : "nothing_compared";
  write_json_file(o.out_dir / "verify.json", verify);
  if (cmp.identical()) spdlog::info("verify: {}", cmp.describe());
  else spdlog::error("verify: {}", cmp.describe());
  if (cmp.unmatched_frames > 0)
    spdlog::warn("verify: {} replayed frames have no record in the capturing run (not compared)", cmp.unmatched_frames);
  return cmp.identical() ? 0 : 1;
}

}  // namespace gi
