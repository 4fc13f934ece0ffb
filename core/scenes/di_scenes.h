// Generated scenes for the realtime DI checks: small, deterministic,
// parameter-free.
//   di_many_lights   : 512 small emissive quads (1024 triangles) of varied
//                      colour over a floor with two boxes.
//   di_occluder      : a floor lit by one area light, with a box ("occluder")
//                      between them; scenarios move it with transform events.
//   di_packing_range : a 2 cm emitter of radiance 3e5 (above rgb9e5's 65408)
//                      beside a 1 m² emitter of radiance 1, over a floor.
//   di_sun_penumbra  : a wall on a floor under a sun of 0.1 rad angular
//                      radius: wide penumbrae (Solari 0.17's hard sun, #22253).
#pragma once
#include "core/scene.h"

namespace gi {

Scene make_di_many_lights();
Scene make_di_occluder();
Scene make_di_packing_range();
Scene make_di_sun_penumbra();

}  // namespace gi
