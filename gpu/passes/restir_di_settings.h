// The realtime DI passes' compile-time settings (from the profile, docs/design.md §3
// steps 4 and 6) and the buffers they share. Each setting becomes a #define,
// so a scenario compiles only the variant it uses.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "gpu/compute_pass.h"
#include "gpu/shader_compiler.h"

namespace gi::gpu {

// Filled by the profile table (gpu/profile_keys.cpp): a profile-filled field
// has no value of its own here (value-initialised; every value is the
// profile's). The run's own fields (background, chains,
// specular_handover_alpha) keep theirs.
struct DiSettings {
  std::uint32_t tile_count{};
  std::uint32_t samples_per_tile{};  // after sizing to the scene
  float exposure{};
  bool log2_radiance{};              // false: plain rgb9e5 (0.17)
  std::uint32_t initial_samples{};
  float confidence_cap{};
  float spatial_radius{};
  std::uint32_t spatial_tries{};
  float plane_tolerance{};
  float normal_min_dot{};
  bool balance_mis{};                // false: constant MIS (0.17)
  // true (restir_di.mis_visibility, Bevy main): visibility in both cross MIS
  // targets of every merge (two more rays per merge), defensive balance MIS
  // in the spatial merge; replaces balance_mis's weights.
  bool mis_visibility{};
  // restir_di.temporal_mis_scene "previous_frame" (Bevy f755ea4a71 #25046):
  // with mis_visibility, the temporal merge asks whether this frame's sample
  // lit the history's surface in last frame's scene (the renderer keeps its
  // TLAS; TRACE_PREVIOUS_SCENE); false ("current"): in this frame's.
  bool mis_previous_scene{};
  bool traces_previous_scene() const { return mis_visibility && mis_previous_scene; }
  // true (restir_di.target = base_over_pi, Solari): the resampling target is
  // luminance(L·cos·base/π); false: base·(1 − metallic)/π (pure metals: no DI).
  bool target_base_color{};
  // true (restir_di.temporal_permutation, 0.18): the reprojected pixel is
  // permuted within 4×4 blocks, falling back to point reprojection when the
  // permuted pixel gives no valid reservoir; false: point reprojection only.
  bool temporal_permutation{};
  // restir_di.temporal_fallback "point" (0.18): with permutation, the
  // point-reprojected pixel when the permuted one fails; "none" (0.19): no
  // second try.
  bool temporal_fallback{};
  // restir_di.offscreen_reprojection "own_pixel" (0.19, DI and GI): a pixel
  // whose surface was off screen last frame starts temporal reuse from
  // itself; "none" (0.17, 0.18): it takes no history.
  bool offscreen_own_pixel{};
  // true (restir_di.tile_choice = workgroup, Solari): one light tile per 8×8
  // workgroup, the same every frame; false: a random tile per pixel and frame.
  bool tile_per_workgroup{};
  bool visibility_final{};           // false: spatial ray fed forward (0.17)
  // restir_di.visibility "final_stored" (Bevy f94997ca37 #21649 to
  // f860ee784b #22033): the final ray zeroes the stored reservoir's W, which
  // the next frame's temporal and spatial reuse read (needs visibility_final).
  bool visibility_final_stored{};
  // restir_di.emissive_exposure "unexposed" (0.17): Bevy multiplied DI by the
  // view's exposure and then added the emissive, so emitters were 1/exposure
  // too bright against the rest (light_tiles.exposure stands for the view's).
  bool emissive_unexposed{};
  // light_tiles.sun_sampling "center" (0.17): every light sample takes the
  // sun's centre direction (hard shadows); false: its cone (0.18 on).
  bool sun_center{};
  // restir_di.background "clear_color" (0.18 on): the scene's background
  // radiance where the camera ray misses; false ("black", 0.17): black there.
  bool show_background{};
  // restir_di.spatial_search "halving" (Bevy d1095b0efb #22617, removed again
  // by #23968 before v0.19.0): each refused spatial try halves the disk's
  // radius; false ("fixed", every release): the full disk every try.
  bool spatial_radius_halving{};
  // restir_di.spatial_disk "concentric_clamped" (Solari, DI and GI): a spatial
  // try is a concentric disk sample clamped to the screen, so it may land on
  // an edge pixel or the pixel itself; false: polar, rounded, refused off the
  // screen or on itself (gpu/shaders/spatial_neighbour.glsl).
  bool spatial_disk_clamped{};
  glm::vec3 background{0.0f};  // Scene::background
  // true: the initial winner's shadow ray zeroes its W and that W is stored
  // and reused (0.17 and 0.18 as released); false: the ray is not traced and
  // only the final shading ray tests visibility (README, "DI bias").
  bool initial_visibility_fed_forward{};
  // restir_di.reuse_radiance "scene" (Bevy, every release): the reused
  // samples' targets and the shaded radiance re-resolve the light from the
  // scene in full precision, only the initial candidates read the tile
  // encoding; false ("tile_encoding", the harness's earlier model): every DI
  // evaluation sees the tile encoding.
  bool reuse_radiance_scene{};
  std::uint32_t chains = 1;               // independent DI chains (2: an honest noise estimate)
  // specular.di_handover_alpha (Solari 0.18+): at alpha ≤ this DI shades the
  // diffuse lobe only and specular GI takes the specular lobe, first-hit
  // emission included. Negative: never (DI shades the full BRDF everywhere).
  // Set only when specular GI runs: a DI-only run keeps the full BRDF.
  float specular_handover_alpha = -1.0f;
  // restir_di.shading "base_over_pi" (0.17): the sample is shaded with
  // base_color/π whatever the metallic, no specular lobe; false ("brdf"): the
  // full BRDF (with the handover above).
  bool shading_base_over_pi{};
  // light_tiles.seeding "scrolling" (Bevy 0.17-0.19, fixed on main by
  // #24670): a tile's pool is seeded by tile + frame, so tile t at frame f
  // draws exactly what tile t + 1 drew at frame f − 1; false ("independent"):
  // every tile and frame draws afresh.
  bool tile_seed_scrolling{};

  std::vector<ShaderDefine> defines() const;
};

class Buffer;

struct DiBuffers {
  const Buffer* gbuffer = nullptr;
  const Buffer* tile_samples = nullptr;
  const Buffer* tile_packed = nullptr;
  const Buffer* stored = nullptr;
  const Buffer* mid = nullptr;
  const Buffer* surfaces = nullptr;
  const Buffer* translation = nullptr;
  const Buffer* output = nullptr;
  const Buffer* accumulation = nullptr;
};

}  // namespace gi::gpu
