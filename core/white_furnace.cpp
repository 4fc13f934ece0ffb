#include "core/white_furnace.h"

#include <cmath>

#include "core/shared/brdf.h"

namespace gi {

using namespace shader;

double white_albedo(std::uint32_t model, float perceptual_roughness, float metallic, float reflectance, float nov,
                    int grid) {
  const BrdfParams p = brdf_params(vec3(1.0f), metallic, perceptual_roughness, reflectance, model);
  const vec3 n(0.0f, 0.0f, 1.0f), v(std::sqrt(std::max(0.0f, 1.0f - nov * nov)), 0.0f, nov);
  double specular = 0.0, diffuse = 0.0;
  for (int i = 0; i < grid; ++i)
    for (int j = 0; j < grid; ++j) {
      const vec2 u((i + 0.5f) / grid, (j + 0.5f) / grid);
      // Specular: l = reflect(-v, h), h from the visible normals; the
      // estimate is f cos / pdf (below the horizon it reflects nothing).
      const vec3 h = sample_ggx_vndf(v, p.alpha, u);
      const vec3 l = reflect(-v, h);
      if (l.z > 0.0f) {
        // n·h as specular_lobe recomputes it from v and l, so that the two
        // D terms cancel exactly: at α = 0.001 D changes by orders of
        // magnitude within a float's rounding of n·h.
        const float noh = saturate(dot(n, normalize(v + l)));
        const float pdf = ggx_vndf_reflection_pdf(p.alpha, nov, noh);
        if (pdf > 0.0f) specular += double(luminance(specular_lobe(p, n, v, l)) * l.z / pdf);
      }
      // Diffuse: cosine-distributed l, f cos / pdf = f π.
      const vec3 ld = sample_cosine_hemisphere(u);
      diffuse += double(luminance(brdf_eval_diffuse(p, n, v, ld))) * double(PI);
    }
  return (specular + diffuse) / double(grid * grid);
}

std::vector<FurnaceSample> white_furnace(std::uint32_t model, const std::vector<float>& perceptual_roughness,
                                         const std::vector<float>& metallic, const std::vector<float>& nov,
                                         float reflectance, int grid) {
  std::vector<FurnaceSample> out;
  out.reserve(perceptual_roughness.size() * metallic.size() * nov.size());
  for (float r : perceptual_roughness)
    for (float m : metallic)
      for (float c : nov) out.push_back({r, m, c, white_albedo(model, r, m, reflectance, c, grid)});
  return out;
}

}  // namespace gi
