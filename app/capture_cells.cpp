#include "app/capture_cells.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <exception>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/profile.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "core/scene_events.h"
#include "core/scene_flatten.h"
#include "core/shared/world_cache.h"
#include "gpu/realtime_settings.h"

namespace gi {
namespace {

using shader::uvec3;
using shader::vec3;

struct CacheTable {
  const std::uint32_t* checksums = nullptr;
  const std::uint32_t* life = nullptr;
  const float* radiance = nullptr;            // 4 a cell
  const std::uint32_t* root_frame = nullptr;  // may be absent (instrumentation)
  std::uint32_t cells = 0;
};

template <class T>
const T* words(const CaptureBuffer* b) {
  return b ? reinterpret_cast<const T*>(b->bytes.data()) : nullptr;
}

// One query as world_cache_query does it (gpu/shaders/world_cache_query.glsl)
// for the floor LOD, no jitter: the cell size at the camera, the quantised
// point and normal, key and checksum, then the probe sequence up to the
// first slot holding the checksum (found) or empty (a new cell: not in the table).
void query(std::uint32_t* row, vec3 p, vec3 n, vec3 eye, const gpu::WorldCacheSettings& s, const CacheTable& t,
           std::uint32_t frame) {
  const float size = shader::world_cache_cell_size(p, eye, s.cell_size_base, s.lod_scale);
  const uvec3 qp = shader::world_cache_quantize_position(p, size);
  const uvec3 qn = shader::world_cache_quantize_normal(n, s.normal_key_scale);
  const std::uint32_t key = shader::world_cache_key(qp, qn, t.cells);
  const std::uint32_t checksum = shader::world_cache_checksum(qp, qn);
  std::uint32_t slot = kNoCell;
  for (std::uint32_t i = 0, k = key; i < s.max_probe_steps; ++i) {
    if (t.checksums[k] == checksum) {
      slot = k;
      break;
    }
    if (t.checksums[k] == shader::WORLD_CACHE_EMPTY_CELL) break;
    k = shader::world_cache_next_key(k, t.cells, s.linear_probing);
  }
  row[0] = key;
  row[1] = slot;
  row[2] = checksum;
  row[3] = slot == kNoCell ? 0u : t.life[slot];
  row[4] = slot == kNoCell || !t.root_frame ? kNoCell : shader::world_cache_age(frame, t.root_frame[slot]);
  std::memcpy(&row[5], &size, 4);
  for (int c = 0; c < 4; ++c) {
    const float r = slot == kNoCell ? 0.0f : t.radiance[4 * std::size_t(slot) + c];
    std::memcpy(&row[6 + c], &r, 4);
  }
}

void no_query(std::uint32_t* row) {
  std::memset(row, 0, kCacheCellWords * 4);
  row[0] = row[1] = row[4] = kNoCell;
}

CaptureBuffer cell_buffer(const std::string& name, std::vector<std::uint64_t> shape) {
  CaptureBuffer b;
  b.name = name;
  b.dtype = "<u4";
  shape.push_back(kCacheCellWords);
  b.shape = shape;
  b.layout = "cache cell query (app/capture_cells.h)";
  b.fields = cache_cell_fields();
  std::uint64_t n = 1;
  for (std::uint64_t d : shape) n *= d;
  b.bytes.assign(n * 4, 0);
  return b;
}

// Where world point p lands in the camera's image, pixel centres at +0.5 (the
// inverse of camera_ray_direction, core/shared/scene_types.h), and its
// distance along the view axis in units of |forward|; false behind the camera.
bool project(const GpuCamera& c, vec3 p, std::uint32_t w, std::uint32_t h, float& px, float& py, float& depth) {
  const vec3 d = p - vec3(c.position), f = vec3(c.forward), r = vec3(c.right), u = vec3(c.up);
  depth = shader::dot(d, f) / shader::dot(f, f);
  if (!(depth > 0.0f)) return false;
  px = (shader::dot(d, r) / (depth * shader::dot(r, r)) + 1.0f) * 0.5f * float(w);
  py = (-shader::dot(d, u) / (depth * shader::dot(u, u)) + 1.0f) * 0.5f * float(h);
  return true;
}

// Every live cell of the table drawn onto the image: the cell's position
// (world_cache/geometry) through the capture's camera as a disc of the cell's
// projected size (at least a pixel, at most kMaxSplat), nearest cell in
// front, hidden where the G-buffer's surface is nearer than the cell by more
// than its size (a cell behind a wall is not drawn through it). Each pixel
// holds the cell drawn there and how many cells landed on it.
constexpr float kMaxSplat = 16.0f;
CaptureBuffer project_cells(const CaptureData& c, const CacheTable& t, const float* geometry, const float* texels,
                            std::size_t texel_stride, const GpuCamera& camera, vec3 eye,
                            const gpu::WorldCacheSettings& s, std::uint32_t& drawn) {
  CaptureBuffer b;
  b.name = "derived/cache_cells_projected";
  b.dtype = "<u4";
  b.shape = {c.height, c.width, kCacheCellWords};
  b.layout = "projected cache cell (app/capture_cells.h)";
  b.fields = projected_cell_fields();
  const std::size_t pixels = std::size_t(c.width) * c.height;
  b.bytes.assign(pixels * kCacheCellWords * 4, 0);
  auto* rows = reinterpret_cast<std::uint32_t*>(b.bytes.data());
  std::vector<float> nearest(pixels, std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < pixels; ++i) rows[i * kCacheCellWords] = kNoCell;
  drawn = 0;
  for (std::uint32_t slot = 0; slot < t.cells; ++slot) {
    if (t.checksums[slot] == shader::WORLD_CACHE_EMPTY_CELL || t.life[slot] == 0) continue;
    const vec3 p(geometry[8 * std::size_t(slot)], geometry[8 * std::size_t(slot) + 1], geometry[8 * std::size_t(slot) + 2]);
    float x, y, depth;
    if (!project(camera, p, c.width, c.height, x, y, depth)) continue;
    const float size = shader::world_cache_cell_size(p, eye, s.cell_size_base, s.lod_scale);
    const float distance = shader::length(p - eye);
    // Pixels a cell's width covers at its distance: the image spans 2·|up|·depth·|forward| vertically.
    const float radius = std::clamp(0.5f * size * float(c.height) /
                                        (2.0f * shader::length(vec3(camera.up)) * depth * shader::length(vec3(camera.forward))),
                                    0.5f, kMaxSplat);
    const int x0 = int(std::floor(x - radius)), x1 = int(std::ceil(x + radius));
    const int y0 = int(std::floor(y - radius)), y1 = int(std::ceil(y + radius));
    bool any = false;
    for (int py = std::max(y0, 0); py <= std::min(y1, int(c.height) - 1); ++py)
      for (int px = std::max(x0, 0); px <= std::min(x1, int(c.width) - 1); ++px) {
        const float dx = float(px) + 0.5f - x, dy = float(py) + 0.5f - y;
        if (dx * dx + dy * dy > radius * radius) continue;
        const std::size_t i = std::size_t(py) * c.width + px;
        if (texels) {
          const float* g = texels + i * texel_stride;
          if (g[7] > 0.0f && shader::length(vec3(g[0], g[1], g[2]) - eye) + 1.5f * size < distance) continue;
        }
        std::uint32_t* row = rows + i * kCacheCellWords;
        row[9] += 1;
        any = true;
        if (!(distance < nearest[i])) continue;
        nearest[i] = distance;
        row[0] = slot;
        row[1] = t.checksums[slot];
        row[2] = t.life[slot];
        row[3] = t.root_frame ? shader::world_cache_age(c.frame, t.root_frame[slot]) : kNoCell;
        std::memcpy(&row[4], &size, 4);
        for (int k = 0; k < 4; ++k) std::memcpy(&row[5 + k], &t.radiance[4 * std::size_t(slot) + k], 4);
      }
    drawn += any ? 1 : 0;
  }
  return b;
}

}  // namespace

nlohmann::json projected_cell_fields() {
  return nlohmann::json::parse(R"([
    {"name": "slot", "offset": 0, "dtype": "<u4", "count": 1, "labels": ""},
    {"name": "checksum", "offset": 4, "dtype": "<u4", "count": 1, "labels": ""},
    {"name": "life", "offset": 8, "dtype": "<u4", "count": 1, "labels": ""},
    {"name": "age", "offset": 12, "dtype": "<u4", "count": 1, "labels": ""},
    {"name": "cell_size", "offset": 16, "dtype": "<f4", "count": 1, "labels": ""},
    {"name": "radiance", "offset": 20, "dtype": "<f4", "count": 4, "labels": "r g b samples"},
    {"name": "cells_here", "offset": 36, "dtype": "<u4", "count": 1, "labels": ""}])");
}

nlohmann::json cache_cell_fields() {
  return nlohmann::json::parse(R"([
    {"name": "key", "offset": 0, "dtype": "<u4", "count": 1, "labels": ""},
    {"name": "slot", "offset": 4, "dtype": "<u4", "count": 1, "labels": ""},
    {"name": "checksum", "offset": 8, "dtype": "<u4", "count": 1, "labels": ""},
    {"name": "life", "offset": 12, "dtype": "<u4", "count": 1, "labels": ""},
    {"name": "age", "offset": 16, "dtype": "<u4", "count": 1, "labels": ""},
    {"name": "cell_size", "offset": 20, "dtype": "<f4", "count": 1, "labels": ""},
    {"name": "radiance", "offset": 24, "dtype": "<f4", "count": 4, "labels": "r g b samples"}])");
}

CaptureDerivation derive_from_capture(const CaptureData& c) {
  CaptureDerivation out;
  const nlohmann::json& m = c.manifest;
  Scenario scenario;
  Scene scene;
  try {
    scenario = parse_scenario(m["scenario"]["document"], m["scenario"].value("file", std::string("manifest.json")));
    scene = scene_at_frame(build_scene(scenario), scenario, c.frame);
  } catch (const std::exception& e) {
    out.notes.push_back(fmt::format("The scene at frame {} could not be re-derived from the manifest's scenario ({}): "
                                    "no lights and no cache cells.", c.frame, e.what()));
    return out;
  }
  const FlatInstances flat = flatten_instances(scene, flatten_geometry(scene));
  out.lights = nlohmann::json::array();
  std::uint32_t directional = 0;
  for (const GpuLight& l : flat.lights) {
    if (l.kind == shader::LIGHT_KIND_DIRECTIONAL) {
      const std::string name = directional < scene.directional_lights.size()
                                   ? scene.directional_lights[directional].name : "";
      ++directional;
      out.lights.push_back({{"kind", "directional"}, {"name", name}, {"triangles", 0}});
    } else {
      out.lights.push_back({{"kind", "emissive mesh"},
                            {"name", l.instance < scene.instances.size() ? scene.instances[l.instance].name : ""},
                            {"triangles", l.triangle_count}});
    }
  }

  const CaptureBuffer* checksums = c.find_buffer("world_cache/checksums");
  const CaptureBuffer* texels = c.find_buffer("gbuffer/texels");
  if (!checksums || !c.find_buffer("world_cache/life") || !c.find_buffer("world_cache/radiance")) {
    out.notes.push_back("The capture holds no world cache (a run without restir_gi.hit_radiance world_cache): no cells.");
    return out;
  }
  gpu::WorldCacheSettings s;
  try {
    std::optional<std::string> profile;
    if (m.contains("profile_option") && m["profile_option"].is_string()) profile = m["profile_option"].get<std::string>();
    s = world_cache_settings_from_profile(resolve_profile(scenario, profile, m.value("sets", std::vector<std::string>{})));
  } catch (const std::exception& e) {
    out.notes.push_back(fmt::format("The profile could not be resolved ({}): no cache cells.", e.what()));
    return out;
  }
  // A 0.19 query draws its cell size and jitter from the querier's random
  // stream, which the capture does not hold: the cell is not determined by
  // the capture alone.
  if (s.stochastic_lod || s.jitter) {
    out.notes.push_back("This profile's cache queries draw their LOD (world_cache.stochastic_lod) or jitter "
                        "(world_cache.jitter) from the querying pixel's random numbers, which a capture does not hold: "
                        "the cell a pixel or a GI sample queried cannot be derived, so none is shown.");
    return out;
  }
  CacheTable t;
  t.checksums = words<std::uint32_t>(checksums);
  t.life = words<std::uint32_t>(c.find_buffer("world_cache/life"));
  t.radiance = words<float>(c.find_buffer("world_cache/radiance"));
  t.root_frame = words<std::uint32_t>(c.find_buffer("world_cache/root_frame"));
  t.cells = std::uint32_t(checksums->shape.at(0));
  const vec3 eye = vec3(make_gpu_camera(scene.camera, c.width, c.height).position);
  const std::size_t pixels = std::size_t(c.width) * c.height;

  if (const CaptureBuffer* geometry = c.find_buffer("world_cache/geometry");
      geometry && geometry->shape.size() == 2 && geometry->shape[0] == t.cells && geometry->shape[1] == 8) {
    std::uint32_t drawn = 0;
    out.buffers.push_back(project_cells(c, t, words<float>(geometry), words<float>(texels),
                                        texels ? texels->shape.back() : 0, make_gpu_camera(scene.camera, c.width, c.height),
                                        eye, s, drawn));
    out.buffer_notes.push_back(fmt::format(
        "The world cache as a picture: each live cell (life > 0) of the table at its position through this frame's "
        "camera, a disc of its size, the nearest in front and none behind the G-buffer's surface; {} cells drawn. "
        "Pick the field: life, radiance (rgb) or its samples component; slot 4294967295: no cell here.", drawn));
  }
  if (texels) {
    CaptureBuffer b = cell_buffer("derived/surface_cache_cell", {c.height, c.width});
    auto* rows = reinterpret_cast<std::uint32_t*>(b.bytes.data());
    const auto* g = words<float>(texels);
    const std::size_t stride = texels->shape.back();
    for (std::size_t i = 0; i < pixels; ++i) {
      const float* x = g + i * stride;  // GBufferTexel: position_depth, geometric_normal, ...
      if (!(x[7] > 0.0f)) {
        no_query(rows + i * kCacheCellWords);
        continue;
      }
      const vec3 p(x[0], x[1], x[2]);
      vec3 n(x[4], x[5], x[6]);
      // The cache view's normal: the geometric normal turned to face the camera.
      if (shader::dot(p - eye, n) >= 0.0f) n = -n;
      query(rows + i * kCacheCellWords, p, n, eye, s, t, c.frame);
    }
    out.buffers.push_back(std::move(b));
    out.buffer_notes.push_back(
        "The cell a pixel-rooted query at this pixel's surface (G-buffer position, geometric normal facing the camera) "
        "finds at this frame's camera, as the cache view queries it; slot 4294967295: not in the table (a query there "
        "inserts it at the commit).");
  }
  if (const CaptureBuffer* gi = c.find_buffer("gi/stored_reservoirs")) {
    const std::uint32_t chains = std::uint32_t(gi->shape.at(0));
    CaptureBuffer b = cell_buffer("derived/gi_sample_cache_cell", {chains, c.height, c.width});
    auto* rows = reinterpret_cast<std::uint32_t*>(b.bytes.data());
    const auto* r = words<float>(gi);
    for (std::size_t i = 0; i < chains * pixels; ++i) {
      const float* x = r + i * 12;  // GiReservoir: sample_position (w M), sample_normal, radiance (w W)
      if (!(x[11] > 0.0f)) {
        no_query(rows + i * kCacheCellWords);
        continue;
      }
      query(rows + i * kCacheCellWords, vec3(x[0], x[1], x[2]), vec3(x[4], x[5], x[6]), eye, s, t, c.frame);
    }
    out.buffers.push_back(std::move(b));
    std::string note =
        "The cell a query at the stored GI reservoir's sample point (its normal) finds at this frame's camera: the "
        "cell the sample's hit looked up when it was found at this camera (a moved camera gives another LOD). key "
        "4294967295: an empty reservoir.";
    if (s.first_bounce_leak_rule)
      note += " This profile's first-bounce rule queries a base cell for rays shorter than their cell; the ray's "
              "length is not stored, so a short ray's cell may differ.";
    out.buffer_notes.push_back(note);
  }
  return out;
}

}  // namespace gi
