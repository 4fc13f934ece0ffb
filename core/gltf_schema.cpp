#include "core/gltf_schema.h"

// One function per schema file (accessor.schema.json → accessor(), ...), each
// listing its properties in the schema's order with the schema's constraints.
// The helpers below (Obj::integer, Obj::index, ...) are the rule classes:
// JSON type, required, enum, range, array length, index reference. String-
// typed properties are not theirs: one table (gltf_string_properties(), at
// the end) and one walk of it (Validator::check_strings) check them all first.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "core/errors.h"

namespace gi {
namespace {

using Json = nlohmann::json;

constexpr double kHalfPi = 1.5707963267948966;
// Byte sizes and counts: the schema sets no upper bound, but GLB chunks and
// TinyGLTF's fields are 32-bit, so larger values cannot describe real data.
constexpr std::int64_t kMaxU32 = 0xffffffffll;

enum class Need { optional, required };

// A numeric range as the schema writes it: minimum, exclusiveMinimum, maximum,
// exclusiveMaximum (draft-04 style: a bound plus whether it is exclusive).
struct Range {
  std::optional<double> min, max;
  bool min_exclusive = false, max_exclusive = false;

  bool contains(double v) const {
    if (min && (min_exclusive ? v <= *min : v < *min)) return false;
    if (max && (max_exclusive ? v >= *max : v > *max)) return false;
    return true;
  }
  std::string describe() const {
    auto num = [](double d) {
      std::string s = std::to_string(d);
      while (s.back() == '0') s.pop_back();
      if (s.back() == '.') s.pop_back();
      return s;
    };
    std::string s;
    if (min) s += (min_exclusive ? " > " : " ≥ ") + num(*min);
    if (min && max) s += " and";
    if (max) s += (max_exclusive ? " < " : " ≤ ") + num(*max);
    return s;
  }
};

Range any() { return {}; }
Range at_least(double lo) { return {lo, std::nullopt, false, false}; }
Range above(double lo) { return {lo, std::nullopt, true, false}; }
Range between(double lo, double hi) { return {lo, hi, false, false}; }
Range unit() { return between(0.0, 1.0); }  // factors: [0, 1]

// An array's length bounds (minItems / maxItems); exactly(n) for vectors.
struct Items {
  std::size_t min = 0, max = std::numeric_limits<std::size_t>::max();
};
Items exactly(std::size_t n) { return {n, n}; }
Items at_least_items(std::size_t n) { return {n}; }
Items items_between(std::size_t lo, std::size_t hi) { return {lo, hi}; }

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

// Integer value of a JSON integer (unsigned ones beyond int64 saturate); none
// for floats, even 2.0: the schema's "integer" is what JSON spells as one.
std::optional<std::int64_t> integer_of(const Json& v) {
  if (v.is_number_unsigned()) {
    const std::uint64_t u = v.get<std::uint64_t>();
    return u > std::uint64_t(std::numeric_limits<std::int64_t>::max()) ? std::numeric_limits<std::int64_t>::max()
                                                                       : std::int64_t(u);
  }
  if (v.is_number_integer()) return v.get<std::int64_t>();
  return std::nullopt;
}

// %XX decoding of a relative URI (glTF URIs are URI-encoded).
std::string uri_decode(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(s[i]);
    }
  }
  return out;
}

// "one of "A", "B"" for an enum's values.
std::string one_of(const std::vector<std::string>& values) {
  std::string list;
  for (const std::string& v : values) list += (list.empty() ? "" : ", ") + quoted(v);
  return "one of " + list;
}

// What a string property must be, as an error message says it.
std::string describe(const GltfStringProperty& p) {
  return p.values.empty() ? "a string" : "a string, " + one_of(p.values);
}

class Validator;

// A JSON object of the document at a JSON pointer, with one checker per rule
// class. Each returns the property (nullptr when absent and optional) so a
// caller can check what depends on it.
class Obj {
 public:
  Obj(const Validator& v, const Json& j, std::string path) : v_(v), j_(j), path_(std::move(path)) {}

  const std::string& path() const { return path_; }
  const Json& json() const { return j_; }
  bool has(const char* key) const { return j_.contains(key); }
  std::string at(const std::string& key) const { return path_ + "/" + key; }

  [[noreturn]] void fail(const std::string& path, const std::string& expected) const;

  const Json* present(const char* key, Need need, const char* type_text) const {
    auto it = j_.find(key);
    if (it == j_.end()) {
      if (need == Need::required) fail(path_, "a required " + quoted(key) + " property (" + type_text + ")");
      return nullptr;
    }
    return &*it;
  }

  const Json* integer(const char* key, Need need, Range range = any()) const {
    const Json* p = present(key, need, "an integer");
    if (p) check_integer(*p, at(key), range);
    return p;
  }
  const Json* number(const char* key, Need need, Range range = any()) const {
    const Json* p = present(key, need, "a number");
    if (p) check_number(*p, at(key), range);
    return p;
  }
  const Json* boolean(const char* key) const {
    const Json* p = present(key, Need::optional, "a boolean");
    if (p && !p->is_boolean()) fail(at(key), "a boolean");
    return p;
  }
  const Json* string(const char* key, Need need) const {
    const Json* p = present(key, need, "a string");
    if (p && !p->is_string()) fail(at(key), "a string");
    return p;
  }
  const Json* integer_enum(const char* key, Need need, std::initializer_list<std::int64_t> values) const {
    std::string list;
    for (std::int64_t x : values) list += (list.empty() ? "" : ", ") + std::to_string(x);
    const Json* p = present(key, need, ("one of " + list).c_str());
    if (!p) return p;
    if (auto i = integer_of(*p))
      for (std::int64_t x : values)
        if (*i == x) return p;
    fail(at(key), "one of " + list);
  }
  // An array of numbers, each in `range`, with `items` elements.
  const Json* numbers(const char* key, Need need, Items items, Range range = any()) const {
    const Json* p = array(key, need, items);
    if (p)
      for (std::size_t i = 0; i < p->size(); ++i) check_number((*p)[i], at(key) + "/" + std::to_string(i), range);
    return p;
  }
  const Json* array(const char* key, Need need, Items items) const;
  // A glTFid: an integer index into the top-level array `collection`.
  const Json* index(const char* key, Need need, const char* collection) const;
  // An array of glTFids; uniqueItems where the schema says so.
  const Json* indices(const char* key, Need need, const char* collection, bool unique) const;
  // A nested object checked by `kind`.
  template <class Kind>
  const Json* object(const char* key, Need need, Kind kind) const {
    const Json* p = present(key, need, "an object");
    if (!p) return p;
    if (!p->is_object()) fail(at(key), "an object");
    kind(Obj(v_, *p, at(key)));
    return p;
  }
  // An array of objects, each checked by `kind`.
  template <class Kind>
  const Json* objects(const char* key, Need need, Items items, Kind kind) const {
    const Json* p = array(key, need, items);
    if (!p) return p;
    for (std::size_t i = 0; i < p->size(); ++i) {
      const std::string ip = at(key) + "/" + std::to_string(i);
      if (!(*p)[i].is_object()) fail(ip, "an object");
      kind(Obj(v_, (*p)[i], ip));
    }
    return p;
  }
  // The "extensions" object's entry `name`, checked by `kind` when present.
  template <class Kind>
  void extension(const char* name, Kind kind) const {
    auto e = j_.find("extensions");
    if (e == j_.end()) return;
    if (!e->is_object()) fail(at("extensions"), "an object");
    Obj(v_, *e, at("extensions")).object(name, Need::optional, kind);
  }
  // JSON Schema "dependencies": `key` present requires `needed`.
  void depends(const char* key, const char* needed) const {
    if (has(key) && !has(needed)) fail(path_, "a " + quoted(needed) + " property (required with " + quoted(key) + ")");
  }
  // JSON Schema "not": {"required": [a, b]}.
  void not_both(const char* a, const char* b) const {
    if (has(a) && has(b)) fail(at(b), "no " + quoted(b) + " next to " + quoted(a) + " (they exclude each other)");
  }
  void check_integer(const Json& value, const std::string& path, Range range) const {
    const auto i = integer_of(value);
    if (!i) fail(path, "an integer" + range.describe());
    if (!range.contains(double(*i))) fail(path, "an integer" + range.describe());
  }
  void check_number(const Json& value, const std::string& path, Range range) const {
    // A JSON number that overflowed a double (1e400) is not a number to use.
    if (!value.is_number() || !std::isfinite(value.get<double>())) fail(path, "a finite number" + range.describe());
    if (!range.contains(value.get<double>())) fail(path, "a number" + range.describe());
  }

 private:
  const Validator& v_;
  const Json& j_;
  std::string path_;
};

// Byte sizes and offsets: integers with the schema's minimum, below 2^32.
Range u32_from(double lo) { return between(lo, double(kMaxU32)); }

class Validator {
 public:
  Validator(const Json& doc, std::string file, bool glb) : doc_(doc), file_(std::move(file)), glb_(glb) {}

  [[noreturn]] void fail(const std::string& path, const std::string& expected) const {
    throw InputError(file_, path, expected);
  }

  // Number of items of the top-level array `collection` ("lights" is
  // KHR_lights_punctual's, under /extensions).
  std::size_t count(const std::string& collection) const {
    const Json* arr = nullptr;
    if (collection == "lights") {
      const Json* ext = find(doc_, "extensions");
      const Json* lp = ext && ext->is_object() ? find(*ext, "KHR_lights_punctual") : nullptr;
      arr = lp && lp->is_object() ? find(*lp, "lights") : nullptr;
    } else {
      arr = find(doc_, collection.c_str());
    }
    return arr && arr->is_array() ? arr->size() : 0;
  }
  static std::string collection_path(const std::string& collection) {
    return collection == "lights" ? "/extensions/KHR_lights_punctual/lights" : "/" + collection;
  }
  void check_index(const Json& value, const std::string& path, const std::string& collection) const {
    const std::size_t n = count(collection);
    const auto i = integer_of(value);
    if (i && *i >= 0 && std::uint64_t(*i) < n) return;
    fail(path, "an index into " + collection_path(collection) +
                   (n ? " (0.." + std::to_string(n - 1) + ")" : " (which has no items)"));
  }

  void run() const;

 private:
  // The string-typed properties (gltf_string_properties()), before the rest:
  // the schema functions below read the strings they depend on (a camera's
  // type, a buffer's uri) as checked strings.
  void check_strings() const;
  void walk_strings(const Json& here, const std::string& path, const std::vector<std::string>& segments,
                    std::size_t k, const GltfStringProperty& p) const;
  void check_string(const Json& value, const std::string& path, const GltfStringProperty& p) const;

  static const Json* find(const Json& o, const char* key) {
    auto it = o.find(key);
    return it == o.end() ? nullptr : &*it;
  }

  // ---- one function per schema file, properties in the schema's order ------

  void gltf(const Obj& o) const;
  static void asset(const Obj& o);
  void accessor(const Obj& o) const;
  void accessor_sparse(const Obj& o) const;
  void animation(const Obj& o) const;
  void buffer(const Obj& o, std::size_t i) const;
  static void buffer_view(const Obj& o);
  static void camera(const Obj& o);
  static void image(const Obj& o);
  void material(const Obj& o) const;
  void texture_info(const Obj& o) const;
  void mesh(const Obj& o) const;
  void primitive(const Obj& o) const;
  void node(const Obj& o) const;
  static void sampler(const Obj& o);
  static void scene(const Obj& o);
  static void skin(const Obj& o);
  static void texture(const Obj& o);
  static void light(const Obj& o);

  const Json& doc_;
  std::string file_;
  bool glb_;
};

void Obj::fail(const std::string& path, const std::string& expected) const { v_.fail(path, expected); }

const Json* Obj::array(const char* key, Need need, Items items) const {
  const Json* p = present(key, need, "an array");
  if (!p) return p;
  std::string count_text;
  if (items.min == items.max)
    count_text = " of " + std::to_string(items.min) + " items";
  else if (items.max != std::numeric_limits<std::size_t>::max())
    count_text = " of " + std::to_string(items.min) + " to " + std::to_string(items.max) + " items";
  else if (items.min > 0)
    count_text = " of at least " + std::to_string(items.min) + " item" + (items.min == 1 ? "" : "s");
  if (!p->is_array() || p->size() < items.min || p->size() > items.max) fail(at(key), "an array" + count_text);
  return p;
}

const Json* Obj::index(const char* key, Need need, const char* collection) const {
  const Json* p = present(key, need, ("an index into " + Validator::collection_path(collection)).c_str());
  if (p) v_.check_index(*p, at(key), collection);
  return p;
}

const Json* Obj::indices(const char* key, Need need, const char* collection, bool unique) const {
  const Json* p = array(key, need, at_least_items(1));
  if (!p) return p;
  std::set<std::int64_t> seen;
  for (std::size_t i = 0; i < p->size(); ++i) {
    const std::string ip = at(key) + "/" + std::to_string(i);
    v_.check_index((*p)[i], ip, collection);
    if (unique && !seen.insert(*integer_of((*p)[i])).second) fail(ip, "an index not already in the array (uniqueItems)");
  }
  return p;
}

// glTF.schema.json. Every top-level array has minItems 1.
void Validator::gltf(const Obj& o) const {
  const Items some = at_least_items(1);
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    if (const Json* names = o.array(key, Need::optional, some)) {
      std::set<std::string> seen;
      for (std::size_t i = 0; i < names->size(); ++i) {
        const std::string ip = o.at(key) + "/" + std::to_string(i);
        if (!seen.insert((*names)[i].get<std::string>()).second) fail(ip, "an extension name not listed before");
      }
    }
  }
  // Checked before the arrays that index into them: lights come from here.
  o.extension("KHR_lights_punctual", [&](const Obj& lp) {
    lp.objects("lights", Need::required, some, [&](const Obj& l) { light(l); });
  });
  o.objects("accessors", Need::optional, some, [&](const Obj& x) { accessor(x); });
  o.objects("animations", Need::optional, some, [&](const Obj& x) { animation(x); });
  o.object("asset", Need::required, [&](const Obj& x) { asset(x); });
  if (const Json* buffers = o.array("buffers", Need::optional, some))
    for (std::size_t i = 0; i < buffers->size(); ++i) {
      const std::string ip = o.at("buffers") + "/" + std::to_string(i);
      if (!(*buffers)[i].is_object()) fail(ip, "an object");
      buffer(Obj(*this, (*buffers)[i], ip), i);
    }
  o.objects("bufferViews", Need::optional, some, [&](const Obj& x) { buffer_view(x); });
  o.objects("cameras", Need::optional, some, [&](const Obj& x) { camera(x); });
  o.objects("images", Need::optional, some, [&](const Obj& x) { image(x); });
  o.objects("materials", Need::optional, some, [&](const Obj& x) { material(x); });
  o.objects("meshes", Need::optional, some, [&](const Obj& x) { mesh(x); });
  o.objects("nodes", Need::optional, some, [&](const Obj& x) { node(x); });
  o.objects("samplers", Need::optional, some, [&](const Obj& x) { sampler(x); });
  o.index("scene", Need::optional, "scenes");
  o.objects("scenes", Need::optional, some, [&](const Obj& x) { scene(x); });
  o.objects("skins", Need::optional, some, [&](const Obj& x) { skin(x); });
  o.objects("textures", Need::optional, some, [&](const Obj& x) { texture(x); });
}

// asset.schema.json (its strings and their version pattern: the table); the
// major version must be 2 (the spec: a loader rejects other major versions).
void Validator::asset(const Obj& o) {
  const Json* version = o.string("version", Need::required);
  if (version->get<std::string>().rfind("2.", 0) != 0) o.fail(o.at("version"), "a glTF version \"2.<minor>\"");
}

// accessor.schema.json
void Validator::accessor(const Obj& o) const {
  o.index("bufferView", Need::optional, "bufferViews");
  o.integer("byteOffset", Need::optional, u32_from(0));
  o.integer_enum("componentType", Need::required, {5120, 5121, 5122, 5123, 5125, 5126});
  o.boolean("normalized");
  o.integer("count", Need::required, u32_from(1));
  o.numbers("max", Need::optional, items_between(1, 16));
  o.numbers("min", Need::optional, items_between(1, 16));
  o.object("sparse", Need::optional, [&](const Obj& x) { accessor_sparse(x); });
  o.depends("byteOffset", "bufferView");
}

// accessor.sparse.schema.json with its indices and values.
void Validator::accessor_sparse(const Obj& o) const {
  o.integer("count", Need::required, u32_from(1));
  o.object("indices", Need::required, [](const Obj& x) {
    x.index("bufferView", Need::required, "bufferViews");
    x.integer("byteOffset", Need::optional, u32_from(0));
    x.integer_enum("componentType", Need::required, {5121, 5123, 5125});  // unsigned only
  });
  o.object("values", Need::required, [](const Obj& x) {
    x.index("bufferView", Need::required, "bufferViews");
    x.integer("byteOffset", Need::optional, u32_from(0));
  });
}

// animation.schema.json, .channel, .channel.target, .sampler. A channel's
// sampler indexes this animation's own samplers.
void Validator::animation(const Obj& o) const {
  const Json* samplers = o.objects("samplers", Need::required, at_least_items(1), [](const Obj& s) {
    s.index("input", Need::required, "accessors");
    s.index("output", Need::required, "accessors");
  });
  o.objects("channels", Need::required, at_least_items(1), [&](const Obj& c) {
    const Json* s = c.present("sampler", Need::required, "an index into this animation's samplers");
    const auto i = integer_of(*s);
    if (!i || *i < 0 || std::uint64_t(*i) >= samplers->size())
      fail(c.at("sampler"), "an index into " + o.at("samplers") + " (0.." + std::to_string(samplers->size() - 1) + ")");
    c.object("target", Need::required, [](const Obj& t) { t.index("node", Need::optional, "nodes"); });
  });
}

// buffer.schema.json, plus where the bytes come from: a buffer without uri is
// the GLB binary chunk (only buffer 0 of a GLB), a relative uri must name an
// existing file next to the glTF (TinyGLTF's message would have no path).
void Validator::buffer(const Obj& o, std::size_t i) const {
  const Json* uri = o.string("uri", Need::optional);
  o.integer("byteLength", Need::required, u32_from(1));
  if (!uri) {
    if (!(glb_ && i == 0)) fail(o.path(), "a \"uri\" (only a .glb's first buffer may omit it)");
    return;
  }
  const std::string text = uri->get<std::string>();
  if (text.rfind("data:", 0) == 0) return;
  std::error_code ec;
  const std::filesystem::path p =
      std::filesystem::absolute(std::filesystem::path(file_), ec).parent_path() / std::filesystem::path(uri_decode(text));
  if (!std::filesystem::is_regular_file(p, ec))
    fail(o.at("uri"), "an existing buffer file (\"" + p.lexically_normal().string() + "\" does not exist)");
}

// bufferView.schema.json
void Validator::buffer_view(const Obj& o) {
  o.index("buffer", Need::required, "buffers");
  o.integer("byteOffset", Need::optional, u32_from(0));
  o.integer("byteLength", Need::required, u32_from(1));
  if (const Json* stride = o.integer("byteStride", Need::optional, between(4, 252)); stride && *integer_of(*stride) % 4)
    o.fail(o.at("byteStride"), "a multiple of 4 (multipleOf)");
  o.integer_enum("target", Need::optional, {34962, 34963});  // ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER
}

// camera.schema.json, .perspective, .orthographic. The object named by "type"
// must be there and the other must not; zfar > znear is the spec's prose.
void Validator::camera(const Obj& o) {
  auto znear_below_zfar = [](const Obj& x) {
    if (x.has("zfar") && x.has("znear") && x.json()["zfar"].get<double>() <= x.json()["znear"].get<double>())
      x.fail(x.at("zfar"), "zfar > znear");
  };
  o.object("orthographic", Need::optional, [&](const Obj& x) {
    x.number("xmag", Need::required);
    x.number("ymag", Need::required);
    x.number("zfar", Need::required, above(0));
    x.number("znear", Need::required, at_least(0));
    znear_below_zfar(x);
  });
  o.object("perspective", Need::optional, [&](const Obj& x) {
    x.number("aspectRatio", Need::optional, above(0));
    x.number("yfov", Need::required, above(0));
    x.number("zfar", Need::optional, above(0));
    x.number("znear", Need::required, above(0));
    znear_below_zfar(x);
  });
  const Json* type = o.string("type", Need::required);  // its enum: the table
  o.not_both("perspective", "orthographic");
  const std::string t = type->get<std::string>();
  if (!o.has(t.c_str())) o.fail(o.path(), "a " + quoted(t) + " object (\"type\" is " + quoted(t) + ")");
}

// image.schema.json: exactly one of uri and bufferView; bufferView needs mimeType.
void Validator::image(const Obj& o) {
  o.index("bufferView", Need::optional, "bufferViews");
  o.not_both("uri", "bufferView");
  if (!o.has("uri") && !o.has("bufferView")) o.fail(o.path(), "a \"uri\" or a \"bufferView\"");
  o.depends("bufferView", "mimeType");
}

// textureInfo.schema.json, with KHR_texture_transform.
void Validator::texture_info(const Obj& o) const {
  o.index("index", Need::required, "textures");
  o.integer("texCoord", Need::optional, at_least(0));  // not checked against the attributes
  o.extension("KHR_texture_transform", [](const Obj& x) {
    x.numbers("offset", Need::optional, exactly(2));
    x.number("rotation", Need::optional);
    x.numbers("scale", Need::optional, exactly(2));
    x.integer("texCoord", Need::optional, at_least(0));
  });
}

// material.schema.json, .pbrMetallicRoughness, .normalTextureInfo,
// .occlusionTextureInfo, and the material extensions the importer reads.
void Validator::material(const Obj& o) const {
  auto info = [&](const Obj& x) { texture_info(x); };
  o.object("pbrMetallicRoughness", Need::optional, [&](const Obj& x) {
    x.numbers("baseColorFactor", Need::optional, exactly(4), unit());
    x.object("baseColorTexture", Need::optional, info);
    x.number("metallicFactor", Need::optional, unit());
    x.number("roughnessFactor", Need::optional, unit());
    x.object("metallicRoughnessTexture", Need::optional, info);
  });
  o.object("normalTexture", Need::optional, [&](const Obj& x) {
    texture_info(x);
    x.number("scale", Need::optional);
  });
  o.object("occlusionTexture", Need::optional, [&](const Obj& x) {
    texture_info(x);
    x.number("strength", Need::optional, unit());
  });
  o.object("emissiveTexture", Need::optional, info);
  o.numbers("emissiveFactor", Need::optional, exactly(3), unit());
  o.number("alphaCutoff", Need::optional, at_least(0));
  o.boolean("doubleSided");
  o.extension("KHR_materials_emissive_strength",
              [](const Obj& x) { x.number("emissiveStrength", Need::optional, at_least(0)); });
  o.extension("KHR_materials_specular", [&](const Obj& x) {
    x.number("specularFactor", Need::optional, unit());
    x.object("specularTexture", Need::optional, info);
    x.numbers("specularColorFactor", Need::optional, exactly(3), at_least(0));
    x.object("specularColorTexture", Need::optional, info);
  });
  o.extension("KHR_materials_ior", [](const Obj& x) {
    // anyOf: exactly 0 (a special value) or ≥ 1.
    if (const Json* ior = x.number("ior", Need::optional); ior && ior->get<double>() != 0.0 && ior->get<double>() < 1.0)
      x.fail(x.at("ior"), "a number ≥ 1, or 0");
  });
}

// mesh.schema.json
void Validator::mesh(const Obj& o) const {
  o.objects("primitives", Need::required, at_least_items(1), [&](const Obj& x) { primitive(x); });
  o.numbers("weights", Need::optional, at_least_items(1));
}

// mesh.primitive.schema.json: attributes and each morph target map semantic
// names to accessors (minProperties 1).
void Validator::primitive(const Obj& o) const {
  auto semantics_to_accessors = [](const Obj& x) {
    if (x.json().empty()) x.fail(x.path(), "at least one attribute (minProperties 1)");
    for (auto it = x.json().begin(); it != x.json().end(); ++it) x.index(it.key().c_str(), Need::required, "accessors");
  };
  o.object("attributes", Need::required, semantics_to_accessors);
  o.index("indices", Need::optional, "accessors");
  o.index("material", Need::optional, "materials");
  o.integer_enum("mode", Need::optional, {0, 1, 2, 3, 4, 5, 6});  // POINTS .. TRIANGLE_FAN
  o.objects("targets", Need::optional, at_least_items(1), semantics_to_accessors);
}

// node.schema.json, with KHR_lights_punctual's light reference.
void Validator::node(const Obj& o) const {
  o.index("camera", Need::optional, "cameras");
  o.indices("children", Need::optional, "nodes", /*unique=*/true);
  o.index("skin", Need::optional, "skins");
  o.numbers("matrix", Need::optional, exactly(16));
  o.index("mesh", Need::optional, "meshes");
  o.numbers("rotation", Need::optional, exactly(4), between(-1, 1));
  o.numbers("scale", Need::optional, exactly(3));
  o.numbers("translation", Need::optional, exactly(3));
  o.numbers("weights", Need::optional, at_least_items(1));
  o.depends("weights", "mesh");
  o.depends("skin", "mesh");
  // "not": matrix together with any TRS property (reported at the matrix, as
  // glTF-Validator's NODE_MATRIX_TRS is).
  for (const char* trs : {"translation", "rotation", "scale"}) o.not_both(trs, "matrix");
  o.extension("KHR_lights_punctual", [](const Obj& x) { x.index("light", Need::required, "lights"); });
}

// sampler.schema.json: WebGL filter and wrap enums.
void Validator::sampler(const Obj& o) {
  o.integer_enum("magFilter", Need::optional, {9728, 9729});  // NEAREST, LINEAR
  o.integer_enum("minFilter", Need::optional, {9728, 9729, 9984, 9985, 9986, 9987});  // + the mipmap ones
  o.integer_enum("wrapS", Need::optional, {33071, 33648, 10497});  // CLAMP_TO_EDGE, MIRRORED_REPEAT, REPEAT
  o.integer_enum("wrapT", Need::optional, {33071, 33648, 10497});
}

// scene.schema.json
void Validator::scene(const Obj& o) { o.indices("nodes", Need::optional, "nodes", /*unique=*/true); }

// skin.schema.json
void Validator::skin(const Obj& o) {
  o.index("inverseBindMatrices", Need::optional, "accessors");
  o.index("skeleton", Need::optional, "nodes");
  o.indices("joints", Need::required, "nodes", /*unique=*/true);
}

// texture.schema.json
void Validator::texture(const Obj& o) {
  o.index("sampler", Need::optional, "samplers");
  o.index("source", Need::optional, "images");
}

// KHR_lights_punctual light.schema.json and light.spot.schema.json: a spot
// light needs its cone, 0 ≤ inner < outer ≤ π/2.
void Validator::light(const Obj& o) {
  o.numbers("color", Need::optional, exactly(3), unit());
  o.number("intensity", Need::optional, at_least(0));
  const Json* spot = o.object("spot", Need::optional, [](const Obj& x) {
    const Json* inner = x.number("innerConeAngle", Need::optional, Range{0.0, kHalfPi, false, true});
    const Json* outer = x.number("outerConeAngle", Need::optional, Range{0.0, kHalfPi, true, false});
    const double inner_angle = inner ? inner->get<double>() : 0.0, outer_angle = outer ? outer->get<double>() : kHalfPi / 2;
    if (inner_angle >= outer_angle) x.fail(x.path(), "innerConeAngle < outerConeAngle (defaults 0 and π/4)");
  });
  const Json* type = o.string("type", Need::required);  // its enum: the table
  o.number("range", Need::optional, above(0));
  if (type->get<std::string>() == "spot" && !spot) o.fail(o.path(), "a \"spot\" object (\"type\" is \"spot\")");
}

void Validator::check_strings() const {
  for (const GltfStringProperty& p : gltf_string_properties()) {
    std::vector<std::string> segments;
    for (std::size_t at = 1; at <= p.pointer.size();) {
      const std::size_t end = std::min(p.pointer.find('/', at), p.pointer.size());
      segments.push_back(p.pointer.substr(at, end - at));
      at = end + 1;
    }
    walk_strings(doc_, "", segments, 0, p);
  }
}

// Down the pointer's segments; a container of the wrong JSON type is left to
// the schema functions, which report it where they meet it.
void Validator::walk_strings(const Json& here, const std::string& path, const std::vector<std::string>& segments,
                             std::size_t k, const GltfStringProperty& p) const {
  const std::string& segment = segments[k];
  const bool last = k + 1 == segments.size();
  if (segment == "*") {
    if (!here.is_array()) return;
    for (std::size_t i = 0; i < here.size(); ++i) {
      const std::string ip = path + "/" + std::to_string(i);
      if (last)
        check_string(here[i], ip, p);
      else
        walk_strings(here[i], ip, segments, k + 1, p);
    }
    return;
  }
  if (!here.is_object()) return;
  const auto it = here.find(segment);
  if (it == here.end()) {
    if (last && p.required) fail(path, "a required " + quoted(segment) + " property (" + describe(p) + ")");
    return;
  }
  if (last)
    check_string(*it, path + "/" + segment, p);
  else
    walk_strings(*it, path + "/" + segment, segments, k + 1, p);
}

void Validator::check_string(const Json& value, const std::string& path, const GltfStringProperty& p) const {
  if (!value.is_string()) fail(path, describe(p));
  const std::string& text = value.get_ref<const std::string&>();
  if (!p.values.empty() && std::find(p.values.begin(), p.values.end(), text) == p.values.end())
    fail(path, one_of(p.values));
  if (!p.pattern.empty() && !std::regex_match(text, std::regex(p.pattern, std::regex::ECMAScript)))
    fail(path, "a string matching the pattern " + p.pattern);
}

void Validator::run() const {
  if (!doc_.is_object()) fail("", "a JSON object at the top level");
  check_strings();
  gltf(Obj(*this, doc_, ""));
}

}  // namespace

// Every property of type "string" in specification/2.0/schema/*.schema.json
// (KhronosGroup/glTF at 77b44be7) and in the schemas of the extensions this
// validator reads (KHR_lights_punctual's light.schema.json; the material and
// texture-transform extensions have none), found by following each schema's
// allOf to glTFProperty / glTFChildOfRootProperty: "type": "string", an array
// whose items are, or an anyOf of string "const"s (the enums; their trailing
// open {"type": "string"} is for future values, which this importer cannot
// read, so the known values are required, as glTF-Validator reports others).
// uri's "format": "iri-reference" is not checked beyond a string (a relative
// buffer uri must name a file: buffer()).
const std::vector<GltfStringProperty>& gltf_string_properties() {
  static const std::vector<GltfStringProperty> table = [] {
    const std::string version = "^(0|[1-9][0-9]{0,8})\\.(0|[1-9][0-9]{0,8})$";  // asset.schema.json
    std::vector<GltfStringProperty> t = {
        {"/extensionsUsed/*", false, {}, "", "glTF.schema.json"},
        {"/extensionsRequired/*", false, {}, "", "glTF.schema.json"},
        {"/asset/copyright", false, {}, "", "asset.schema.json"},
        {"/asset/generator", false, {}, "", "asset.schema.json"},
        {"/asset/version", true, {}, version, "asset.schema.json"},
        {"/asset/minVersion", false, {}, version, "asset.schema.json"},
        {"/accessors/*/type", true, {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"}, "", "accessor.schema.json"},
        {"/animations/*/channels/*/target/path", true, {"translation", "rotation", "scale", "weights"}, "",
         "animation.channel.target.schema.json"},
        {"/animations/*/samplers/*/interpolation", false, {"LINEAR", "STEP", "CUBICSPLINE"}, "",
         "animation.sampler.schema.json"},
        {"/buffers/*/uri", false, {}, "", "buffer.schema.json"},
        {"/cameras/*/type", true, {"perspective", "orthographic"}, "", "camera.schema.json"},
        {"/images/*/uri", false, {}, "", "image.schema.json"},
        {"/images/*/mimeType", false, {"image/jpeg", "image/png"}, "", "image.schema.json"},
        {"/materials/*/alphaMode", false, {"OPAQUE", "MASK", "BLEND"}, "", "material.schema.json"},
        {"/extensions/KHR_lights_punctual/lights/*/type", true, {"directional", "point", "spot"}, "",
         "KHR_lights_punctual/schema/light.schema.json"},
    };
    // "name": every object that is a child of the root (the schemas whose allOf
    // is glTFChildOfRootProperty.schema.json), KHR_lights_punctual's lights too.
    for (const char* child : {"/accessors/*", "/animations/*", "/buffers/*", "/bufferViews/*", "/cameras/*",
                              "/images/*", "/materials/*", "/meshes/*", "/nodes/*", "/samplers/*", "/scenes/*",
                              "/skins/*", "/textures/*", "/extensions/KHR_lights_punctual/lights/*"})
      t.push_back({std::string(child) + "/name", false, {}, "", "glTFChildOfRootProperty.schema.json"});
    return t;
  }();
  return table;
}

void validate_gltf_document(const nlohmann::json& document, const std::string& file, bool glb) {
  Validator(document, file, glb).run();
}

}  // namespace gi
