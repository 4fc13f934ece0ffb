// The split-sum scale and bias table (F_ab) that the BRDF_LAYERED material
// model reads (core/shared/dfg_lut.h), baked here from the shared GGX maths.
// Bevy 0.19 samples a 64×64 R16G16 table of the same integral, baked by
// Monte Carlo (bevy_pbr environment_map/dfg.ktx2, #23737); this bake uses the
// same grid and precision with a deterministic midpoint rule instead, so the
// table is reproducible to the bit and its error is quadrature, not noise.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace gi {

struct DfgLutBake {
  std::uint32_t size = 64;             // texels per side: NdotV across, perceptual roughness down
  std::uint32_t samples_per_axis = 64;  // midpoint rule on the VNDF's unit square
};

// Texel (x, y) at NdotV = (x + 0.5) / size and perceptual roughness
// (y + 0.5) / size, packed as packHalf2x16(A, B) with
// A = ∫ (1 − (1 − v·h)⁵) f cos, B = ∫ (1 − v·h)⁵ f cos (f: the GGX lobe with F = 1),
// each clipped below at 1e-6 as Bevy's table is. Row-major, y outer.
std::vector<std::uint32_t> bake_dfg_lut(const DfgLutBake& bake = {});

// core/shared/dfg_lut.h's text for a baked table.
std::string dfg_lut_header(const std::vector<std::uint32_t>& texels, const DfgLutBake& bake = {});

}  // namespace gi
