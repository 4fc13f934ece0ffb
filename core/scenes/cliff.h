// A procedural cliff (docs/design.md §7, §8): a closed rock slab whose front face is
// carved by fractal value noise and horizontal strata. Closed on purpose: with
// meshoptimizer 0.18 only the topological border can be locked, and a closed
// mesh has no border but the groups' own, so its cluster DAG can simplify down
// to one cluster. Deterministic: the same options give the same bits.
//
// The triangle count is a target: the slab is a grid of near-square cells of
// one size on all six faces, sized so the total is within a few percent of it.
#pragma once
#include <cstdint>

#include "core/scene.h"

namespace gi {

struct CliffOptions {
  std::uint32_t triangles = 20000;  // target, 12 .. 16 M
  std::uint32_t seed = 1;
  float width = 40.0f;   // x, metres
  float height = 20.0f;  // y
  float depth = 8.0f;    // z
};

inline constexpr std::uint32_t kCliffMaxTriangles = 16'000'000;

Mesh make_cliff_mesh(const CliffOptions& options);
Material make_cliff_material();
// One instance "cliff" (material "rock") standing on y = 0, a directional
// light "sun", the camera in front of the carved face.
Scene make_cliff_scene(const CliffOptions& options);

}  // namespace gi
