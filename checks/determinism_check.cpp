#include "checks/determinism_check.h"
#include "checks/check_registry.h"

#include <fstream>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/run_options.h"

namespace gi {
namespace {

using FrameHashes = std::vector<std::pair<std::string, std::string>>;  // (buffer, hash) in list order

std::map<std::uint32_t, FrameHashes> read_hash_log(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "", "a buffer hash log (buffer_hashes.jsonl / run_hashes.jsonl)");
  std::map<std::uint32_t, FrameHashes> log;
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    try {
      const nlohmann::json j = nlohmann::json::parse(line);
      FrameHashes& frame = log[j.at("frame").get<std::uint32_t>()];
      frame.clear();  // a later record of the same frame (e.g. restored, then re-rendered) wins
      for (const nlohmann::json& b : j.at("buffers")) frame.emplace_back(b.at(0).get<std::string>(), b.at(1).get<std::string>());
    } catch (const nlohmann::json::exception& e) {
      throw InputError(file.string(), fmt::format("line {}", n),
                       std::string("{\"frame\": F, \"buffers\": [[name, hash], …]} (") + e.what() + ")");
    }
  }
  return log;
}

std::vector<std::string> differing_buffers(const FrameHashes& original, const FrameHashes& candidate) {
  std::map<std::string, std::string> want(original.begin(), original.end());
  std::vector<std::string> out;
  for (const auto& [name, hash] : candidate) {
    const auto it = want.find(name);
    if (it == want.end()) out.push_back(name + " (missing in the original)");
    else if (it->second != hash) out.push_back(name);
    if (it != want.end()) want.erase(it);
  }
  for (const auto& [name, hash] : original)
    if (want.count(name)) out.push_back(name + " (missing in the candidate)");
  return out;
}

}  // namespace

std::string HashLogComparison::describe() const {
  if (frames_compared == 0) return "no frame in common with the original run's hashes: nothing verified";
  if (!first) return fmt::format("{} frames bit-identical in every buffer", frames_compared);
  std::string names;
  for (const std::string& b : first->buffers) names += (names.empty() ? "" : ", ") + b;
  return fmt::format("first divergence at frame {}: {} ({} of {} frames differ)", first->frame, names,
                     divergent_frames, frames_compared);
}

nlohmann::json HashLogComparison::to_json() const {
  nlohmann::json j = {{"frames_compared", frames_compared},
                      {"divergent_frames", divergent_frames},
                      {"unmatched_frames", unmatched_frames}};
  j["first_divergent_frame"] = first ? nlohmann::json(first->frame) : nlohmann::json(nullptr);
  j["first_divergent_buffers"] = first ? nlohmann::json(first->buffers) : nlohmann::json::array();
  return j;
}

HashLogComparison compare_hash_logs(const std::filesystem::path& original, const std::filesystem::path& candidate) {
  const auto want = read_hash_log(original);
  const auto got = read_hash_log(candidate);
  HashLogComparison c;
  for (const auto& [frame, hashes] : got) {  // std::map: ascending frames, so `first` is the earliest
    const auto it = want.find(frame);
    if (it == want.end()) {
      ++c.unmatched_frames;
      continue;
    }
    ++c.frames_compared;
    std::vector<std::string> diff = differing_buffers(it->second, hashes);
    if (diff.empty()) continue;
    ++c.divergent_frames;
    if (!c.first) c.first = Divergence{frame, std::move(diff)};
  }
  return c;
}

DeterminismParams determinism_params(const CheckSpec& spec, const Scenario& scenario, std::uint32_t frames) {
  DeterminismParams p;
  const std::string file = scenario.file.string();
  if (spec.params.contains("second_run")) {
    if (!spec.params["second_run"].is_boolean())
      throw InputError(file, spec.json_path + "/second_run", "expected true or false");
    p.second_run = spec.params["second_run"].get<bool>();
  }
  if (frames >= 2) p.snapshot_frame = frames / 2 - 1;  // replays the second half
  if (spec.params.contains("snapshot_frame")) {
    const nlohmann::json& f = spec.params["snapshot_frame"];
    if (f.is_null()) {
      p.snapshot_frame.reset();
    } else if (!f.is_number_unsigned() || f.get<std::uint64_t>() + 1 >= frames) {
      throw InputError(file, spec.json_path + "/snapshot_frame",
                       fmt::format("expected null or a frame below {} (the replay needs a frame after it)",
                                   frames - 1));
    } else {
      p.snapshot_frame = f.get<std::uint32_t>();
    }
  }
  if (!p.second_run && !p.snapshot_frame)
    throw InputError(file, spec.json_path, "a second run, a snapshot frame, or both (else nothing is compared)");
  return p;
}

std::vector<Rerun> determinism_reruns(const DeterminismParams& params) {
  std::vector<Rerun> reruns;
  if (params.second_run) reruns.push_back({.out_subdir = "determinism/second_run"});
  if (params.snapshot_frame) reruns.push_back({.out_subdir = "determinism/replay", .resume_from = params.snapshot_frame});
  return reruns;
}

CheckResult judge_determinism(const std::filesystem::path& out_dir, const DeterminismParams& params) {
  const std::filesystem::path original = out_dir / "buffer_hashes.jsonl";
  CheckResult r;
  r.name = "determinism";
  r.verdict = Verdict::pass;
  std::vector<std::string> lines;
  auto judge = [&](const char* what, const std::filesystem::path& out) {
    const HashLogComparison cmp = compare_hash_logs(original, out / "buffer_hashes.jsonl");
    r.figures[what] = cmp.to_json();
    lines.push_back(fmt::format("{}: {}", what, cmp.describe()));
    r.evidence.push_back(std::filesystem::relative(out / "buffer_hashes.jsonl", out_dir).string());
    if (cmp.first && (!r.first_failing_frame || cmp.first->frame < *r.first_failing_frame))
      r.first_failing_frame = cmp.first->frame;
    if (cmp.first) r.verdict = Verdict::fail;
    else if (cmp.frames_compared == 0 && r.verdict == Verdict::pass) r.verdict = Verdict::inconclusive;
  };
  for (const Rerun& rerun : determinism_reruns(params))
    judge(rerun.resume_from ? "replay" : "second_run", out_dir / rerun.out_subdir);
  r.limits = {{"differing_buffers", 0}};
  if (params.snapshot_frame) r.limits["snapshot_frame"] = *params.snapshot_frame;
  for (const std::string& l : lines) r.message += (r.message.empty() ? "" : "; ") + l;
  return r;
}


namespace {

// Asks the main run for its hashes and the snapshot capture, and the run
// engine for the second run and the replay after it; result() compares.
class DeterminismPlugin final : public Check {
 public:
  explicit DeterminismPlugin(const CheckContext& c)
      : out_dir_(c.options.out_dir), params_(determinism_params(c.spec, c.scenario, c.frames)) {}
  CheckNeeds needs() const override {
    CheckNeeds n;
    n.frames = std::set<std::uint32_t>{};  // judges no frame of the main run
    n.record_hashes = true;
    if (params_.snapshot_frame) n.captures.insert(*params_.snapshot_frame);
    n.reruns = determinism_reruns(params_);
    return n;
  }
  void observe(const FrameView&, nlohmann::json&) override {}
  CheckResult result() override { return judge_determinism(out_dir_, params_); }

 private:
  std::filesystem::path out_dir_;
  DeterminismParams params_;
};

// This check's parameters as scenarios/schema.json states them ($defs/check_determinism,
// which `giharness schema` writes from here); the parser accepts exactly
// these keys.
constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "description": "Determinism (docs/design.md §6): the hashes of every recorded buffer, per frame, of a second run and of a replay from a snapshot captured mid-run, compared with the run's bit for bit; the first divergent frame and buffers are named.",
  "properties": {
    "name": {
      "const": "determinism"
    },
    "second_run": {
      "type": "boolean",
      "description": "Run the scenario a second time from frame 0 and compare (default true)."
    },
    "snapshot_frame": {
      "oneOf": [
        {
          "$ref": "#/$defs/frame"
        },
        {
          "type": "null"
        }
      ],
      "description": "Capture this frame and replay the rest of the run from it (default frames / 2 - 1; null: no replay). Must be below the last frame."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "whether a second run and a replay from a mid-run snapshot give every recorded buffer's hash, "
    "frame by frame, bit for bit",
    "none: a bit comparison; the seed fixes every random stream",
    CheckModel::Basis::exact,
    0.0,
    "0: a differing bit is a finding on every device class the project supports"};

const RegisteredCheck<DeterminismPlugin> kRegistration{{"determinism", kSchema, kModel, {}, true}};

}  // namespace

}  // namespace gi
