// The geometry of 2D radiance cascades (the seed lesson,
// ../shared/seeds/radiance-cascades-lesson.txt), written once for the
// shaders (gpu/shaders/rc_*.comp) and the CPU (tests, checks, sweep).
//
// Cascade c is a grid of probes, each a width×width block of texels of the
// cascade texture, one texel per ray: width = 2^(c + resolution_factor), so
// a probe has width² rays and the probes are width texels apart. Its rays
// cover the distance interval [start, start + range) from the probe's
// centre, start = interval0·(4^c − 1)/3 and range = interval0·4^c: the
// intervals of consecutive cascades meet end to end, each four times longer.
//
// The RC headers live in core/shared/rc/, not core/shared/: the Embree
// reference's cache key hashes core/shared/*.h, and nothing here is its.
#ifndef GI_SHARED_RC_CASCADES_H
#define GI_SHARED_RC_CASCADES_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

GI_CONST uint RC_MAX_CASCADES = 16u;
GI_CONST uint RC_GROUP = 8u;  // 8×8 workgroups for every RC pass

// What rc_mipmap divides a probe's sum of width² rays by.
GI_CONST uint RC_MIPMAP_PROBE_WIDTH_X2 = 0u;  // the lesson's width·2: right only when width = 2
GI_CONST uint RC_MIPMAP_RAY_COUNT = 1u;       // width², the mean over the probe's rays

// How rc_cascade merges the coarser cascade into a ray that misses.
GI_CONST uint RC_MERGE_LESSON = 0u;        // the lesson's: the fine ray's own interval, then the four coarser
                                            // probes' radiance, bilinearly
GI_CONST uint RC_MERGE_BILINEAR_FIX = 1u;  // each of the four coarser probes is reached by a ray of its own, from
                                            // the fine interval's start to that probe's interval start

struct RcProbe {
  uint width;   // texels per probe edge; rays per probe = width²
  float start;  // where its rays begin, from the probe centre (pixels)
  float range;  // how far they march from there (pixels)
  uint cascade;
};

GI_FN RcProbe rc_probe_for_cascade(uint c, uint resolution_factor, float interval0) {
  RcProbe p;
  p.width = 1u << (c + resolution_factor);
  const float four_c = float(1u << (2u * c));
  p.start = interval0 * (four_c - 1.0f) / 3.0f;
  p.range = interval0 * four_c;
  p.cascade = c;
  return p;
}

// Ray `ray_index` of `ray_count`: the centre of its angular sector.
GI_FN vec2 rc_ray_direction(uint ray_index, uint ray_count) {
  const float angle = (float(ray_index) + 0.5f) / float(ray_count) * TWO_PI;
  return vec2(cos(angle), sin(angle));
}

// Merging: a probe of cascade c (grid cell `cell`) reads the four nearest
// probes of cascade c + 1, whose grid is half as fine. With odd = cell mod 2,
// they are cell/2 + odd + {-1, 0}², and the bilinear weight of the second
// of each pair is 0.75 − 0.5·odd: a probe centre (cell + ½)·w lies ¾ or ¼
// of the way between the coarser centres (q + ½)·2w.
GI_FN ivec2 rc_upper_probe(ivec2 cell, ivec2 corner) { return cell / 2 + (cell - (cell / 2) * 2) + corner; }
GI_FN vec2 rc_merge_weight(ivec2 cell) {
  const ivec2 odd = cell - (cell / 2) * 2;
  return vec2(0.75f) - vec2(odd) * 0.5f;
}

GI_FN float rc_mipmap_divisor(uint width, uint mode) {
  return mode == RC_MIPMAP_RAY_COUNT ? float(width * width) : float(width * 2u);
}

GI_SHADER_END

#endif
