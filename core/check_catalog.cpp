#include "core/check_catalog.h"

#include "core/scenario.h"

#include <algorithm>
#include <stdexcept>

namespace gi {
namespace {

// A function-local static: declarations arrive during static initialisation,
// in an order the linker chooses.
std::vector<CheckDeclaration>& catalog() {
  static std::vector<CheckDeclaration> declarations;
  return declarations;
}

}  // namespace

void declare_check(CheckDeclaration declaration) {
  std::vector<CheckDeclaration>& c = catalog();
  if (find_declared_check(declaration.name)) throw std::logic_error("check declared twice: " + declaration.name);
  const auto at = std::lower_bound(c.begin(), c.end(), declaration.name,
                                   [](const CheckDeclaration& d, const std::string& n) { return d.name < n; });
  c.insert(at, std::move(declaration));
}

const std::vector<CheckDeclaration>& declared_checks() { return catalog(); }

const CheckDeclaration* find_declared_check(const std::string& name) {
  for (const CheckDeclaration& d : catalog())
    if (d.name == name) return &d;
  return nullptr;
}

void drop_rerunning_checks(Scenario& scenario) {
  std::erase_if(scenario.checks, [](const CheckSpec& c) {
    const CheckDeclaration* d = find_declared_check(c.name);
    return d && d->reruns_scenario;
  });
}

}  // namespace gi
