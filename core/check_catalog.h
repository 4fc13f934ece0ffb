// The checks a scenario may name, and the parameter keys each accepts: what
// the scenario parser needs to know of the checks, and no more. The checks
// themselves live in replay/checks/, one file each; each declares itself
// here at start-up through its registration (replay/checks/check_registry.h),
// so core parses a scenario without knowing any check by name, and a new
// check touches no parser, summary or report.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace gi {

struct CheckSpec;
struct Scenario;

struct CheckDeclaration {
  std::string name;
  std::vector<std::string> keys;  // every key the check's object may hold, "name" included
  // Parse-time validation of what needs no run (types, ranges): an InputError
  // naming the check's JSON path. Empty: the check validates when it is made.
  std::function<void(const CheckSpec&, const Scenario&)> validate;
  // The check runs the scenario again itself (determinism): runs that are
  // themselves repeats (a replay, a failure capture's rerun) drop it.
  bool reruns_scenario = false;
};

// Drops the checks that run the scenario again (CheckDeclaration::reruns_scenario).
void drop_rerunning_checks(Scenario& scenario);

// Called during static initialisation (one declaration per name).
void declare_check(CheckDeclaration declaration);
// Sorted by name; complete once static initialisation is over.
const std::vector<CheckDeclaration>& declared_checks();
const CheckDeclaration* find_declared_check(const std::string& name);

}  // namespace gi
