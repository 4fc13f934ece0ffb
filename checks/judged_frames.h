// A check's "frames" parameter: the frames it judges, read the one way every
// counter check reads it (each an integer in [first, frames − 1], an input
// error at its JSON path otherwise).
#pragma once
#include <cstdint>
#include <optional>
#include <set>

#include "core/json_reader.h"
#include "checks/check.h"

namespace gi {

// None when the scenario gives no "frames" (the check's own default).
inline std::optional<std::set<std::uint32_t>> judged_frames(const CheckContext& c, std::uint32_t first = 0) {
  const nlohmann::json& p = c.spec.params;
  if (!p.contains("frames")) return std::nullopt;
  const JsonReader r(c.scenario.file.string());
  const std::string at = c.spec.json_path + "/frames";
  const nlohmann::json& f = r.array(p["frames"], at, 1);
  std::set<std::uint32_t> judged;
  for (std::size_t i = 0; i < f.size(); ++i) judged.insert(r.uint(f[i], JsonReader::at(at, i), first, c.frames - 1));
  return judged;
}

}  // namespace gi
