#include "core/seed_set.h"

#include <algorithm>

namespace gi {

std::uint64_t splitmix64(std::uint64_t x) {
  std::uint64_t z = x + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::vector<std::uint32_t> seed_set(std::uint32_t base, std::uint32_t count) {
  std::vector<std::uint32_t> seeds;
  seeds.reserve(count);
  if (count > 0) seeds.push_back(base);
  const std::uint64_t mixed_base = splitmix64(base);
  for (std::uint32_t k = 1; k < count; ++k) {
    std::uint64_t x = splitmix64(mixed_base ^ std::uint64_t(k));
    while (std::find(seeds.begin(), seeds.end(), std::uint32_t(x)) != seeds.end()) x = splitmix64(x);
    seeds.push_back(std::uint32_t(x));
  }
  return seeds;
}

std::string seed_dir_name(std::uint32_t seed) { return "seed-" + std::to_string(seed); }

std::string seed_rule_text() {
  return std::string(kSeedRule) +
         ": seed 0 is the base seed; seed k >= 1 is the low 32 bits of x = splitmix64(splitmix64(base) xor k), "
         "x = splitmix64(x) again while that value is already in the set (core/seed_set.h)";
}

}  // namespace gi
