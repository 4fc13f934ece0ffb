// The Cornell box with the measurements of the Cornell Program of Computer
// Graphics' published data set (millimetres there, metres here), open at the
// front, camera at the published position with a 39.3077° field of view.
#pragma once
#include "core/scene.h"

namespace gi {

struct CornellBoxOptions {
  float light_scale = 1.0f;          // multiplies the light's radiance (17, 12, 4)
  float albedo_scale = 1.0f;         // multiplies every wall and block albedo
  bool blocks = true;                // the short and the tall block
  float scale = 1.0f;                // multiplies every length (1: the data set's 0.56 m box)
};

// Instances: floor_ceiling_back (white), red_wall, green_wall, short_block,
// tall_block, light (emissive quad just under the ceiling).
Scene make_cornell_box(const CornellBoxOptions& options = {});

}  // namespace gi
