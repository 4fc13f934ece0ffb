// Generated scenes for the world-cache checks: small, deterministic,
// parameter-free, all Lambertian (the cache treats surfaces as diffuse).
//   cache_closed_room : a closed 4 × 3 × 4 m room lit by one ceiling panel
//                       ("light"); light bounces around and cannot leave, so a
//                       cache feeding on itself lags longest here.
//   cache_room_and_yard : the same room with a doorway in its +z wall onto a
//                       60 × 60 m yard with a row of blocks under a sun
//                       ("sun", directional); a camera walks out and back.
//   cache_open_field  : a 400 × 400 m field of blocks under a sun: far
//                       surfaces fall into coarse LOD cells.
//   leak_thin_wall    : two rooms split by a 2 cm wall with a doorway at one
//                       end; a panel lights the far room only, and the camera
//                       looks at the wall's dark side, which the world cache's
//                       cells (15-25 cm) straddle (the light_leak check).
//   leak_zero_thickness_wall : the same two rooms split by a wall of one
//                       face (no thickness; the mesh's normal towards the
//                       lit room, both sides drawn as a double_sided plane
//                       is in Bevy), so rays from the dark room hit its back:
//                       which cell a back face keys (world_cache.hit_normal).
#pragma once
#include "core/scene.h"

namespace gi {

Scene make_cache_closed_room();
Scene make_cache_room_and_yard();
Scene make_cache_open_field();
Scene make_leak_thin_wall();
Scene make_leak_zero_thickness_wall();

}  // namespace gi
