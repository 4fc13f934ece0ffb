// GLSL -> SPIR-V at run time (glslang), Vulkan 1.2 / SPIR-V 1.4, with defines
// and #include, cached on disk. A scenario compiles only the passes it uses,
// each with the defines it needs (Falcor-style programs from define lists).
//
// Includes (GL_GOOGLE_include_directive, enabled for every shader) resolve
// relative to the including file, then to the data folder (core/data_dir.h:
// the source tree's layout, installed or not), so a shader can write
// #include "core/shared/brdf.h".
//
// Cache: <cache_dir>/spirv/<XXH3-64 hex>.spv, keyed by the compiler version,
// the defines and the fully resolved source (the main file and the content of
// every file it includes, recursively, with its path relative to the data
// folder, so an installation shares the build tree's entries). Files are
// written under a temporary name and renamed into place, so concurrent runs
// never read half a file.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gi::gpu {

struct ShaderDefine {
  std::string name;
  std::string value;  // "#define name value"; may be empty
};

struct CompiledShader {
  std::string name;                  // the file as the compiler names it in messages
  std::vector<std::uint32_t> spirv;
  std::uint64_t key = 0;             // the cache key
  bool cache_hit = false;
};

class ShaderCompiler {
 public:
  // cache_dir: the cache root (SPIR-V under its spirv/); without it, default_cache_dir().
  explicit ShaderCompiler(std::optional<std::filesystem::path> cache_dir = std::nullopt);
  ~ShaderCompiler();
  ShaderCompiler(const ShaderCompiler&) = delete;
  ShaderCompiler& operator=(const ShaderCompiler&) = delete;

  // cache_root() (core/cache_root.h); SPIR-V goes to its spirv/ folder.
  static std::filesystem::path default_cache_dir();
  // glslang's version and the targets; part of every cache key.
  static std::string compiler_version();

  // A compute shader file; a relative path is taken from the data folder
  // (core/data_dir.h), e.g. "gpu/shaders/primary_visibility.comp".
  // Throws DeviceError with glslang's log and the defines on a compile error.
  CompiledShader compile_file(const std::filesystem::path& path, const std::vector<ShaderDefine>& defines = {});
  // The same for source text; `name` (relative to the data folder) anchors
  // its relative includes and names it in messages.
  CompiledShader compile_source(const std::string& source, const std::string& name,
                                const std::vector<ShaderDefine>& defines = {});

  // Defines added to every compile from now on, before the call's own: the
  // tracing backend's variant (gpu/bvh_buffers.h's trace_backend_defines),
  // which the Renderer sets from its Device, so that no pass knows which
  // backend runs. Part of the cache key like any define.
  void set_global_defines(std::vector<ShaderDefine> defines) { global_defines_ = std::move(defines); }
  const std::vector<ShaderDefine>& global_defines() const { return global_defines_; }

  const std::filesystem::path& cache_dir() const { return cache_dir_; }  // holds spirv/
  std::uint64_t cache_hits() const { return hits_; }
  std::uint64_t cache_misses() const { return misses_; }

 private:
  std::filesystem::path cache_dir_;
  std::vector<ShaderDefine> global_defines_;
  std::uint64_t hits_ = 0;
  std::uint64_t misses_ = 0;
};

}  // namespace gi::gpu
