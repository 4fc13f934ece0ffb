// A 2D scene for the radiance-cascades pipeline: emitting and
// occluding shapes on a canvas of pixels, as a scenario's "scene": {"shapes"}
// describes them, and what its events make of it at a frame.
//
// Shapes (JSON, pixel units, y down; "emission" absent: an occluder):
//   {"name", "type": "rect",     "min": [x, y], "max": [x, y]}
//   {"name", "type": "ellipse",  "center": [x, y], "radii": [rx, ry]}
//   {"name", "type": "line",     "from": [x, y], "to": [x, y], "width": w}
//   {"name", "type": "polyline", "points": [[x, y], ...], "width": w}
// Events (the Solari ones, read in 2D): light_on / light_off / light_intensity
// / light_color on an emitting shape by name, and transform with a
// translation [dx, dy, 0] of a shape; the same rules as core/scene_events.h
// (the canvas at frame f is a pure function of the initial one and f).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/shared/rc/shapes.h"

namespace gi {

class JsonReader;
struct Scenario;

struct CanvasShape {
  std::string name;
  std::string type;                // rect, ellipse, line, polyline
  std::vector<glm::vec2> points;   // rect: min, max; ellipse: centre, radii; line, polyline: the path
  float half_width = 0.0f;         // line, polyline
  glm::vec3 emission{0.0f};        // as written
  bool emissive = false;
  // What the events make of it.
  bool on = true;
  float intensity = 1.0f;
  glm::vec3 color{1.0f};
  glm::vec2 offset{0.0f};

  glm::vec3 radiance() const { return emissive && on ? emission * intensity * color : glm::vec3(0.0f); }
};

struct Canvas {
  std::uint32_t width = 0, height = 0;
  std::vector<CanvasShape> shapes;
  const CanvasShape* find(const std::string& name) const;
  // The GPU's list: a polyline becomes one segment per edge, every shape
  // offset by its translation.
  std::vector<shader::RcShape> gpu_shapes() const;
  std::size_t emitters() const;
  // 64-bit hash of everything the image depends on (the reference's cache key).
  std::uint64_t hash() const;
  nlohmann::json to_json() const;  // the shapes as the frame sees them
};

// Parses "scene"/"shapes"; InputError at the JSON path for anything amiss.
Canvas parse_canvas(const JsonReader& r, const nlohmann::json& shapes, const std::string& path, std::uint32_t width,
                    std::uint32_t height);
// The scenario's events, checked against its canvas (at parse time): only
// the event types above, naming shapes that exist (emitting ones for lights).
void validate_canvas_events(const JsonReader& r, const Scenario& scenario, const Canvas& canvas);
// The canvas at `frame` under the scenario's events.
Canvas canvas_at_frame(const Canvas& initial, const Scenario& scenario, std::uint32_t frame);

}  // namespace gi
