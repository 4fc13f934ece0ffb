// MikkTSpace tangents: what glTF 2.0 asks for when a mesh with a
// normal map has no TANGENT attribute. Our own implementation of Morten
// Mikkelsen's algorithm (mikktspace.c, as Blender and the glTF tools run it,
// with its default 180° angular threshold), checked corner by corner against
// the original's output in tests/data/gltf/tangent_oracle.gltf.
//
// Sign convention: glTF's, as Mesh::tangents documents it (bitangent =
// cross(normal, tangent.xyz) * w). glTF's v axis runs down the image while its
// normal maps' +Y points up, so w is MikkTSpace's sign negated, as
// glTF-Transform's tangents() does (KhronosGroup/glTF-Sample-Models#174).
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "core/scene.h"

namespace gi {

// One tangent per entry of mesh.indices (face corner), as MikkTSpace computes
// it for the unwelded triangles: corners are welded by exact equality of
// position, normal and uv (the input's own vertex numbering does not matter).
// Each tangent is unit length and orthogonal to its corner's normal; w = ±1.
// Throws std::invalid_argument unless the mesh has one normal and one uv per
// position, a whole number of triangles and indices within range.
std::vector<glm::vec4> mikktspace_corner_tangents(const Mesh& mesh);

// Fills mesh.tangents, one per vertex, from mikktspace_corner_tangents. A
// vertex whose corners got different tangents (a uv seam's far side sharing
// the vertex, mirrored uvs) is split: the extra copies get the same position,
// normal and uv and the corners are re-pointed at them, as glTF tools'
// unweld → MikkTSpace → weld would do. New vertices are appended in corner
// order, so the result is deterministic. Vertices no triangle uses get an
// arbitrary unit tangent orthogonal to their normal. Same errors as above.
void generate_tangents(Mesh& mesh);

}  // namespace gi
