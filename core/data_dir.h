// Where giharness finds the files it reads at run time: the GLSL it compiles
// (gpu/shaders, core/shared and two C++/GLSL headers they include), the
// profiles, schema and assets under scenarios/, the nightly suite and the
// committed baselines (reports/baselines). The folder has the source tree's
// layout, so a checkout is a valid data folder too.
//
// Lookup, the first match wins (a match holds gpu/shaders and
// scenarios/profiles):
//   1. $GIHARNESS_DATA_DIR; an error if it is set and does not match (a typo
//      must not silently run other shaders);
//   2. <exe dir>/../share/giharness: an installed binary (<prefix>/bin), and
//      the test binary (<build>/tests);
//   3. <exe dir>/share/giharness: the build tree's binary (<build>/giharness),
//      where CMake keeps a tree of symlinks into the source tree.
// The executable is /proc/self/exe, so a symlink to the binary still finds
// its own installation. No source path is compiled in: the binary runs from
// any directory and with the checkout gone (tests/install_test.sh).
#pragma once
#include <filesystem>

#include "core/errors.h"

namespace gi {

// The lookup above, done once per process. Throws DataDirError (core/errors.h).
const std::filesystem::path& data_dir();

// The lookup itself, for tests: `env` is $GIHARNESS_DATA_DIR (nullptr when
// unset), `exe` the running executable's path.
std::filesystem::path find_data_dir(const char* env, const std::filesystem::path& exe);

}  // namespace gi
