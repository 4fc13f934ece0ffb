// The points of a `giharness sweep`: `--vary key=v1,v2,…` (repeatable) over a
// scenario document, the cartesian product in command-line order (the last
// key varies fastest). What a key names:
//   - a top-level scenario key (samples_per_frame, frames, seed, resolution,
//     mode, profile, …): that key; "resolution" also takes WxH (64x36);
//   - a JSON Pointer (starts with '/', e.g. /scene/params/light_scale): that
//     value of the document;
//   - anything else: a profile key (e.g. restir_di.initial_samples), set in
//     the scenario's "overrides", the layer `--set` also writes, so the
//     profile validates it exactly as it validates --set.
// Values are JSON where they parse (4, 0.5, true, [64,36]), else strings.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi {

struct SweepAxis {
  std::string key;
  std::vector<std::string> values;  // as typed
};

struct SweepPoint {
  std::vector<std::pair<std::string, std::string>> settings;  // key, value as typed
  nlohmann::json document;                                    // the scenario with them applied
  std::string label() const;                                  // "samples_per_frame=4 resolution=64x36"
  std::string slug() const;                                   // a folder name: samples_per_frame-4_resolution-64x36
};

// InputError naming "--vary" for a malformed item ("key=v1,v2").
SweepAxis parse_sweep_axis(const std::string& item);

// The product of the axes over `base` (a scenario document). InputError
// naming "--vary" for a pointer that does not resolve.
std::vector<SweepPoint> sweep_points(const nlohmann::json& base, const std::vector<SweepAxis>& axes);

}  // namespace gi
