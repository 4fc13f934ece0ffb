// The capture inspector's page (giharness inspect, docs/commands/inspect.md):
// one self-contained HTML file, as the nightly's pages are (reports/html_page.h:
// opens offline, no server). Every image layer and every buffer of the
// capture is embedded as its raw little-endian bytes, zlib-deflated and
// base64-encoded, which the page inflates on first use
// (DecompressionStream('deflate')); the output's PNG preview is embedded as
// an image. The page script (reports/inspect_script.cpp) draws any layer or
// buffer field in false colour or tone-mapped, decodes a clicked pixel in
// every buffer by the fields the manifest names, and shows the comparison
// with another capture. The fragment opens it at a place:
//   #pixel=x,y        decode that pixel once loaded (what the browser test clicks)
//   #source=NAME      the view's source (a layer or buffer name)
//   #region=x0,y0,x1,y1   outline a check's region (inclusive pixels); a region
//                     the page was written with (the nightly's failing check) is outlined without it
//   #all              draw every thumbnail at once (else as scrolled to)
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/capture_data.h"
#include "reports/capture_diff.h"

namespace gi {

extern const char* const kInspectScript;

struct InspectPageInputs {
  const CaptureData* capture = nullptr;
  // Buffers the inspector derived from the capture (the world-cache cell of
  // each pixel's surface and of its GI sample), shown like the capture's own
  // with their note; group "derived".
  std::vector<CaptureBuffer> derived;
  std::vector<std::string> derived_notes;
  nlohmann::json lights;  // [{kind, name, triangles}] by light id, or null
  std::vector<std::string> notes;  // said at the top of the page (what could not be derived, and why)
  const CaptureData* against = nullptr;  // with `diff`: another capture
  const CaptureDiff* diff = nullptr;     // against `against`, or against a baseline (`against_label`)
  std::string against_label;             // what the comparison is against (a folder or a baseline file)
  // Images beside the capture's layers, each an image-sized source the view
  // draws and a clicked pixel reads: "reference/output" (Embree), "baseline/output".
  struct ExtraLayer {
    std::string name, group, note;
    const Image* image = nullptr;
  };
  std::vector<ExtraLayer> extra_layers;
  // A check's region: [x0, y0, x1, y1] inclusive pixels, or null; and its
  // mask, one byte a pixel (1 inside), empty for none. The page outlines it.
  nlohmann::json region;
  std::vector<std::uint8_t> region_mask;
};

std::string inspect_page(const InspectPageInputs& in);

// zlib's deflate of `bytes` (RFC 1950, what DecompressionStream('deflate') reads).
std::string deflate_bytes(const void* bytes, std::size_t size);

}  // namespace gi
