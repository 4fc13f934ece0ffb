#include "gpu/shader_compiler.h"

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>

#include <fmt/format.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <spdlog/spdlog.h>
#include <unistd.h>
#include <xxhash.h>

#include "core/cache_root.h"
#include "core/data_dir.h"
#include "core/errors.h"
#include "core/phase_clock.h"

namespace gi::gpu {

namespace fs = std::filesystem;

namespace {

// glslang wants one InitializeProcess per process before any shader.
void ensure_glslang() {
  static std::once_flag once;
  std::call_once(once, [] { glslang::InitializeProcess(); });
}

std::optional<std::string> read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string defines_text(const std::vector<ShaderDefine>& defines) {
  if (defines.empty()) return "(none)";
  std::string s;
  for (const auto& d : defines) s += (s.empty() ? "" : ", ") + (d.value.empty() ? d.name : d.name + "=" + d.value);
  return s;
}

// Resolves includes relative to the includer, then to the data folder, and
// remembers every file it handed out (name and content) for the cache key.
class Includer : public glslang::TShader::Includer {
 public:
  explicit Includer(fs::path root) : root_(std::move(root)) {}

  IncludeResult* includeLocal(const char* header, const char* includer, size_t) override {
    fs::path from = fs::path(includer).parent_path();
    if (auto r = open(from / header)) return r;
    return open(root_ / header);
  }
  IncludeResult* includeSystem(const char* header, const char*, size_t) override { return open(root_ / header); }
  void releaseInclude(IncludeResult* r) override {
    if (r) delete static_cast<std::string*>(r->userData);
    delete r;
  }

  // (resolved path, content) in the order the preprocessor asked for them.
  const std::vector<std::pair<std::string, std::string>>& files() const { return files_; }

 private:
  IncludeResult* open(const fs::path& candidate) {
    std::error_code ec;
    if (!fs::is_regular_file(candidate, ec)) return nullptr;
    std::optional<std::string> text = read_text(candidate);
    if (!text) return nullptr;
    std::string name = candidate.lexically_normal().string();
    files_.emplace_back(name, *text);
    auto* data = new std::string(std::move(*text));
    return new IncludeResult(name, data->data(), data->size(), data);
  }

  fs::path root_;
  std::vector<std::pair<std::string, std::string>> files_;
};

struct ShaderSetup {
  std::unique_ptr<glslang::TShader> shader;
  std::string preamble;
  const char* text;
  int length;
  const char* name;
};

std::unique_ptr<glslang::TShader> make_shader(const std::string& source, const std::string& name,
                                              const std::string& preamble, const char** text, int* length,
                                              const char** cname) {
  auto shader = std::make_unique<glslang::TShader>(EShLangCompute);
  *text = source.c_str();
  *length = int(source.size());
  *cname = name.c_str();
  shader->setStringsWithLengthsAndNames(text, length, cname, 1);
  shader->setPreamble(preamble.c_str());
  shader->setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
  shader->setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
  shader->setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_4);
  shader->setEntryPoint("main");
  return shader;
}

std::string hex64(std::uint64_t v) { return fmt::format("{:016x}", v); }

// An include's name in the cache key: relative to the data folder, so the
// build tree, an installation and a moved installation share their cache
// entries (the content is hashed beside it).
std::string key_name(const std::string& file, const fs::path& root) {
  const fs::path rel = fs::path(file).lexically_relative(root);
  return rel.empty() || *rel.begin() == ".." ? file : rel.generic_string();
}

}  // namespace

ShaderCompiler::ShaderCompiler(std::optional<fs::path> cache_dir)
    : cache_dir_(cache_dir ? *cache_dir : default_cache_dir()) {
  ensure_glslang();
}

ShaderCompiler::~ShaderCompiler() = default;

fs::path ShaderCompiler::default_cache_dir() { return cache_root(); }

std::string ShaderCompiler::compiler_version() {
  glslang::Version v = glslang::GetVersion();
  return fmt::format("glslang {}.{}.{}{} vulkan1.2 spirv1.4 giharness-shader-cache-1", v.major, v.minor, v.patch,
                     v.flavor ? v.flavor : "");
}

CompiledShader ShaderCompiler::compile_file(const fs::path& path, const std::vector<ShaderDefine>& defines) {
  fs::path full = path.is_absolute() ? path : data_dir() / path;
  std::optional<std::string> source = read_text(full);
  if (!source) throw DeviceError(fmt::format("shader {}: cannot read {}", path.string(), full.string()));
  return compile_source(*source, full.lexically_normal().string(), defines);
}

CompiledShader ShaderCompiler::compile_source(const std::string& source, const std::string& name_in,
                                              const std::vector<ShaderDefine>& own_defines) {
  const PhaseScope timed(phase::kShaderSources);
  std::vector<ShaderDefine> defines = global_defines_;
  defines.insert(defines.end(), own_defines.begin(), own_defines.end());
  const fs::path& root = data_dir();
  const std::string name = fs::path(name_in).is_absolute() ? name_in : (root / name_in).lexically_normal().string();
  std::string preamble = "#extension GL_GOOGLE_include_directive : require\n";
  for (const auto& d : defines) preamble += "#define " + d.name + (d.value.empty() ? "" : " " + d.value) + "\n";
  const TBuiltInResource* resources = GetDefaultResources();
  const auto messages = EShMessages(EShMsgSpvRules | EShMsgVulkanRules);
  auto fail = [&](const std::string& stage, const std::string& log) -> DeviceError {
    return DeviceError(fmt::format("shader {}: {} failed\n  defines: {}\n{}", name, stage, defines_text(defines), log));
  };

  // 1. Preprocess: resolves every include, so the key covers their content.
  Includer pre_includer(root);
  const char* text;
  int length;
  const char* cname;
  auto pre = make_shader(source, name, preamble, &text, &length, &cname);
  std::string preprocessed;
  if (!pre->preprocess(resources, 460, ENoProfile, false, false, messages, &preprocessed, pre_includer))
    throw fail("preprocessing", std::string(pre->getInfoLog()) + pre->getInfoDebugLog());

  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  auto feed = [&](const std::string& s) {
    std::uint64_t n = s.size();
    XXH3_64bits_update(state, &n, sizeof n);
    XXH3_64bits_update(state, s.data(), s.size());
  };
  feed(compiler_version());
  feed(preamble);
  feed(source);
  for (const auto& [file, content] : pre_includer.files()) {
    feed(key_name(file, root));
    feed(content);
  }
  const std::uint64_t key = XXH3_64bits_digest(state);
  XXH3_freeState(state);

  CompiledShader out;
  out.name = name;
  out.key = key;
  const fs::path dir = cache_dir_ / "spirv";
  const fs::path file = dir / (hex64(key) + ".spv");
  if (std::optional<std::string> cached = read_text(file); cached && !cached->empty() && cached->size() % 4 == 0) {
    out.spirv.resize(cached->size() / 4);
    std::memcpy(out.spirv.data(), cached->data(), cached->size());
    if (out.spirv[0] == 0x07230203u) {
      out.cache_hit = true;
      ++hits_;
      spdlog::debug("shader {} [{}]: cache hit {}", name, defines_text(defines), file.string());
      return out;
    }
    out.spirv.clear();
  }

  // 2. Compile.
  Includer includer(root);
  auto shader = make_shader(source, name, preamble, &text, &length, &cname);
  if (!shader->parse(resources, 460, false, messages, includer))
    throw fail("compilation", std::string(shader->getInfoLog()) + shader->getInfoDebugLog());
  glslang::TProgram program;
  program.addShader(shader.get());
  if (!program.link(messages)) throw fail("linking", std::string(program.getInfoLog()) + program.getInfoDebugLog());
  glslang::SpvOptions options;
  options.generateDebugInfo = false;
  spv::SpvBuildLogger logger;
  glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), out.spirv, &logger, &options);
  if (out.spirv.empty()) throw fail("SPIR-V generation", logger.getAllMessages());
  ++misses_;

  // 3. Store: temp name, then rename (atomic on one file system).
  std::error_code ec;
  fs::create_directories(dir, ec);
  static std::atomic<unsigned> counter{0};
  const fs::path tmp = dir / fmt::format("{}.tmp.{}.{}", hex64(key), ::getpid(), counter++);
  {
    std::ofstream o(tmp, std::ios::binary);
    o.write(reinterpret_cast<const char*>(out.spirv.data()), std::streamsize(out.spirv.size() * 4));
    if (!o) ec = std::make_error_code(std::errc::io_error);
  }
  if (!ec) fs::rename(tmp, file, ec);
  if (ec) {
    fs::remove(tmp, ec);
    spdlog::warn("shader cache: could not write {} (continuing without cache)", file.string());
  }
  spdlog::debug("shader {} [{}]: compiled, {} words", name, defines_text(defines), out.spirv.size());
  return out;
}

}  // namespace gi::gpu
