// The CPU twin of the `bvh` backend's traversal: core/shared/bvh_traverse.h
// compiled as C++ over a SceneBvh's arrays. Tests run it against Embree; the
// shaders run the very same source on the GPU. BvhCpuTracer is the one-loop
// form (what lavapipe runs), BvhCpuTracerPerLevel the loop-per-level form
// (what GPUs run); tests/bvh_test.cpp holds them to the same bits.
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

#define BVH_TRAVERSAL_ONE_LOOP
#include "core/shared/bvh_traverse.h"
#undef BVH_TRAVERSAL_ONE_LOOP
};

struct BvhCpuTracerPerLevel {
  const BvhNode* nodes = nullptr;
  const BvhTriangle* tris = nullptr;

  explicit BvhCpuTracerPerLevel(const gi::bvh::SceneBvh& bvh)
      : nodes(bvh.nodes().data()), tris(bvh.triangles().data()) {}

  BvhNode bvh_node(uint i) const { return nodes[i]; }
  BvhTriangle bvh_triangle(uint i) const { return tris[i]; }

#include "core/shared/bvh_traverse.h"
};

}  // namespace gi::shader
