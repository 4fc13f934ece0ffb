// What the inspector derives from a capture beyond its buffers (the page's
// "derived" sources): the world-cache cell each pixel's surface and each GI
// reservoir's sample point queries, computed with the shaders' own maths
// (core/shared/world_cache.h: cell size, quantisation, key, checksum, probing),
// and the scene's lights by the DI reservoirs' light ids. Both need the scene
// at the captured frame, which the manifest's scenario document re-derives
// (core/scene_events.h), and the profile's world-cache settings.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/capture_data.h"

namespace gi {

struct CaptureDerivation {
  // "derived/cache_cells_projected" [h, w, 10], "derived/surface_cache_cell" [h, w, 10],
  // "derived/gi_sample_cache_cell" [c, h, w, 10]
  std::vector<CaptureBuffer> buffers;
  std::vector<std::string> buffer_notes;
  std::vector<std::string> notes;  // what could not be derived, and why
  nlohmann::json lights;           // [{kind, name, triangles}] by light id, or null
};

CaptureDerivation derive_from_capture(const CaptureData& capture);

// The row of a derived cell buffer (one query): the fields as the manifest
// writes a struct's.
nlohmann::json cache_cell_fields();
// The row of "derived/cache_cells_projected" [h, w, 10] (the world cache's
// live cells drawn onto the image): slot, checksum, life, age, cell_size,
// radiance (r g b samples), cells_here.
nlohmann::json projected_cell_fields();
inline constexpr std::uint32_t kCacheCellWords = 10;
inline constexpr std::uint32_t kNoCell = 0xFFFFFFFFu;  // key and slot of "no query here", slot of "not in the table"

}  // namespace gi
