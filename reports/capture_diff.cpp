#include "reports/capture_diff.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/npy.h"

namespace gi {
namespace {

nlohmann::json word_value(const std::uint8_t* p, const std::string& dtype) {
  if (dtype == "<f4") {
    float f;
    std::memcpy(&f, p, 4);
    // JSON has no inf or NaN: those are named.
    if (std::isfinite(f)) return double(f);
    return std::isnan(f) ? "nan" : (f > 0 ? "inf" : "-inf");
  }
  if (dtype == "<i4") {
    std::int32_t i;
    std::memcpy(&i, p, 4);
    return i;
  }
  if (dtype == "<u8") {
    std::uint64_t u;
    std::memcpy(&u, p, 8);
    return u;
  }
  if (dtype == "|u1") return *p;
  std::uint32_t u;
  std::memcpy(&u, p, 4);
  return u;
}

// The field that holds byte `offset` of a row, and its dtype.
std::pair<std::string, std::string> field_at(const nlohmann::json& fields, std::uint32_t offset,
                                             const std::string& dtype) {
  if (fields.is_array())
    for (const nlohmann::json& f : fields) {
      const std::uint32_t o = f["offset"], n = f["count"];
      if (offset >= o && offset < o + 4 * n) {
        const std::uint32_t c = (offset - o) / 4;
        return {n == 1 ? f["name"].get<std::string>() : f["name"].get<std::string>() + "[" + std::to_string(c) + "]",
                f["dtype"]};
      }
    }
  return {"", dtype};
}

std::vector<std::uint64_t> unravel(std::uint64_t flat, const std::vector<std::uint64_t>& shape) {
  std::vector<std::uint64_t> index(shape.size());
  for (std::size_t i = shape.size(); i-- > 0;) {
    index[i] = shape[i] ? flat % shape[i] : 0;
    flat = shape[i] ? flat / shape[i] : 0;
  }
  return index;
}

// Element by element over rows of `row_bytes`.
void compare_rows(CaptureEntryDiff& d, const std::uint8_t* a, const std::uint8_t* b, std::size_t row_bytes,
                  std::size_t word_bytes, const std::vector<std::uint64_t>& element_shape, const nlohmann::json& fields,
                  const std::string& dtype) {
  d.mask.assign(d.elements, 0);
  for (std::uint64_t e = 0; e < d.elements; ++e) {
    const std::uint8_t* ra = a + e * row_bytes;
    const std::uint8_t* rb = b + e * row_bytes;
    if (std::memcmp(ra, rb, row_bytes) == 0) continue;
    d.mask[e] = 1;
    if (d.differing++ > 0) continue;
    d.first_index = unravel(e, element_shape);
    for (std::size_t w = 0; w * word_bytes < row_bytes; ++w)
      if (std::memcmp(ra + w * word_bytes, rb + w * word_bytes, word_bytes) != 0) {
        d.first_word = std::uint32_t(w);
        const auto [field, field_dtype] = field_at(fields, std::uint32_t(w * word_bytes), dtype);
        d.first_field = field;
        d.here = word_value(ra + w * word_bytes, field_dtype);
        d.there = word_value(rb + w * word_bytes, field_dtype);
        break;
      }
  }
  d.status = d.differing ? "different" : "equal";
  if (!d.differing) d.mask.clear();
}

// An entry the other capture holds and this one does not.
CaptureEntryDiff only_there(const std::string& name, const char* kind) {
  CaptureEntryDiff d;
  d.name = name;
  d.kind = kind;
  d.status = "only_there";
  return d;
}

}  // namespace

std::uint32_t buffer_row_words(const CaptureBuffer& b, std::uint32_t width, std::uint32_t height) {
  const std::size_t n = b.shape.size();
  if (n == 0) return 1;
  if (!b.fields.is_null()) return std::uint32_t(b.shape.back());
  if (n >= 2 && b.shape[n - 2] == height && b.shape[n - 1] == width) return 1;
  return n >= 2 ? std::uint32_t(b.shape.back()) : 1;
}

std::uint64_t buffer_elements(const CaptureBuffer& b, std::uint32_t width, std::uint32_t height) {
  std::uint64_t n = 1;
  for (std::uint64_t d : b.shape) n *= d;
  return n / std::max<std::uint32_t>(buffer_row_words(b, width, height), 1);
}

std::vector<std::uint64_t> buffer_element_shape(const CaptureBuffer& b, std::uint32_t width, std::uint32_t height) {
  std::vector<std::uint64_t> shape = b.shape;
  const std::size_t n = shape.size();
  const bool row_axis = n >= 1 && (!b.fields.is_null() || (n >= 2 && !(shape[n - 2] == height && shape[n - 1] == width)));
  if (row_axis) shape.pop_back();
  return shape;
}

std::uint32_t buffer_pixel_chains(const CaptureBuffer& b, std::uint32_t width, std::uint32_t height) {
  const std::vector<std::uint64_t> e = buffer_element_shape(b, width, height);
  if (e.size() == 2 && e[0] == height && e[1] == width) return 1;
  if (e.size() == 3 && e[1] == height && e[2] == width) return std::uint32_t(e[0]);
  return 0;
}

CaptureDiff diff_captures(const CaptureData& here, const CaptureData& there) {
  CaptureDiff out;
  for (const CaptureBuffer& a : here.buffers) {
    CaptureEntryDiff d;
    d.name = a.name;
    d.kind = "buffer";
    d.row_words = buffer_row_words(a, here.width, here.height);
    d.elements = buffer_elements(a, here.width, here.height);
    const CaptureBuffer* b = there.find_buffer(a.name);
    if (!b) {
      d.status = "only_here";
    } else if (b->dtype != a.dtype || b->shape != a.shape || b->bytes.size() != a.bytes.size()) {
      d.status = "shape";
    } else {
      const std::vector<std::uint64_t> element_shape = buffer_element_shape(a, here.width, here.height);
      const std::size_t word_bytes = npy_itemsize(a.dtype);
      compare_rows(d, a.bytes.data(), b->bytes.data(), word_bytes * d.row_words, word_bytes, element_shape, a.fields,
                   a.dtype);
    }
    out.entries.push_back(std::move(d));
  }
  for (const CaptureBuffer& b : there.buffers)
    if (!here.find_buffer(b.name)) out.entries.push_back(only_there(b.name, "buffer"));
  for (const CaptureLayer& a : here.layers) {
    CaptureEntryDiff d;
    d.name = a.name;
    d.kind = "layer";
    d.row_words = 3;
    d.elements = a.image.size();
    const CaptureLayer* b = there.find_layer(a.name);
    if (!b) {
      d.status = "only_here";
    } else if (b->image.width != a.image.width || b->image.height != a.image.height) {
      d.status = "shape";
    } else {
      static const nlohmann::json rgb = nlohmann::json::parse(
          R"([{"name":"R","offset":0,"dtype":"<f4","count":1},{"name":"G","offset":4,"dtype":"<f4","count":1},
              {"name":"B","offset":8,"dtype":"<f4","count":1}])");
      compare_rows(d, reinterpret_cast<const std::uint8_t*>(a.image.pixels.data()),
                   reinterpret_cast<const std::uint8_t*>(b->image.pixels.data()), 12, 4,
                   {a.image.height, a.image.width}, rgb, "<f4");
    }
    out.entries.push_back(std::move(d));
  }
  for (const CaptureLayer& b : there.layers)
    if (!here.find_layer(b.name)) out.entries.push_back(only_there(b.name, "layer"));
  for (const CaptureEntryDiff& d : out.entries)
    if (d.status != "equal") out.identical = false;
  return out;
}

CaptureDiff diff_against_baseline(const CaptureData& here, const nlohmann::json& baseline, const std::map<std::string, std::string>& here_hashes,
                                  const Image* output_half, const Image* baseline_image, const std::string& image_note) {
  CaptureDiff out;
  const nlohmann::json& hashes = baseline["hashes"]["final_buffers"];
  for (const CaptureBuffer& a : here.buffers) {
    CaptureEntryDiff d;
    d.name = a.name;
    d.kind = "buffer";
    d.by = "hash";
    d.row_words = buffer_row_words(a, here.width, here.height);
    d.elements = buffer_elements(a, here.width, here.height);
    const auto mine = here_hashes.find(a.name);
    if (!hashes.contains(a.name)) {
      d.status = "only_here";
    } else {
      d.here = mine == here_hashes.end() ? nlohmann::json() : nlohmann::json(mine->second);
      d.there = hashes[a.name];
      d.status = d.here == d.there ? "equal" : "different";
    }
    out.entries.push_back(std::move(d));
  }
  for (const auto& [name, hash] : hashes.items())
    if (!here.find_buffer(name)) {
      CaptureEntryDiff d;
      d.name = name;
      d.kind = "buffer";
      d.by = "hash";
      d.status = "only_there";
      d.there = hash;
      out.entries.push_back(std::move(d));
    }
  if (baseline_image && output_half) {
    CaptureEntryDiff d;
    d.name = "output";
    d.kind = "layer";
    d.row_words = 3;
    d.elements = output_half->size();
    if (baseline_image->width != output_half->width || baseline_image->height != output_half->height) {
      d.status = "shape";
    } else {
      static const nlohmann::json rgb = nlohmann::json::parse(
          R"([{"name":"R","offset":0,"dtype":"<f4","count":1},{"name":"G","offset":4,"dtype":"<f4","count":1},
              {"name":"B","offset":8,"dtype":"<f4","count":1}])");
      compare_rows(d, reinterpret_cast<const std::uint8_t*>(output_half->pixels.data()),
                   reinterpret_cast<const std::uint8_t*>(baseline_image->pixels.data()), 12, 4,
                   {output_half->height, output_half->width}, rgb, "<f4");
    }
    out.entries.push_back(std::move(d));
  } else if (!image_note.empty()) {
    out.notes.push_back(image_note);
  }
  for (const CaptureEntryDiff& d : out.entries)
    if (d.status != "equal") out.identical = false;
  return out;
}

}  // namespace gi
