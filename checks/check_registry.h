// Checks by name. Each check file registers itself in an anonymous-namespace
// object, which also declares its name and keys to the scenario parser
// (core/check_catalog.h):
//
//   const RegisteredCheck<FiniteCheck> kRegistration{{"finite", kSchema, {}}};
//
// Where the kind of check depends on the context (the reference check), a
// CheckRegistration with its own factory does the same. Nothing else names a check: the parser, the frame
// loop, the summary, the JUnit writer and the reports find them here or in
// the results. (The giharness and test binaries link gi_replay whole, so
// registrations in otherwise unreferenced files are kept.)
#pragma once
#include <memory>
#include <utility>

#include "core/check_catalog.h"
#include "checks/check.h"

namespace gi {

using CheckFactory = std::unique_ptr<Check> (*)(const CheckContext& context);

struct CheckRegistration {
  CheckRegistration(CheckDeclaration declaration, CheckFactory factory);
};

// The usual registration: the declaration, and a factory that makes a T.
template <class T>
struct RegisteredCheck : CheckRegistration {
  explicit RegisteredCheck(CheckDeclaration declaration)
      : CheckRegistration(std::move(declaration),
                          [](const CheckContext& c) -> std::unique_ptr<Check> { return std::make_unique<T>(c); }) {}
};

// The check the context's spec names; InputError from its parameters.
std::unique_ptr<Check> make_check(const CheckContext& context);

}  // namespace gi
