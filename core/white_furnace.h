// The white furnace: a white object under uniform white light reflects,
// at each view angle, its BRDF's directional albedo ∫ f(v, l) (n·l) dl.
// A convex object (a sphere) sees no other surface, so one bounce is the
// whole image, and a model that conserves energy gives exactly 1 where
// nothing is absorbed (base colour 1). Bevy judged #23442, #23737, #24243
// and #24246 by this image; it is computed here with the material code
// both renderers run (core/shared/brdf.h), by quadrature instead of a
// noisy render.
#pragma once

#include <cstdint>
#include <vector>

namespace gi {

// Directional albedo of a white material (base colour 1) under `model`, at
// n·v = nov. The specular lobe is integrated over visible normals, the
// diffuse lobe over cosine-distributed directions, each by a grid² midpoint
// rule, so narrow lobes are resolved as well as wide ones.
double white_albedo(std::uint32_t model, float perceptual_roughness, float metallic, float reflectance, float nov,
                    int grid = 64);

struct FurnaceSample {
  float perceptual_roughness = 0.0f;
  float metallic = 0.0f;
  float nov = 0.0f;
  double albedo = 0.0;
};

// Every (roughness, metallic, n·v) of the grid, in that nesting order.
std::vector<FurnaceSample> white_furnace(std::uint32_t model, const std::vector<float>& perceptual_roughness,
                                         const std::vector<float>& metallic, const std::vector<float>& nov,
                                         float reflectance, int grid = 64);

}  // namespace gi
