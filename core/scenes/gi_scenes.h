// Hard scenes for ReSTIR GI and specular GI (docs/design.md §7), generated,
// deterministic, small, parameter-free:
//   gi_corners    : a closed room (so nearly every GI ray finds a surface)
//                   with tight corners — a wedge of two walls 5° apart, a
//                   thin wall 1 cm thick — lit by one ceiling emitter; the
//                   camera looks into the corner. Neighbouring pixels see
//                   sample points nearly edge-on: jacobians blow up here.
//   gi_mirror     : a Cornell-like room with a zero-roughness metallic mirror
//                   (perceptual roughness 0) on the back wall and a glossy
//                   floor (roughness 0.3): zero roughness is NaN without the clamp.
//   gi_hard_cases : a grazing view along a long floor, emitters of radiance
//                   1e-4 and 1e6 side by side with one of 1, a degenerate
//                   (zero-area) triangle and sliver triangles (aspect 1e4),
//                   and a zero-roughness mirror — everything `finite` must survive.
//   gi_indirect_shadow: a floor lit only by a bright wall (a wall washer
//                   lights the wall and faces away from the floor), and a
//                   black 1 m screen, "screen", that a scenario moves in
//                   between: an indirect shadow, for shadow_lag on ReSTIR
//                   GI's visibility (Bevy #22287).
//   gi_headon_panel: a glossy metal panel tilted off every axis in a lit room,
//                   seen head-on through a 1.5° lens: reflected rays leave
//                   nearly along the view ray, where Fresnel's L·H rounds
//                   above 1 (Bevy #24668's NaN).
//   gi_mirror_shadow_stripe: a mirror fills the view and shows the floor, on
//                   which a 30 cm bar under a small light throws a 37 cm
//                   shadow stripe: a reflection whose detail is finer than a
//                   world-cache cell (Bevy #22311).
#pragma once
#include "core/scene.h"

namespace gi {

Scene make_gi_corners();
Scene make_gi_mirror();
Scene make_gi_hard_cases();
Scene make_gi_indirect_shadow();
Scene make_gi_headon_panel();
Scene make_gi_mirror_shadow_stripe();

}  // namespace gi
