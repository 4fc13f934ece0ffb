// Where giharness keeps what it can rebuild (compiled SPIR-V under spirv/,
// Embree references under reference/, the shader prewarm's markers under
// prewarmed/): $GIHARNESS_CACHE_DIR, else
// $XDG_CACHE_HOME/giharness, else ~/.cache/giharness, else a folder in the
// temporary directory. One lookup for the shader compiler and the commands.
#pragma once
#include <filesystem>

namespace gi {

std::filesystem::path cache_root();

}  // namespace gi
