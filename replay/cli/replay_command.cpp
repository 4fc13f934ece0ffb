// `giharness replay CAPTURE [--frames N] [--verify] [--out DIR]` (DESIGN §9,
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
#include "core/scenario.h"
#include "core/shared/word_hash.h"
#include "replay/capture.h"
#include "replay/checks/determinism_check.h"
#include "replay/cli/commands.h"

namespace gi {

int run_replay_command(const ReplayOptions& o) {
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
