// The pixel one spatial-reuse try looks at, for DI's and GI's spatial passes
// (restir_di.spatial_disk). SPATIAL_DISK_CLAMPED 1 is Solari's
// get_neighbor_pixel_id (v0.18.0 realtime/restir_di.wgsl:218-222,
// restir_gi.wgsl:183-187; v0.17.0 restir_di.wgsl:195-199, v0.19.0 :199-203):
// bevy_pbr's concentric disk sample (v0.18.0 crates/bevy_pbr/src/render/
// utils.wgsl:124-143) added to the pixel, clamped to the screen and truncated,
// so a try past the edge lands on the edge pixel and a try may return the
// pixel itself; every try is then judged by the surface test alone. 0 (the
// harness's earlier pick): r = radius·√u, φ uniform, rounded, and a try off
// the screen or on the pixel itself is refused (returns false).
//
// Include after core/shared/host_device.h and rng.h.

#ifndef SPATIAL_DISK_CLAMPED
#define SPATIAL_DISK_CLAMPED 0
#endif

bool spatial_neighbour_pixel(uvec2 pixel, uvec2 resolution, float radius, inout uint rng, out ivec2 q) {
#if SPATIAL_DISK_CLAMPED != 0
  vec2 ab = 2.0 * rng_next_vec2(rng) - 1.0;
  float a = ab.x;
  float b = ab.y == 0.0 ? 1.0 : ab.y;
  float r;
  float phi;
  if (a * a > b * b) {
    r = radius * a;
    phi = (PI / 4.0) * (b / a);
  } else {
    r = radius * b;
    phi = (PI / 2.0) - (PI / 4.0) * (a / b);
  }
  vec2 p = clamp(vec2(pixel) + vec2(r * cos(phi), r * sin(phi)), vec2(0.0), vec2(resolution) - 1.0);
  q = ivec2(uvec2(p));
  return true;
#else
  vec2 u = rng_next_vec2(rng);
  float r = radius * sqrt(u.x);
  float phi = TWO_PI * u.y;
  q = ivec2(pixel) + ivec2(round(vec2(r * cos(phi), r * sin(phi))));
  return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(resolution))) && q != ivec2(pixel);
#endif
}
