// The shapes of a 2D radiance-cascades canvas (core/rc/canvas.h) as the
// GPU reads them, and their signed distance functions: the analytic
// distance pass (gpu/shaders/rc_distance.comp), the scene raster
// (rc_scene.comp), the CPU reference's inside tests and the JFA test all
// call these. Pixel (x, y) covers [x, x + 1) × [y, y + 1); y grows down.
#ifndef GI_SHARED_RC_SHAPES_H
#define GI_SHARED_RC_SHAPES_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

GI_CONST uint RC_SHAPE_RECT = 0u;     // geometry: min x, min y, max x, max y
GI_CONST uint RC_SHAPE_ELLIPSE = 1u;  // geometry: centre x, y, radius x, y
GI_CONST uint RC_SHAPE_SEGMENT = 2u;  // geometry: x0, y0, x1, y1; half_width: the stroke's half width
GI_CONST uint RC_MAX_SHAPES = 256u;

struct RcShape {
  vec4 geometry;
  vec4 radiance;  // rgb: emitted radiance (0: an occluder); w: the stroke's half width (segments)
  uvec4 info;     // x: kind; yzw: unused
};

GI_FN float rc_sdf_rect(vec2 p, vec4 g) {
  const vec2 centre = 0.5f * (vec2(g.x, g.y) + vec2(g.z, g.w));
  const vec2 half_size = 0.5f * (vec2(g.z, g.w) - vec2(g.x, g.y));
  const vec2 d = abs(p - centre) - half_size;
  return length(max(d, vec2(0.0f))) + min(max(d.x, d.y), 0.0f);
}

// The exact distance to an ellipse: the closest point e(t) = (a cos t,
// b sin t) in the first quadrant by Newton's method on the angle. Inside,
// the sign is right and the magnitude need not be (the passes keep max(d, 0)).
GI_FN float rc_sdf_ellipse(vec2 p, vec4 g) {
  const vec2 q = abs(p - vec2(g.x, g.y));
  const float a = g.z, b = g.w;
  const float k = (q.x / a) * (q.x / a) + (q.y / b) * (q.y / b);
  if (a == b) return length(q) - a;
  float t = atan(a * q.y, b * q.x);
  for (int i = 0; i < 8; ++i) {
    const float c = cos(t), s = sin(t);
    const float f = (a * a - b * b) * c * s - q.x * a * s + q.y * b * c;
    const float df = (a * a - b * b) * (c * c - s * s) - q.x * a * c - q.y * b * s;
    if (df == 0.0f) break;
    t = clamp(t - f / df, 0.0f, 0.5f * PI);
  }
  const float d = length(q - vec2(a * cos(t), b * sin(t)));
  return k < 1.0f ? -d : d;
}

GI_FN float rc_sdf_segment(vec2 p, vec4 g, float half_width) {
  const vec2 a = vec2(g.x, g.y), ba = vec2(g.z, g.w) - a, pa = p - a;
  const float len2 = dot(ba, ba);
  const float h = len2 > 0.0f ? clamp(dot(pa, ba) / len2, 0.0f, 1.0f) : 0.0f;
  return length(pa - ba * h) - half_width;
}

GI_FN float rc_sdf(vec2 p, RcShape s) {
  if (s.info.x == RC_SHAPE_RECT) return rc_sdf_rect(p, s.geometry);
  if (s.info.x == RC_SHAPE_ELLIPSE) return rc_sdf_ellipse(p, s.geometry);
  return rc_sdf_segment(p, s.geometry, s.radiance.w);
}

GI_SHADER_END

#endif
