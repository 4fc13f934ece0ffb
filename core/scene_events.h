// Applying a scenario's events to the scene (docs/design.md §7, §9).
//
// The rule (what makes replay from a mid-run snapshot bit-identical):
// the scene at frame f is a pure function of (initial scene, scenario, f).
// apply_events() does not accumulate: it recomputes the state from `initial`
// and then reports what differs from the scene it was given. It is
//
//   initial, then every event with first <= f, in event_order() (start frame,
//   then position in the file), each evaluated at frame f, where
//     t = 1                          for "frame" events and once f >= last,
//     t = (f - first) / (last - first)   inside a "frames": [first, last] range
//
//  - light_on / light_off: the light's on flag. An instance light's
//    emissive_scale = on ? initial_emissive_scale · intensity · colour : 0;
//    a directional light: enabled = on, illuminance = initial · intensity,
//    color = colour. intensity starts at 1; colour at (1,1,1) for instances
//    (a per-channel tint of the material's emission) and at the light's
//    initial colour for directional lights (an absolute colour).
//  - light_intensity: intensity = mix(current, scale, t); light_color:
//    colour = mix(current, color, t). "current" is the value under the events
//    applied before this one, at the same frame f; with no overlapping ranged
//    event on the same light it is the value at the event's first frame.
//  - material: each given field = mix(current, target, t), same "current".
//  - camera_keyframes: governs the camera from frame 0 (holds its first key
//    before it, its last key after it), piecewise linear between keys; a key
//    without fov_y_degrees carries the previous key's (before any key has
//    one: the camera's field of view under the earlier events). camera_sweep:
//    from its first frame on, mix(from, to, ease(t)), ease = t or smoothstep;
//    holds "to" after its last frame. The camera event started last wins
//    (ties: the later in the file). "up" is never changed by events.
//  - transform: transform = Δ(t) · current, Δ(t) = T(t·translation) ·
//    R(t·rotation_degrees) · S(mix(1, scale, t)) in world space, R = Rz·Ry·Rx
//    (xyz Euler). Several transform events on one instance compose in order.
//  - spawn: appends an instance (so instance indices are stable: the initial
//    ones, then spawns in event_order()). "of": the source instance's mesh,
//    material and initial emissive_scale, transform = Δ · the source's initial
//    (or spawn) transform, visible. "mesh": a generated mesh and material are
//    appended (generate_mesh()), transform = Δ.
//  - despawn: visible = false (the instance stays in the list).
//  - every instance's previous_transform is its transform at frame f − 1
//    where that differs from its transform at f; none at frame 0 and on a
//    spawn's first frame (Bevy gives a new mesh its own transform as the
//    previous one: v0.18.0:bevy_pbr/src/prepass/mod.rs:229-230).
//  - remove_raytracing_mesh: visible = false and raytracing_mesh_removed
//    (Bevy's RaytracingMesh3d removed while the entity lives on). The scene
//    here is the truth the references see; FrameLoop decides what the
//    renderer keeps (profile key scene.raytracing_mesh_removal).
#pragma once
#include <cstdint>

#include "core/scenario.h"
#include "core/scene.h"

namespace gi {

struct ChangeSet {
  bool geometry = false;    // meshes or the instance list changed (spawn): rebuild acceleration structures
  bool transforms = false;  // an instance's transform changed
  bool visibility = false;  // an instance's visible flag changed (despawn)
  bool materials = false;   // a material changed
  bool lights = false;      // emissive_scale, a directional light, or a material's emission changed
  bool camera = false;
  // An instance's previous transform changed (Instance::previous_transform):
  // the motion vectors only, so not part of any(); the frame after an object
  // stops moving has it alone.
  bool motion = false;
  bool any() const { return geometry || transforms || visibility || materials || lights || camera; }
};

// Sets `scene` to the state at `frame` (see above) and returns what changed
// relative to the `scene` it was given. `initial` is what build_scene()
// returned (its events validated).
ChangeSet apply_events(Scene& scene, const Scene& initial, const Scenario& scenario, std::uint32_t frame);
// What apply_events would report at `frame`, without changing `scene`.
ChangeSet changes_at(const Scene& scene, const Scene& initial, const Scenario& scenario, std::uint32_t frame);

// The state at `frame`, from scratch.
Scene scene_at_frame(const Scene& initial, const Scenario& scenario, std::uint32_t frame);

}  // namespace gi
