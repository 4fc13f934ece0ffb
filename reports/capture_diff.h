// Two captures compared buffer by buffer and layer by layer, bit for bit
// (the inspector's --against): equal or different, how many elements differ
// (an element is a buffer's innermost row: one texel's reservoir, one
// cache cell; a layer's pixel), a mask of the differing ones for the page's
// difference image, and the first differing element with its values.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/capture_data.h"

namespace gi {

struct CaptureEntryDiff {
  std::string name;
  std::string kind;    // "buffer" or "layer"
  // "elements" (compared element by element) or "hash" (against a baseline:
  // equal or different by the hash of the bytes; `here` and `there` hold the hashes).
  std::string by = "elements";
  std::string status;  // "equal", "different", "shape" (dtype or shape differ), "only_here", "only_there"
  std::uint64_t elements = 0, differing = 0;
  std::uint32_t row_words = 1;  // words (components) of one element
  // The first differing element: its index into the buffer's shape without
  // the row axis, its first differing word, the field that word belongs to
  // (or "" for a raw buffer) and both values as numbers.
  std::vector<std::uint64_t> first_index;
  std::uint32_t first_word = 0;
  std::string first_field;
  nlohmann::json here, there;
  std::vector<std::uint8_t> mask;  // one byte per element, 1 where it differs ("different" only)
};

struct CaptureDiff {
  bool identical = true;
  std::vector<CaptureEntryDiff> entries;
  std::vector<std::string> notes;  // what could not be compared, and why
};

CaptureDiff diff_captures(const CaptureData& here, const CaptureData& there);

// A capture against a baseline (reports/baselines/<class>/<scenario>.json): each buffer equal or different by hash
// (`here_hashes`: the capture's buffers' hashes in the scheme the baseline
// names, by name), and the output layer element by element against
// `baseline_image` (the baseline's final image, half floats), null when the
// capture is not of the last frame (then `image_note` says so). `output_half`:
// the capture's output rounded to half floats, as the baseline stores it.
CaptureDiff diff_against_baseline(const CaptureData& here, const nlohmann::json& baseline, const std::map<std::string, std::string>& here_hashes,
                                  const Image* output_half, const Image* baseline_image, const std::string& image_note);

// A buffer's elements and words per element: a struct's row (the last axis of
// a buffer with fields), else the last axis of two or more unless the buffer
// ends in the image's height and width (gbuffer/depth [h, w]: one word a
// pixel), else one word.
std::uint32_t buffer_row_words(const CaptureBuffer& b, std::uint32_t width, std::uint32_t height);
std::uint64_t buffer_elements(const CaptureBuffer& b, std::uint32_t width, std::uint32_t height);
// The shape of the elements (the buffer's without the row axis), and the
// chains when the elements are the image's pixels ([h, w] or [chains, h, w]),
// else 0.
std::vector<std::uint64_t> buffer_element_shape(const CaptureBuffer& b, std::uint32_t width, std::uint32_t height);
std::uint32_t buffer_pixel_chains(const CaptureBuffer& b, std::uint32_t width, std::uint32_t height);

}  // namespace gi
