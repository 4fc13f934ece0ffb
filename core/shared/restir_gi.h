// ReSTIR GI's maths (docs/design.md §3 step 7), shared by the GPU passes
// (gpu/shaders/gi_*.comp) and the CPU unit tests (host_device.h rules): the
// reservoir, the reconnection jacobian, permutation sampling, the pairwise
// merge with jacobians in the balance heuristic, and the statistics the
// `jacobian` and `finite` checks read.
//
// A GI sample is a point on a surface seen from the pixel (position, normal)
// and the radiance it sends back; reusing it at another pixel reconnects to
// the same point, so densities change by the solid-angle jacobian.
#ifndef GI_SHARED_RESTIR_GI_H
#define GI_SHARED_RESTIR_GI_H
#include "host_device.h"
#include "reservoir.h"

GI_SHADER_BEGIN

// Random streams (added to the chain index), distinct from DI's.
GI_CONST uint RNG_DOMAIN_GI_INITIAL = 0x2545F491u;
GI_CONST uint RNG_DOMAIN_GI_SPATIAL = 0x9E3779B1u;
GI_CONST uint RNG_DOMAIN_GI_PERMUTATION = 0x632BE5ABu;
GI_CONST uint RNG_DOMAIN_SPECULAR = 0x4CF5AD43u;

// 48 bytes, whole vec4s (std430 == C++).
struct GiReservoir {
  vec4 sample_position;   // xyz the reconnection point, w M (confidence weight)
  vec4 sample_normal;     // xyz its normal (restir_gi.sample_normal: the hit's shading normal, or its face normal facing the pixel that found it)
  vec4 radiance;          // rgb radiance the point sends back, a W (0: empty)
};

GI_FN GiReservoir empty_gi_reservoir(float confidence) {
  GiReservoir r;
  r.sample_position = vec4(0.0f, 0.0f, 0.0f, confidence);
  r.sample_normal = vec4(0.0f, 0.0f, 1.0f, 0.0f);
  r.radiance = vec4(0.0f);
  return r;
}

GI_FN bool gi_reservoir_valid(GiReservoir r) { return r.radiance.w > 0.0f; }
GI_FN float gi_confidence(GiReservoir r) { return r.sample_position.w; }

// The resampling target at a surface (position p, shading normal n): the
// luminance of the sample's radiance times the cosine at p. The caller
// weighs the radiance with the surface's colour (Solari: base colour / π;
// gi_common.glsl gi_target_colour), so the target carries no lobe shape and
// the same reservoir serves diffuse shading and rough specular (docs/design.md §3 step 8).
GI_FN float gi_target(vec3 radiance, vec3 sample_position, vec3 p, vec3 n) {
  vec3 d = sample_position - p;
  float len2 = dot(d, d);
  if (!(len2 > 0.0f)) return 0.0f;
  return luminance(radiance) * max(dot(d * inversesqrt(len2), n), 0.0f);
}

// The reconnection jacobian (docs/design.md §3 step 7): moving the sample's origin
// from orig_pos to new_pos, with sample point s and its normal n_s,
//   J = (saturate(dot(r/|r|, n_s)) · |q|²) / (saturate(dot(q/|q|, n_s)) · |r|²),
//   r = new_pos − s, q = orig_pos − s.
// Raw: may be inf or NaN (a grazing original direction, coincident points).
GI_FN float gi_jacobian_raw(vec3 new_pos, vec3 orig_pos, vec3 sample_pos, vec3 sample_normal) {
  vec3 r = new_pos - sample_pos;
  vec3 q = orig_pos - sample_pos;
  float r2 = dot(r, r);
  float q2 = dot(q, q);
  float cos_r = saturate(dot(r * inversesqrt(r2), sample_normal));
  float cos_q = saturate(dot(q * inversesqrt(q2), sample_normal));
  return (cos_r * q2) / (cos_q * r2);
}

// Solari's sanitised form: J = isinf(J) || isnan(J) ? 0 : J.
// (|x| ≤ FLT_MAX is false for NaN and inf, in both languages, without isinf/isnan overloads.)
GI_FN bool gi_finite(float x) { return abs(x) <= 3.40282347e38f; }
GI_FN float gi_jacobian(vec3 new_pos, vec3 orig_pos, vec3 sample_pos, vec3 sample_normal) {
  float j = gi_jacobian_raw(new_pos, orig_pos, sample_pos, sample_normal);
  return gi_finite(j) ? j : 0.0f;
}

// Permutation sampling for temporal reuse (docs/design.md §3 step 7): a per-frame
// random r permutes the reprojected pixel within aligned 4×4 blocks,
//   offset = (r & 3, (r >> 2) & 3),  p = ((p + offset) ^ 3) − offset,
// then clamps to the image. Decorrelates neighbouring pixels' histories.
GI_FN ivec2 gi_permute_pixel(ivec2 p, uint r, ivec2 resolution) {
  ivec2 offset = ivec2(int(r & 3u), int((r >> 2u) & 3u));
  ivec2 q = ((p + offset) ^ ivec2(3)) - offset;
  return clamp(q, ivec2(0), resolution - ivec2(1));
}

// Everything a pairwise merge of canonical c with other o needs (targets at
// both surfaces, and the jacobians of moving each sample to the other pixel).
struct GiMergeInputs {
  float pc_xc;  // p_c(x_c)
  float po_xc;  // p_o(x_c)
  float po_xo;  // p_o(x_o)
  float pc_xo;  // p_c(x_o)
  float j_oc;   // jacobian of reusing c's sample at o
  float j_co;   // jacobian of reusing o's sample at c
};

struct GiMergeResult {
  GiReservoir merged;
  bool selected_other;
};

// Pairwise merge with jacobians in the balance heuristic (docs/design.md §3 step 7):
//   mis_c = balance(c.M·p_c(x_c), o.M·p_o(x_c)·J_oc),  mis_o = balance(o.M·p_o(x_o), c.M·p_c(x_o)·J_co)
//   w_c = mis_c·p_c(x_c)·c.W,  w_o = mis_o·p_c(x_o)·o.W·J_co
//   pick o with probability w_o/(w_c + w_o);  M = c.M + o.M;  W = (w_c + w_o)/p_c(x_sel).
// Rejection of o (J above the threshold) is the caller's: it skips the merge.
GI_FN GiMergeResult merge_gi_reservoirs(GiReservoir c, GiReservoir o, GiMergeInputs t, float u) {
  float cm = gi_confidence(c);
  float om = gi_confidence(o);
  float mis_c = balance_mis(cm * t.pc_xc, om * t.po_xc * t.j_oc);
  float mis_o = balance_mis(om * t.po_xo, cm * t.pc_xo * t.j_co);
  float w_c = gi_reservoir_valid(c) ? mis_c * t.pc_xc * c.radiance.w : 0.0f;
  float w_o = gi_reservoir_valid(o) ? mis_o * t.pc_xo * o.radiance.w * t.j_co : 0.0f;
  float sum = w_c + w_o;
  GiMergeResult m;
  m.selected_other = sum > 0.0f && u * sum < w_o;
  m.merged = m.selected_other ? o : c;
  float target = m.selected_other ? t.pc_xo : t.pc_xc;
  m.merged.radiance.w = (sum > 0.0f && target > 0.0f) ? sum / target : 0.0f;
  m.merged.sample_position.w = cm + om;
  return m;
}

// Per-frame statistics (integer atomics, so they are the same at any thread
// count): read by the `jacobian` and `finite` checks. 40 words.
GI_CONST uint GI_JACOBIAN_HISTOGRAM_BINS = 32u;
GI_CONST int GI_JACOBIAN_HISTOGRAM_MIN_LOG2 = -16;  // bin 0: J < 2^-15 (and J = 0); bin 31: J ≥ 2^15

struct GiStats {
  uint merges;                // neighbours (temporal and spatial) with a sample, offered for a merge
  uint rejections;            // of those, refused for J above the threshold
  uint max_accepted_j_bits;   // floatBitsToUint of the largest accepted J (non-negative: order-preserving)
  uint nonfinite_jacobians;   // raw J that was inf or NaN (sanitised to 0)
  uint nonfinite_reservoirs;  // stored reservoirs with a non-finite W or radiance
  uint nonfinite_output;      // output pixels (GI or specular) with a non-finite value
  uint temporal_edge_pixels;  // GI_TEMPORAL_EDGE_STATS: chain A's edge pixels with an on-screen history
  uint temporal_edge_reused;  // of those, the pixels whose temporal reuse found a usable history
  uint histogram[32];         // log2(J) of accepted merges, one bin per power of two
};

// Path counters (GI_PATH_COUNTERS, compiled in only for a check that reads
// them: ray_budget, spatial_acceptance), chain A only, integer atomics. A
// buffer of its own, so a run without them hashes the same state as before.
struct GiCounters {
  uint specular_paths;     // pixels that traced a glossy path
  uint specular_segments;  // closest-hit rays those paths traced (shadow rays not counted)
  uint spatial_pixels;     // pixels that looked for a spatial neighbour
  uint spatial_found;      // of those, the pixels that found one (a similar surface in the disk)
};

GI_FN uint gi_jacobian_bin(float j) {
  if (!(j > 0.0f)) return 0u;
  int b = int(floor(log2(j))) - GI_JACOBIAN_HISTOGRAM_MIN_LOG2;
  return uint(clamp(b, 0, int(GI_JACOBIAN_HISTOGRAM_BINS) - 1));
}

GI_FN bool gi_reservoir_finite(GiReservoir r) {
  return gi_finite(r.radiance.x) && gi_finite(r.radiance.y) && gi_finite(r.radiance.z) && gi_finite(r.radiance.w) &&
         gi_finite(r.sample_position.w);
}

GI_SHADER_END

#endif
