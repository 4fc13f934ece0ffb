// Seeds as a dimension (`run --seeds N`, `nightly --seeds N`): the N seeds a
// scenario runs at, derived from one base seed (the scenario's own, or
// `run --seed`) by a fixed rule, so a night's seeds are the same every night
// and on every machine.
//
// The rule (version "splitmix64-v1"):
//   seed 0 is the base itself (so `--seeds 1` is today's run, bit for bit);
//   seed k >= 1 is the low 32 bits of x = mix(mix(base) XOR k), where mix is
//   splitmix64's step (add 0x9E3779B97F4A7C15, then its two xor-shift-multiply
//   rounds: Steele, Lea and Flood 2014, as in java.util.SplittableRandom);
//   should that value already be in the set (a 32-bit collision, about one
//   set in 8 600 at N = 1000), x = mix(x) again until it is not.
// So seed k depends on the base and k alone, except after a collision, and
// the N seeds are distinct. Changing the rule changes every night's seeds:
// tests/seeds_test.cpp holds expected values.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace gi {

inline constexpr std::uint32_t kMaxSeeds = 1000;  // `--seeds` above this is bad input (exit 2)
inline constexpr const char* kSeedRule = "splitmix64-v1";

// splitmix64's output function on one 64-bit value.
std::uint64_t splitmix64(std::uint64_t x);

// The first `count` seeds of `base`'s set (the rule above); seed_set(b, 1) is {b}.
std::vector<std::uint32_t> seed_set(std::uint32_t base, std::uint32_t count);

// The out dir of one seed's run: "seed-<value>".
std::string seed_dir_name(std::uint32_t seed);

// The rule in one sentence, for summary.json.
std::string seed_rule_text();

}  // namespace gi
