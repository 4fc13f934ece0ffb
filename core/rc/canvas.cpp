#include "core/rc/canvas.h"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>
#include <xxhash.h>

#include "core/json_reader.h"
#include "core/scenario.h"

namespace gi {
namespace {

using nlohmann::json;

// Coordinates may sit off the canvas (a shape half outside it), within reason.
constexpr double kCoordinateLimit = 1e6;

glm::vec2 point(const JsonReader& r, const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 2) r.fail(path, "expected [x, y] in pixels");
  return {r.number(j[0], path + "/0", -kCoordinateLimit, kCoordinateLimit),
          r.number(j[1], path + "/1", -kCoordinateLimit, kCoordinateLimit)};
}

CanvasShape parse_shape(const JsonReader& r, const json& j, const std::string& path) {
  if (!j.is_object()) r.fail(path, "expected a shape object");
  if (!j.contains("type")) r.fail(path + "/type", "missing required key \"type\" (rect, ellipse, line or polyline)");
  CanvasShape s;
  s.type = r.one_of(j["type"], path + "/type", {"rect", "ellipse", "line", "polyline"});
  if (s.type == "rect") {
    r.object(j, path, {"name", "type", "min", "max", "emission"}, {"name", "min", "max"});
    s.points = {point(r, j["min"], path + "/min"), point(r, j["max"], path + "/max")};
    if (!(s.points[1].x > s.points[0].x && s.points[1].y > s.points[0].y))
      r.fail(path + "/max", "expected max greater than min on both axes");
  } else if (s.type == "ellipse") {
    r.object(j, path, {"name", "type", "center", "radii", "emission"}, {"name", "center", "radii"});
    s.points = {point(r, j["center"], path + "/center"), point(r, j["radii"], path + "/radii")};
    if (!(s.points[1].x > 0.0f && s.points[1].y > 0.0f)) r.fail(path + "/radii", "expected positive radii");
  } else {
    const bool line = s.type == "line";
    r.object(j, path, {"name", "type", line ? "from" : "points", line ? "to" : "points", "width", "emission"},
             {"name", line ? "from" : "points", "width"});
    if (line) {
      if (!j.contains("to")) r.fail(path + "/to", "missing required key \"to\"");
      s.points = {point(r, j["from"], path + "/from"), point(r, j["to"], path + "/to")};
    } else {
      const json& pts = r.array(j["points"], path + "/points", 2);
      for (std::size_t i = 0; i < pts.size(); ++i) s.points.push_back(point(r, pts[i], JsonReader::at(path + "/points", i)));
    }
    s.half_width = 0.5f * r.number(j["width"], path + "/width", 1e-3, kCoordinateLimit);
  }
  s.name = r.string(j["name"], path + "/name");
  if (j.contains("emission")) {
    s.emission = r.vec3(j["emission"], path + "/emission", 0.0, 1e6);
    s.emissive = true;
  }
  return s;
}

shader::RcShape gpu_shape(std::uint32_t kind, glm::vec4 geometry, glm::vec3 radiance, float half_width) {
  shader::RcShape g{};
  g.geometry = geometry;
  g.radiance = glm::vec4(radiance, half_width);
  g.info = glm::uvec4(kind, 0u, 0u, 0u);
  return g;
}

}  // namespace

const CanvasShape* Canvas::find(const std::string& name) const {
  for (const CanvasShape& s : shapes)
    if (s.name == name) return &s;
  return nullptr;
}

std::size_t Canvas::emitters() const {
  return std::size_t(std::count_if(shapes.begin(), shapes.end(), [](const CanvasShape& s) { return s.emissive; }));
}

std::vector<shader::RcShape> Canvas::gpu_shapes() const {
  std::vector<shader::RcShape> out;
  for (const CanvasShape& s : shapes) {
    const glm::vec3 L = s.radiance();
    const glm::vec2 o = s.offset;
    if (s.type == "rect") {
      out.push_back(gpu_shape(shader::RC_SHAPE_RECT, glm::vec4(s.points[0] + o, s.points[1] + o), L, 0.0f));
    } else if (s.type == "ellipse") {
      out.push_back(gpu_shape(shader::RC_SHAPE_ELLIPSE, glm::vec4(s.points[0] + o, s.points[1]), L, 0.0f));
    } else {
      for (std::size_t i = 0; i + 1 < s.points.size(); ++i)
        out.push_back(gpu_shape(shader::RC_SHAPE_SEGMENT, glm::vec4(s.points[i] + o, s.points[i + 1] + o), L,
                                s.half_width));
    }
  }
  return out;
}

std::uint64_t Canvas::hash() const {
  const std::vector<shader::RcShape> g = gpu_shapes();
  XXH64_state_t* st = XXH64_createState();
  XXH64_reset(st, 0);
  const std::uint32_t size[2] = {width, height};
  XXH64_update(st, size, sizeof(size));
  XXH64_update(st, g.data(), g.size() * sizeof(shader::RcShape));
  const std::uint64_t h = XXH64_digest(st);
  XXH64_freeState(st);
  return h;
}

json Canvas::to_json() const {
  json out = json::array();
  for (const CanvasShape& s : shapes) {
    json pts = json::array();
    for (glm::vec2 p : s.points) pts.push_back({p.x, p.y});
    const glm::vec3 L = s.radiance();
    out.push_back({{"name", s.name}, {"type", s.type}, {"points", pts}, {"offset", {s.offset.x, s.offset.y}},
                   {"radiance", {L.x, L.y, L.z}}, {"emissive", s.emissive}});
  }
  return out;
}

Canvas parse_canvas(const JsonReader& r, const json& shapes, const std::string& path, std::uint32_t width,
                    std::uint32_t height) {
  Canvas c;
  c.width = width;
  c.height = height;
  const json& a = r.array(shapes, path, 1);
  std::size_t segments = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string at = JsonReader::at(path, i);
    CanvasShape s = parse_shape(r, a[i], at);
    if (c.find(s.name)) r.fail(at + "/name", fmt::format("expected a name of its own, \"{}\" repeats", s.name));
    segments += s.type == "polyline" ? s.points.size() - 1 : 1;
    if (segments > shader::RC_MAX_SHAPES)
      r.fail(at, fmt::format("expected at most {} shapes (a polyline counts one per edge)", shader::RC_MAX_SHAPES));
    c.shapes.push_back(std::move(s));
  }
  return c;
}

void validate_canvas_events(const JsonReader& r, const Scenario& scenario, const Canvas& canvas) {
  for (const Event& e : scenario.events) {
    switch (e.type) {
      case EventType::LightOn: case EventType::LightOff: case EventType::LightIntensity: case EventType::LightColor: {
        const CanvasShape* s = canvas.find(e.light);
        if (!s || !s->emissive)
          r.fail(e.json_path + "/light", fmt::format("expected the name of an emitting shape, got \"{}\"", e.light));
        break;
      }
      case EventType::Transform: {
        if (!canvas.find(e.instance))
          r.fail(e.json_path + "/instance", fmt::format("expected the name of a shape, got \"{}\"", e.instance));
        const json& raw = scenario.raw["events"][e.index];
        if (raw.contains("rotation_degrees") || raw.contains("scale"))
          r.fail(e.json_path, "expected a translation only (a canvas shape is moved, not turned or scaled)");
        if (e.translation.z != 0.0f) r.fail(e.json_path + "/translation/2", "expected 0 (the canvas is 2D)");
        break;
      }
      default:
        r.fail(e.json_path + "/type", fmt::format("expected light_on, light_off, light_intensity, light_color or "
                                                  "transform for the radiance_cascades pipeline, got \"{}\"",
                                                  to_string(e.type)));
    }
  }
}

Canvas canvas_at_frame(const Canvas& initial, const Scenario& scenario, std::uint32_t frame) {
  Canvas c = initial;
  for (std::size_t i : event_order(scenario)) {
    const Event& e = scenario.events[i];
    if (e.first > frame) continue;
    const float t = event_progress(e, frame);
    auto shape = [&](const std::string& name) {
      return std::find_if(c.shapes.begin(), c.shapes.end(), [&](const CanvasShape& s) { return s.name == name; });
    };
    switch (e.type) {
      case EventType::LightOn: shape(e.light)->on = true; break;
      case EventType::LightOff: shape(e.light)->on = false; break;
      case EventType::LightIntensity: {
        auto s = shape(e.light);
        s->intensity += (e.scale - s->intensity) * t;
        break;
      }
      case EventType::LightColor: {
        auto s = shape(e.light);
        s->color += (e.color - s->color) * t;
        break;
      }
      case EventType::Transform: shape(e.instance)->offset += t * glm::vec2(e.translation); break;
      default: break;  // refused when the scenario was read
    }
  }
  return c;
}

}  // namespace gi
