// The checks a scenario may name, and the parameter keys each accepts: what
// the scenario parser needs to know of the checks, and no more. The checks
// themselves live in checks/, one file each; each declares itself
// here at start-up through its registration (checks/check_registry.h),
// so core parses a scenario without knowing any check by name, and a new
// check touches no parser, summary or report.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi {

struct CheckSpec;
struct Scenario;

// The statistics behind a check's verdict (docs/statistics.md, "Each check's
// model"): what its figure estimates, the noise estimate its limit allows
// for, and how often that limit fails a pipeline without the bug.
struct CheckModel {
  enum class Basis {
    exact,     // a count or a bit comparison: no sampling noise reaches the verdict
    derived,   // the rate follows from the noise model (a stated quantile)
    measured,  // the limit is placed from the fixed pipeline's spread over seeds
  };
  std::string estimates;  // what the judged figure estimates
  std::string noise;      // the noise estimate the limit allows for
  Basis basis = Basis::measured;
  // Per judged run on a pipeline without the bug: 0 for exact checks, the
  // quantile's tail for derived ones, the normal tail at the measured margin
  // for measured ones. The seed soak (tests/alarm_rates/) counts alarms
  // against it.
  double false_alarm_rate = 0.0;
  std::string false_alarm;  // the rate in words, with where it comes from
};

const char* to_string(CheckModel::Basis basis);

struct CheckDeclaration {
  std::string name;
  // The JSON Schema of the check's object (scenarios/schema.json's
  // $defs/check_<name>, which with_declared_checks writes from it): its
  // properties are every key the object may hold, "name" included.
  std::string schema;
  // Every check states one (declare_check refuses a declaration without it);
  // the schema's description and every result's limits carry it.
  CheckModel model = {};
  // Parse-time validation of what needs no run (types, ranges): an InputError
  // naming the check's JSON path. Empty: the check validates when it is made.
  std::function<void(const CheckSpec&, const Scenario&)> validate;
  // The check runs the scenario again itself (determinism): runs that are
  // themselves repeats (a replay, a failure capture's rerun) drop it.
  bool reruns_scenario = false;
  std::vector<std::string> keys = {};  // the schema's properties (declare_check fills them)
};

// Drops the checks that run the scenario again (CheckDeclaration::reruns_scenario).
void drop_rerunning_checks(Scenario& scenario);

// The scenario schema with its check part written from the declared checks:
// $defs/check (the names, and each name's parameters by reference) and one
// $defs/check_<name> per check, in name order; everything else as given.
// scenarios/schema.json is this of itself (`giharness schema` writes it; the
// schema test holds it so).
nlohmann::ordered_json with_declared_checks(nlohmann::ordered_json schema);

// Called during static initialisation (one declaration per name); a schema
// that is not a JSON object with properties, or a model left unstated, is a
// logic_error.
void declare_check(CheckDeclaration declaration);
// Sorted by name; complete once static initialisation is over.
const std::vector<CheckDeclaration>& declared_checks();
const CheckDeclaration* find_declared_check(const std::string& name);

}  // namespace gi
