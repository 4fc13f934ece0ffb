// Watertight ray-triangle intersection (Woop, Benthin, Wald: "Watertight
// Ray/Triangle Intersection", JCGT 2013) and a conservative ray-box slab test,
// compiled as GLSL by the `bvh` backend and as C++ by its CPU twin and tests.
//
// Why watertight: a plain Möller-Trumbore test in the compute BVH missed 2
// grazing rays in 57 600 through shared edges (docs/design.md §4). Woop's test shears
// the triangle into ray space, so an edge shared by two triangles gets the
// same (negated) edge function in both and no ray slips between them.
//
// `GI_PRECISE` forbids fused multiply-adds in GLSL (`precise`): contraction
// would round the two triangles' edge functions differently and reopen the
// cracks; the C++ build (no -mfma) never contracts.
#ifndef GI_SHARED_WATERTIGHT_H
#define GI_SHARED_WATERTIGHT_H
#include "host_device.h"

#ifdef __cplusplus
#define GI_PRECISE
#else
#define GI_PRECISE precise
#endif

GI_SHADER_BEGIN

// Per-ray constants of the shear (kz: the dominant axis of the direction,
// kx/ky the other two, swapped when dir[kz] < 0 to keep the winding) as one
// matrix: shear * (p - origin) = (p[kx] - sx p[kz], p[ky] - sy p[kz], sz p[kz]).
// Its other entries are exactly 0 or 1, so the products and sums they add are
// exact and the result rounds as Woop's explicit formula does; the matrix
// only avoids per-triangle dynamic vector indexing, which GPU compilers (and
// lavapipe's SIMD lanes) handle slowly.
struct WatertightRay {
  vec3 origin;
  mat3 shear;
};

GI_FN vec3 unit_axis(int k) { return vec3(k == 0 ? 1.0f : 0.0f, k == 1 ? 1.0f : 0.0f, k == 2 ? 1.0f : 0.0f); }

GI_FN WatertightRay watertight_ray(vec3 origin, vec3 dir) {
  vec3 a = abs(dir);
  int kz = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  if (dir[kz] < 0.0f) {
    int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  float sx = dir[kx] / dir[kz];
  float sy = dir[ky] / dir[kz];
  float sz = 1.0f / dir[kz];
  // Rows (kx - sx kz), (ky - sy kz), (sz kz); mat3 takes columns, so transpose.
  vec3 row_x = unit_axis(kx) - sx * unit_axis(kz);
  vec3 row_y = unit_axis(ky) - sy * unit_axis(kz);
  vec3 row_z = sz * unit_axis(kz);
  WatertightRay r;
  r.origin = origin;
  r.shear = transpose(mat3(row_x, row_y, row_z));
  return r;
}

// Two-sided. On a hit with 0 < t < tmax returns true with t and the
// barycentrics (u, v) of p1 and p2 (the ray-query / Embree convention).
GI_FN bool watertight_triangle(WatertightRay r, vec3 p0, vec3 p1, vec3 p2, float tmax, OUT(float) t,
                               OUT(vec2) bary) {
  GI_PRECISE vec3 a = r.shear * (p0 - r.origin);
  GI_PRECISE vec3 b = r.shear * (p1 - r.origin);
  GI_PRECISE vec3 c = r.shear * (p2 - r.origin);
  GI_PRECISE float u = c.x * b.y - c.y * b.x;
  GI_PRECISE float v = a.x * c.y - a.y * c.x;
  GI_PRECISE float w = b.x * a.y - b.y * a.x;
  t = 0.0f;
  bary = vec2(0.0f);
  if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
  GI_PRECISE float det = u + v + w;
  if (det == 0.0f) return false;
  GI_PRECISE float tt = u * a.z + v * b.z + w * c.z;
  float rcp = 1.0f / det;
  float th = tt * rcp;
  if (!(th > 0.0f && th < tmax)) return false;
  t = th;
  bary = vec2(v * rcp, w * rcp);
  return true;
}

// 1/dir with zero components replaced by a huge finite value of the same
// sign, so slab products never form 0 * inf = NaN.
GI_FN float safe_inverse(float d) { return abs(d) > 1e-20f ? 1.0f / d : (d >= 0.0f ? 1e20f : -1e20f); }
GI_FN vec3 safe_inverse_direction(vec3 dir) {
  return vec3(safe_inverse(dir.x), safe_inverse(dir.y), safe_inverse(dir.z));
}

// Slab test of [bmin, bmax] against [0, tmax]. The far distance is scaled by
// 1 + 2 gamma(3) (Ize 2013, as in PBRT) so rounding never culls a box that
// the watertight triangle test would hit. tnear: entry distance on a hit.
GI_FN bool ray_box(vec3 bmin, vec3 bmax, vec3 origin, vec3 inv_dir, float tmax, OUT(float) tnear) {
  vec3 t0 = (bmin - origin) * inv_dir;
  vec3 t1 = (bmax - origin) * inv_dir;
  vec3 tn = min(t0, t1);
  vec3 tf = max(t0, t1);
  float near = max(max(tn.x, tn.y), max(tn.z, 0.0f));
  float far = min(min(tf.x, tf.y), tf.z) * 1.0000004f;
  tnear = near;
  return near <= min(far, tmax);
}

GI_SHADER_END

#endif
