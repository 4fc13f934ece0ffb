// The CPU twin of the `bvh` backend's traversal: core/shared/bvh_traverse.h
// compiled as C++ over a SceneBvh's arrays. Tests run it against Embree; the
// shaders run the very same source on the GPU.
#pragma once
#include "core/bvh/scene_bvh.h"
#include "core/shared/bvh_types.h"
#include "core/shared/scene_types.h"
#include "core/shared/watertight.h"

namespace gi::shader {

struct BvhCpuTracer {
  const BvhNode* nodes = nullptr;
  const BvhTriangle* tris = nullptr;

  explicit BvhCpuTracer(const gi::bvh::SceneBvh& bvh) : nodes(bvh.nodes().data()), tris(bvh.triangles().data()) {}

  BvhNode bvh_node(uint i) const { return nodes[i]; }
  BvhTriangle bvh_triangle(uint i) const { return tris[i]; }

#include "core/shared/bvh_traverse.h"
};

}  // namespace gi::shader
