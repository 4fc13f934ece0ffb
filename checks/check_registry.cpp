#include "checks/check_registry.h"

#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/run_options.h"
#include "gpu/realtime_settings.h"

namespace gi {
namespace {

std::map<std::string, CheckFactory>& factories() {
  static std::map<std::string, CheckFactory> f;  // filled during static initialisation
  return f;
}

}  // namespace

CheckRegistration::CheckRegistration(CheckDeclaration declaration, CheckFactory factory) {
  factories()[declaration.name] = factory;
  declare_check(std::move(declaration));
}

std::unique_ptr<Check> make_check(const CheckContext& context) {
  const auto it = factories().find(context.spec.name);
  if (it == factories().end())  // the parser accepts declared names only
    throw std::logic_error("no registered check named " + context.spec.name);
  return it->second(context);
}

const RealtimeSettings& CheckContext::resolved_settings() const {
  if (settings) return *settings;
  if (!resolved_here) resolved_here = std::make_shared<const RealtimeSettings>(realtime_settings(profile));
  return *resolved_here;
}

void CheckContext::refuse(const std::string& key, const std::string& why) const {
  throw InputError(scenario.file.string(), spec.json_path + "/" + (key.empty() ? std::string("name") : key),
                   fmt::format("\"{}\" {}", spec.name, why));
}

}  // namespace gi
