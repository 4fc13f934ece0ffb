#include "reports/inspect_page.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>
#include <zlib.h>

#include "core/npy.h"
#include "reports/html_page.h"

namespace gi {

std::string deflate_bytes(const void* bytes, std::size_t size) {
  uLongf bound = compressBound(uLong(size));
  std::string out(bound, '\0');
  // Level 1: a 1080p capture's hundreds of MB deflate in seconds, and what
  // costs the page its load time is the base64 text, not the last few percent.
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &bound, static_cast<const Bytef*>(bytes), uLong(size), 1) != Z_OK)
    throw std::runtime_error("zlib compress2 failed");
  out.resize(bound);
  return out;
}

namespace {

// The page's embedded arrays, each in chunks of whole elements of about
// kChunkBytes, deflated apiece: a clicked pixel inflates only the chunk that
// holds it in each buffer, not a 1080p G-buffer's 200 MB.
constexpr std::size_t kChunkBytes = std::size_t(1) << 20;

// Each chunk's bytes may be regrouped by byte plane before deflating: all
// first bytes of its words, then all second bytes, and so on, for words of 4
// bytes or of a whole element (one texel's struct). A struct array's fields
// then sit in planes of like values (a normal's exponent bytes, a material
// id), which deflate finds and interleaved they hide: on a 480x270 capture the
// G-buffer texels deflate to 57 % and the surfaces to 60 % of their size
// unshuffled, while the GI reservoirs deflate best as they are. The writer
// keeps whichever of the three is smallest, per chunk. Lossless: the page
// puts the bytes back after inflating, so every value a click reads is the
// capture's bit for bit.
std::string shuffled(const std::uint8_t* bytes, std::size_t n, std::size_t word) {
  std::string out(n, '\0');
  const std::size_t words = n / word;
  for (std::size_t w = 0; w < words; ++w)
    for (std::size_t b = 0; b < word; ++b) out[b * words + w] = char(bytes[w * word + b]);
  for (std::size_t i = words * word; i < n; ++i) out[i] = char(bytes[i]);
  return out;
}

class Blobs {
 public:
  // `word_bytes`: the size of the array's words (1: bytes, never regrouped).
  nlohmann::json add(const void* bytes, std::size_t size, std::size_t element_bytes = 4, std::size_t word_bytes = 4) {
    const std::size_t e = std::max<std::size_t>(element_bytes, 1);
    const std::size_t chunk = std::max<std::size_t>(kChunkBytes / e, 1) * e;
    std::vector<std::size_t> planes{1};
    if (word_bytes > 1 && e % word_bytes == 0) planes.push_back(word_bytes);
    if (e > word_bytes && word_bytes > 1 && e % word_bytes == 0) planes.push_back(e);
    nlohmann::json ids = nlohmann::json::array(), shuffles = nlohmann::json::array();
    for (std::size_t at = 0; at < size || at == 0; at += chunk) {
      const std::size_t n = std::min(chunk, size - at);
      const std::uint8_t* p = static_cast<const std::uint8_t*>(bytes) + at;
      std::string best;
      std::size_t best_word = 1;
      for (const std::size_t word : planes) {
        const std::string d = word == 1 ? deflate_bytes(p, n) : [&] {
          const std::string s = shuffled(p, n, word);
          return deflate_bytes(s.data(), n);
        }();
        if (best.empty() || d.size() < best.size()) best = d, best_word = word;
      }
      html_ += fmt::format("<script type=\"text/plain\" id=\"blob-{}\">{}</script>\n", count_, base64(best));
      ids.push_back(count_++);
      shuffles.push_back(best_word);
      if (size == 0) break;
    }
    return {{"chunks", ids}, {"chunk_bytes", chunk}, {"bytes", size}, {"shuffle", shuffles}};
  }
  const std::string& html() const { return html_; }

 private:
  std::string html_;
  int count_ = 0;
};

nlohmann::json buffer_meta(const CaptureBuffer& b, std::uint32_t w, std::uint32_t h, Blobs& blobs,
                           const std::string& group, const std::string& note) {
  nlohmann::json m = {{"name", b.name},
                      {"dtype", b.dtype},
                      {"shape", b.shape},
                      {"layout", b.layout},
                      {"fields", b.fields},
                      {"row_words", buffer_row_words(b, w, h)},
                      {"elements", buffer_elements(b, w, h)},
                      {"group", group},
                      {"note", note}};
  const std::uint32_t chains = buffer_pixel_chains(b, w, h);
  m["pixels"] = chains ? nlohmann::json{{"chains", chains}} : nlohmann::json();
  m["blob"] = blobs.add(b.bytes.data(), b.bytes.size(), npy_itemsize(b.dtype) * buffer_row_words(b, w, h),
                        npy_itemsize(b.dtype));
  return m;
}

nlohmann::json layer_meta(const Image& image, Blobs& blobs, const std::string& name, const std::string& group,
                          const std::string& note = "") {
  return {{"name", name},
          {"group", group},
          {"note", note},
          {"blob", blobs.add(image.pixels.data(), image.pixels.size() * sizeof(glm::vec3), sizeof(glm::vec3))}};
}

// JSON inside <script>: "</" would end the element.
std::string script_json(const nlohmann::json& j) {
  std::string s = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '<' && i + 1 < s.size() && s[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += s[i];
    }
  }
  return out;
}

}  // namespace

std::string inspect_page(const InspectPageInputs& in) {
  const CaptureData& c = *in.capture;
  Blobs blobs;
  nlohmann::json meta;
  meta["width"] = c.width;
  meta["height"] = c.height;
  meta["frame"] = c.frame;
  meta["dir"] = c.dir.string();
  meta["layers"] = nlohmann::json::array();
  for (const CaptureLayer& l : c.layers) meta["layers"].push_back(layer_meta(l.image, blobs, l.name, "layer"));
  for (const InspectPageInputs::ExtraLayer& l : in.extra_layers)
    if (l.image && l.image->width == c.width && l.image->height == c.height)
      meta["layers"].push_back(layer_meta(*l.image, blobs, l.name, l.group, l.note));
  meta["buffers"] = nlohmann::json::array();
  for (const CaptureBuffer& b : c.buffers) meta["buffers"].push_back(buffer_meta(b, c.width, c.height, blobs, "buffer", ""));
  for (std::size_t i = 0; i < in.derived.size(); ++i)
    meta["buffers"].push_back(buffer_meta(in.derived[i], c.width, c.height, blobs, "derived",
                                          i < in.derived_notes.size() ? in.derived_notes[i] : ""));
  meta["lights"] = in.lights;
  meta["region"] = in.region;
  if (!in.region_mask.empty() && in.region_mask.size() == std::size_t(c.width) * c.height)
    meta["region_mask"] = blobs.add(in.region_mask.data(), in.region_mask.size(), 1, 1);
  if (in.diff) {
    nlohmann::json a = {{"dir", in.against ? in.against->dir.string() : in.against_label},
                        {"identical", in.diff->identical},
                        {"notes", in.diff->notes},
                        {"baseline", !in.against}};
    a["entries"] = nlohmann::json::array();
    for (const CaptureEntryDiff& d : in.diff->entries) {
      nlohmann::json e = {{"name", d.name},           {"kind", d.kind},          {"status", d.status}, {"by", d.by},
                          {"elements", d.elements},   {"differing", d.differing}, {"first_index", d.first_index},
                          {"first_word", d.first_word}, {"first_field", d.first_field}, {"here", d.here},
                          {"there", d.there}};
      if (!d.mask.empty()) e["mask_blob"] = blobs.add(d.mask.data(), d.mask.size(), 1, 1);
      a["entries"].push_back(e);
    }
    meta["against"] = a;
    // The other capture's output, so a pixel shows its value there too.
    if (const CaptureLayer* o = in.against ? in.against->find_layer("output") : nullptr;
        o && o->image.width == c.width && o->image.height == c.height)
      meta["layers"].push_back(layer_meta(o->image, blobs, "against/output", "against"));
  }

  const nlohmann::json& m = c.manifest;
  const std::string scenario = m.contains("scenario") ? m["scenario"].value("name", std::string("?")) : "?";
  const std::string title = fmt::format("inspect: {} frame {}", scenario, c.frame);
  std::string body = R"(<style>
#view { image-rendering: pixelated; width: min(100%, 960px); border: 1px solid #999; cursor: crosshair; }
canvas.thumb, canvas.diff { width: 192px; image-rendering: pixelated; border: 1px solid #999; }
#gallery, .diffs { display: flex; flex-wrap: wrap; gap: 8px; } #gallery figure { margin: 0; cursor: pointer; }
#gallery figcaption, figcaption { font-size: 11px; color: #555; max-width: 192px; overflow-wrap: anywhere; }
#pixel td { font-family: monospace; font-size: 12px; } tr.explain td { color: #135e13; }
</style>
)";
  body += fmt::format("<h1>{}</h1>\n", html_escape(title));
  body += fmt::format("<p class=\"small\">capture <code>{}</code>, {}×{}, profile {}, seed {}</p>\n", html_escape(c.dir.string()),
                      c.width, c.height, html_escape(m.value("profile", std::string("?"))),
                      m.contains("seed") ? m["seed"].dump() : "?");
  for (const std::string& n : in.notes) body += "<p class=\"note\">" + html_escape(n) + "</p>\n";
  const std::filesystem::path preview = c.dir / "images.png";
  body += "<div class=\"triplet\"><figure>" + html_image_file(preview, "output preview") +
          "<figcaption>images.png (the run's preview)</figcaption></figure></div>\n";
  body += "<p class=\"small\" id=\"status\">loading…</p>\n";
  body += "<h2>View</h2><div id=\"controls\"></div><p class=\"small\" id=\"layout-note\"></p>"
          "<canvas id=\"view\"></canvas><p class=\"small\" id=\"range-note\"></p>\n"
          "<p class=\"small\">Click a pixel: its value in every layer and buffer, decoded by the manifest's fields.</p>\n";
  if (!in.extra_layers.empty() && in.extra_layers.front().group == "reference")
    body += "<h2>Output and reference</h2><div class=\"diffs\" id=\"beside\"></div>\n";
  body += "<section id=\"pixel\"></section>\n<section id=\"diff\"></section>\n";
  body += "<h2>Every layer and buffer</h2><div id=\"gallery\"></div>\n";
  body += "<script type=\"application/json\" id=\"meta\">" + script_json(meta) + "</script>\n";
  body += blobs.html();
  body += std::string("<script>") + kInspectScript + "</script>\n";
  return html_page(title, body);
}

}  // namespace gi
