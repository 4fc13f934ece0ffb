#include "core/scenes/cliff.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/shared/rng.h"

namespace gi {
namespace {

std::uint32_t hash3(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t seed) {
  std::uint32_t h = seed * 0x9E3779B9u;
  for (std::uint32_t v : {std::uint32_t(x), std::uint32_t(y), std::uint32_t(z)}) {
    h ^= v + 0x7F4A7C15u + (h << 6) + (h >> 2);
    h = gi::shader::pcg_hash(h);
  }
  return h;
}

// Value noise in [0, 1], smooth trilinear.
float value_noise(glm::vec3 p, std::uint32_t seed) {
  const glm::vec3 f = glm::floor(p);
  const glm::ivec3 i(f);
  glm::vec3 t = p - f;
  t = t * t * (3.0f - 2.0f * t);
  float c[2][2][2];
  for (int dx = 0; dx < 2; ++dx)
    for (int dy = 0; dy < 2; ++dy)
      for (int dz = 0; dz < 2; ++dz)
        c[dx][dy][dz] = float(hash3(i.x + dx, i.y + dy, i.z + dz, seed) >> 8) / float(1u << 24);
  auto lerp = [](float a, float b, float u) { return a + (b - a) * u; };
  const float x00 = lerp(c[0][0][0], c[1][0][0], t.x), x10 = lerp(c[0][1][0], c[1][1][0], t.x);
  const float x01 = lerp(c[0][0][1], c[1][0][1], t.x), x11 = lerp(c[0][1][1], c[1][1][1], t.x);
  return lerp(lerp(x00, x10, t.y), lerp(x01, x11, t.y), t.z);
}

float fbm(glm::vec3 p, std::uint32_t seed) {
  float sum = 0.0f, amp = 0.5f;
  for (int o = 0; o < 5; ++o) {
    sum += amp * (value_noise(p, seed + 101u * o) - 0.5f);
    p *= 2.03f;
    amp *= 0.5f;
  }
  return sum;  // about [-0.5, 0.5]
}

// Displacement of a point of the undisplaced slab: a continuous function of
// position, so vertices shared by two faces move together and the mesh stays closed.
glm::vec3 displaced(glm::vec3 p, const CliffOptions& o) {
  const float front = glm::clamp(p.z / (0.5f * o.depth), 0.0f, 1.0f);  // 0 at the back half, 1 at the front face
  const float up = glm::clamp(p.y / o.height, 0.0f, 1.0f);
  const float carve = fbm(p * 0.15f, o.seed) * 0.45f * o.depth;         // large rock masses
  const float strata = std::sin(p.y * 2.1f + 3.0f * fbm(p * 0.4f, o.seed + 7u)) * 0.06f * o.depth;
  const float grit = fbm(p * 1.3f, o.seed + 13u) * 0.05f * o.depth;
  glm::vec3 q = p;
  q.z += front * (carve + strata + grit) * (0.3f + 0.7f * up) ;
  q.x += fbm(p * 0.2f + 17.0f, o.seed + 29u) * 0.1f * o.depth * up;
  return q;
}

}  // namespace

Mesh make_cliff_mesh(const CliffOptions& o) {
  const float area = o.width * o.height + o.width * o.depth + o.height * o.depth;  // half the surface
  const float target = float(std::clamp<std::uint32_t>(o.triangles, 12u, kCliffMaxTriangles));
  const float cell = std::sqrt(4.0f * area / target);  // 2 triangles per cell, 2·area of surface
  const glm::ivec3 n(std::max(1, int(std::lround(o.width / cell))), std::max(1, int(std::lround(o.height / cell))),
                     std::max(1, int(std::lround(o.depth / cell))));
  const glm::vec3 lo(-0.5f * o.width, 0.0f, -0.5f * o.depth);
  const glm::vec3 step = glm::vec3(o.width, o.height, o.depth) / glm::vec3(n);

  Mesh mesh;
  mesh.name = "cliff";
  std::unordered_map<std::uint64_t, std::uint32_t> lattice;  // lattice point → vertex (welds the slab's edges)
  auto vertex = [&](glm::ivec3 l) {
    const std::uint64_t key = (std::uint64_t(l.x) << 42) | (std::uint64_t(l.y) << 21) | std::uint64_t(l.z);
    auto [it, fresh] = lattice.emplace(key, std::uint32_t(mesh.positions.size()));
    if (fresh) mesh.positions.push_back(displaced(lo + glm::vec3(l) * step, o));
    return it->second;
  };
  // Face at `origin` spanned by lattice axes u, v (u × v points outwards).
  auto face = [&](glm::ivec3 origin, glm::ivec3 u, glm::ivec3 v, int nu, int nv) {
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const std::uint32_t a = vertex(origin + i * u + j * v), b = vertex(origin + (i + 1) * u + j * v);
        const std::uint32_t c = vertex(origin + (i + 1) * u + (j + 1) * v), d = vertex(origin + i * u + (j + 1) * v);
        mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
      }
  };
  const glm::ivec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
  face(glm::ivec3(0, 0, n.z), X, Y, n.x, n.y);        // front (+z)
  face(glm::ivec3(n.x, 0, 0), -X, Y, n.x, n.y);       // back (-z)
  face(glm::ivec3(n.x, 0, 0), Y, Z, n.y, n.z);        // right (+x)
  face(glm::ivec3(0, 0, 0), Z, Y, n.z, n.y);          // left (-x)
  face(glm::ivec3(0, n.y, 0), Z, X, n.z, n.x);        // top (+y)
  face(glm::ivec3(0, 0, 0), X, Z, n.x, n.z);          // bottom (-y)
  // Every face's u × v points outwards, so triangles wind counter-clockwise
  // seen from outside (tests/cliff_test.cpp: closed and outward).

  // Smooth normals: area-weighted face normals.
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    const glm::vec3& p0 = mesh.positions[mesh.indices[t]];
    const glm::vec3 nrm = glm::cross(mesh.positions[mesh.indices[t + 1]] - p0, mesh.positions[mesh.indices[t + 2]] - p0);
    for (int k = 0; k < 3; ++k) mesh.normals[mesh.indices[t + k]] += nrm;
  }
  for (glm::vec3& v : mesh.normals) {
    const float l = glm::length(v);
    v = l > 0.0f ? v / l : glm::vec3(0.0f, 1.0f, 0.0f);
  }
  return mesh;
}

Material make_cliff_material() {
  Material m;
  m.name = "rock";
  m.base_color = glm::vec3(0.45f, 0.38f, 0.32f);
  m.perceptual_roughness = 0.8f;
  return m;
}

Scene make_cliff_scene(const CliffOptions& o) {
  Scene s;
  s.name = "cliff";
  s.meshes.push_back(make_cliff_mesh(o));
  s.materials.push_back(make_cliff_material());
  Instance i;
  i.name = "cliff";
  s.instances.push_back(i);
  DirectionalLight sun;
  sun.name = "sun";
  sun.direction = glm::normalize(glm::vec3(0.4f, 0.8f, 0.6f));
  sun.illuminance = 3.0f;
  s.directional_lights.push_back(sun);
  s.camera.position = glm::vec3(0.0f, 0.5f * o.height, 0.5f * o.depth + 1.6f * std::max(o.width, o.height));
  s.camera.target = glm::vec3(0.0f, 0.5f * o.height, 0.0f);
  return s;
}

}  // namespace gi
