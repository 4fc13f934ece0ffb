#include <gtest/gtest.h>

#include "core/scene_flatten.h"
#include "core/scenes/cornell_box.h"

// The Cornell box flattens into the layout the shaders read: every triangle
// indexes a vertex of its own mesh and the light becomes one emissive light.
TEST(CornellBox, FlattensWithOneEmissiveLight) {
  gi::Scene scene = gi::make_cornell_box();
  gi::FlatGeometry g = gi::flatten_geometry(scene);
  gi::FlatInstances f = gi::flatten_instances(scene, g);
  ASSERT_EQ(f.lights.size(), 1u);
  EXPECT_EQ(f.lights[0].kind, gi::shader::LIGHT_KIND_EMISSIVE_MESH);
  EXPECT_EQ(f.directional_light_count, 0u);
  for (const gi::MeshRange& r : g.meshes)
    for (std::uint32_t i = 0; i < 3 * r.triangle_count; ++i) EXPECT_LT(g.indices[r.first_index + i], r.vertex_count);
}
