// Packed visibility IDs (docs/design.md §3 step 3, §8), shared by C++ and GLSL
// (core/shared/host_device.h rules): `cluster_id << triangle_bits | triangle`,
// 25/7 by default as in Bevy 0.15, configurable so a small scene can reach the
// limit. The packing keeps only the low cluster_bits of the ID, exactly what a
// 32-bit shift does at 25/7: an ID past the limit silently aliases another
// cluster — the bug the `cluster_ids` check exists for (seeds/virtual-geometry-0.15).
//
// The cluster table (one uint buffer, built by core/clusters/cluster_table.cpp)
// tells the visibility pass which cluster a hit primitive belongs to and the
// G-buffer resolve which primitive a packed ID names:
//   header  [CT_*] words below
//   instances   4 words each: first ID, ID count (0 if hidden), first LOD-0
//               cluster of its mesh (global), LOD-0 cluster count of its mesh
//   primitives  1 word per global triangle (GpuInstance.first_index / 3 + primitive):
//               LOD-0 cluster within its mesh << 8 | triangle within the cluster
//   clusters    max_triangles words per global LOD-0 cluster: mesh-local
//               primitive of each triangle, CLUSTER_NO_PRIMITIVE past its end
// Every instance owns as many IDs as its mesh's whole DAG has clusters (Bevy
// gives every cluster of every instance an ID); only LOD-0 clusters are drawn.
#ifndef GI_CORE_CLUSTERS_CLUSTER_IDS_H
#define GI_CORE_CLUSTERS_CLUSTER_IDS_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

// Binding of the cluster table in primary_visibility.comp and gbuffer_resolve.comp
// (far from gpu/shaders/bindings.h's numbers, which other passes extend).
GI_CONST uint BINDING_CLUSTER_TABLE = 31u;

GI_CONST uint CT_CLUSTER_BITS = 0u;
GI_CONST uint CT_TRIANGLE_BITS = 1u;
GI_CONST uint CT_INSTANCE_COUNT = 2u;
GI_CONST uint CT_INSTANCES = 3u;       // offset of the instance records
GI_CONST uint CT_PRIMITIVES = 4u;      // offset of the per-triangle words
GI_CONST uint CT_CLUSTERS = 5u;        // offset of the per-cluster primitive lists
GI_CONST uint CT_MAX_TRIANGLES = 6u;   // words per cluster list
GI_CONST uint CT_HEADER_WORDS = 8u;
GI_CONST uint CLUSTER_NO_PRIMITIVE = 0xFFFFFFFFu;

GI_FN uint cluster_bits_mask(uint bits) { return bits >= 32u ? 0xFFFFFFFFu : (1u << bits) - 1u; }

GI_FN uint cluster_pack(uint cluster_id, uint triangle, uint cluster_bits, uint triangle_bits) {
  return ((cluster_id & cluster_bits_mask(cluster_bits)) << triangle_bits) | (triangle & cluster_bits_mask(triangle_bits));
}
GI_FN uint cluster_unpack_id(uint packed, uint cluster_bits, uint triangle_bits) {
  return (packed >> triangle_bits) & cluster_bits_mask(cluster_bits);
}
GI_FN uint cluster_unpack_triangle(uint packed, uint triangle_bits) { return packed & cluster_bits_mask(triangle_bits); }

GI_SHADER_END

#endif
