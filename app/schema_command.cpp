// `giharness schema`: the scenario schema with its check part written from the
// checks' own declarations (core/check_catalog.h, with_declared_checks).
// Everything but the checks is read from the installed scenarios/schema.json;
// `--out` rewrites a file atomically (scenarios/schema.json itself after a
// check changed its parameters).
#include <fstream>
#include <iostream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/check_catalog.h"
#include "core/data_dir.h"
#include "core/errors.h"
#include "app/commands.h"

namespace gi {

std::string scenario_schema_text() {
  const std::filesystem::path base = data_dir() / "scenarios" / "schema.json";
  std::ifstream in(base, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::ordered_json schema = nlohmann::ordered_json::parse(text.str(), nullptr, /*allow_exceptions=*/false);
  if (!in || !schema.is_object() || !schema.contains("$defs"))
    throw InputError(base.string(), "", "expected the scenario schema, a JSON object with $defs");
  return with_declared_checks(schema).dump(2, ' ', /*ensure_ascii=*/false) + "\n";
}

int run_schema_command(const SchemaOptions& o) {
  const std::string text = scenario_schema_text();
  if (o.out.empty())
    std::cout << text;
  else
    write_text_file(o.out, text);
  return 0;
}

}  // namespace gi
