// ReSTIR reservoirs and their merging (docs/design.md §3 step 6), shared by the GPU DI
// passes and the CPU unit tests (host_device.h rules). The functions here see
// only numbers — target-function values and random numbers — so a test can
// drive them with a known distribution; the DI passes supply the values.
//
// Terms (Wyman et al., "A Gentle Introduction to ReSTIR", 2023):
// - p_c(x): the target function of the pixel doing the merge (canonical), p_o(x)
//   that of the pixel a reused reservoir came from;
// - W: unbiased contribution weight, so f(x)·W estimates ∫f;
// - M: confidence weight.
#ifndef GI_SHARED_RESERVOIR_H
#define GI_SHARED_RESERVOIR_H
#include "host_device.h"

GI_SHADER_BEGIN

// A light sample as the light tiles draw it: which light, which triangle of an
// emissive mesh, and the seed of the point on it (or of the direction in a
// directional light's cone). Resolving it against the scene gives the point.
struct LightSample {
  uint light_id;
  uint triangle_id;
  uint seed;
  uint valid;  // 0: empty reservoir
};

// 32 bytes, whole vec4s (std430 == C++).
struct DiReservoir {
  LightSample light;
  float confidence_weight;            // M
  float unbiased_contribution_weight; // W
  float pad0;
  float pad1;
};

GI_FN DiReservoir empty_di_reservoir() {
  DiReservoir r;
  r.light.light_id = 0u;
  r.light.triangle_id = 0u;
  r.light.seed = 0u;
  r.light.valid = 0u;
  r.confidence_weight = 0.0f;
  r.unbiased_contribution_weight = 0.0f;
  r.pad0 = 0.0f;
  r.pad1 = 0.0f;
  return r;
}

GI_FN bool di_reservoir_valid(DiReservoir r) { return r.light.valid != 0u; }

// balance(f, g) = f / (f + g), written so that f = 0 gives 0 and g = inf
// gives 0 (Bevy 0.18's form: max(0, 1 / (1 + g/f))).
GI_FN float balance_mis(float f, float g) {
  if (f == 0.0f) return 0.0f;
  return max(0.0f, 1.0f / (1.0f + g / f));
}

// Streaming RIS over candidates drawn from a source pdf: each candidate's
// resampling weight is mis · p̂(x) / pdf(x) (mis = 1/N for N candidates, the
// constant weights Solari uses for initial sampling). update() returns true
// when the candidate becomes the selected one.
struct RisStream {
  float weight_sum;
  float selected_target;
};

GI_FN RisStream ris_begin() {
  RisStream s;
  s.weight_sum = 0.0f;
  s.selected_target = 0.0f;
  return s;
}

GI_FN bool ris_update(INOUT(RisStream) s, float resampling_weight, float target, float u) {
  if (!(resampling_weight > 0.0f)) return false;
  s.weight_sum += resampling_weight;
  if (u * s.weight_sum < resampling_weight) {
    s.selected_target = target;
    return true;
  }
  return false;
}

// W of the selected candidate: Σw / p̂(x_sel), 0 when nothing was selected.
GI_FN float ris_contribution_weight(RisStream s) {
  return s.selected_target > 0.0f ? s.weight_sum / s.selected_target : 0.0f;
}

// The four target values a pairwise merge of canonical c with other o needs.
struct MergeTargets {
  float pc_xc;  // p_c(x_c)
  float po_xc;  // p_o(x_c): c's sample under o's target
  float po_xo;  // p_o(x_o)
  float pc_xo;  // p_c(x_o): o's sample under c's target
};

struct MergeResult {
  DiReservoir merged;
  bool selected_other;
  float selected_target;  // p_c(x_sel)
};

// Resampling of a pairwise merge once the MIS weights are known: w_c =
// mis_c·p_c(x_c)·c.W, w_o = mis_o·p_c(x_o)·o.W, pick o with probability
// w_o/(w_c + w_o) (u in [0, 1)), M = c.M + o.M, W = (w_c + w_o)/p_c(x_sel).
GI_FN MergeResult merge_di_reservoirs_weighted(DiReservoir c, DiReservoir o, MergeTargets t, float mis_c, float mis_o,
                                               float u) {
  float w_c = di_reservoir_valid(c) ? mis_c * t.pc_xc * c.unbiased_contribution_weight : 0.0f;
  float w_o = di_reservoir_valid(o) ? mis_o * t.pc_xo * o.unbiased_contribution_weight : 0.0f;
  float sum = w_c + w_o;

  MergeResult r;
  r.selected_other = sum > 0.0f && u * sum < w_o;
  r.merged = r.selected_other ? o : c;
  r.selected_target = r.selected_other ? t.pc_xo : t.pc_xc;
  // An empty reservoir still counts its confidence: it stands for sampling
  // attempts that found nothing.
  r.merged.confidence_weight = c.confidence_weight + o.confidence_weight;
  r.merged.unbiased_contribution_weight = r.selected_target > 0.0f ? sum / r.selected_target : 0.0f;
  if (!(sum > 0.0f)) {
    // Nothing to carry but the confidence: an empty sample with W = 0.
    r.merged.unbiased_contribution_weight = 0.0f;
  }
  return r;
}

// Pairwise merge (docs/design.md §3 step 6). balance = true: the balance heuristic
// with confidence weights (Solari 0.18)
//   mis_c = balance(c.M·p_c(x_c), o.M·p_o(x_c)),  mis_o = balance(o.M·p_o(x_o), c.M·p_c(x_o));
// false: constant weights mis_c = c.M/(c.M+o.M), mis_o = o.M/(c.M+o.M) (0.17).
// Then merge_di_reservoirs_weighted.
GI_FN MergeResult merge_di_reservoirs(DiReservoir c, DiReservoir o, MergeTargets t, bool balance, float u) {
  float cm = c.confidence_weight;
  float om = o.confidence_weight;
  float mis_c;
  float mis_o;
  if (balance) {
    mis_c = balance_mis(cm * t.pc_xc, om * t.po_xc);
    mis_o = balance_mis(om * t.po_xo, cm * t.pc_xo);
  } else {
    float total = cm + om;
    mis_c = total > 0.0f ? cm / total : 0.0f;
    mis_o = total > 0.0f ? om / total : 0.0f;
  }
  return merge_di_reservoirs_weighted(c, o, t, mis_c, mis_o, u);
}

// Bevy main's merge (realtime/restir.wesl, merge_reservoirs): the caller puts
// visibility into the two cross targets (p_o(x_c)·V_o(x_c), p_c(x_o)·V_c(x_o)),
// so a sample the other pixel cannot see takes no MIS share there; with
// defensive = true (spatial reuse) the balance weights are mixed with the
// canonical's confidence share t = c.M/(c.M+o.M):
//   mis_c = t + (1−t)·balance(c.M·p_c(x_c), o.M·p_o(x_c)),
//   mis_o = (1−t)·balance(o.M·p_o(x_o), c.M·p_c(x_o)),
// which still sum to one over the two techniques for any sample.
GI_FN MergeResult merge_di_reservoirs_defensive(DiReservoir c, DiReservoir o, MergeTargets t, bool defensive,
                                                float u) {
  float cm = c.confidence_weight;
  float om = o.confidence_weight;
  float total = cm + om;
  float share = defensive ? (total > 0.0f ? cm / total : 1.0f) : 0.0f;
  float mis_c = mix(balance_mis(cm * t.pc_xc, om * t.po_xc), 1.0f, share);
  float mis_o = mix(balance_mis(om * t.po_xo, cm * t.pc_xo), 0.0f, share);
  return merge_di_reservoirs_weighted(c, o, t, mis_c, mis_o, u);
}

GI_SHADER_END

#endif
