// One instance of the flattened scene as an Embree triangle geometry in world
// space, transformed with exactly the float maths of surface_at()
// (core/shared/scene_access.h), so Embree's hits and the shaders'
// reconstruction agree. Shared by the Embree reference and the Embree ray
// caster the BVH backend is checked against.
#pragma once
#include <cstdint>

#include <embree3/rtcore.h>

#include "core/scene_flatten.h"

namespace gi {

// Attaches instance `index` to `scene` with geomID == index. Returns false when
// Embree cannot allocate its buffers (the caller reports the device error).
bool attach_instance_geometry(RTCDevice device, RTCScene scene, const FlatGeometry& geometry,
                              const GpuInstance& instance, std::uint32_t index);

}  // namespace gi
