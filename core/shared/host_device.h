// One header, two languages. Every file in core/shared compiles as GLSL 460
// (through glslang, GL_GOOGLE_include_directive) and as C++20 with GLM, so the
// shaders, the Embree reference and the unit tests run the very same maths.
//
// Rules for shared code (both compilers enforce them):
// - float literals carry an `f` suffix (C++ would otherwise pick double and
//   GLM templates would not deduce); unsigned literals a `u`.
// - `out`/`inout` parameters are written OUT(T)/INOUT(T).
// - no constructors on structs: declare, then assign fields.
// - functions are marked GI_FN (C++ `inline`, nothing in GLSL).
#ifndef GI_SHARED_HOST_DEVICE_H
#define GI_SHARED_HOST_DEVICE_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>
namespace gi::shader {
using namespace glm;
using uint = std::uint32_t;
}  // namespace gi::shader
#define GI_SHADER_BEGIN namespace gi::shader {
#define GI_SHADER_END }
#define GI_FN inline
#define OUT(T) T&
#define INOUT(T) T&
#define GI_CONST inline constexpr
#else
#define GI_SHADER_BEGIN
#define GI_SHADER_END
#define GI_FN
#define OUT(T) out T
#define INOUT(T) inout T
#define GI_CONST const
#endif

GI_SHADER_BEGIN

GI_CONST float PI = 3.14159265358979323846f;
GI_CONST float TWO_PI = 6.28318530717958647692f;
GI_CONST float INV_PI = 0.31830988618379067154f;

GI_FN float saturate(float x) { return clamp(x, 0.0f, 1.0f); }
GI_FN float luminance(vec3 c) { return dot(c, vec3(0.2126f, 0.7152f, 0.0722f)); }
GI_FN float max3(vec3 v) { return max(v.x, max(v.y, v.z)); }

GI_SHADER_END

#endif
