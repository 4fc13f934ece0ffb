#include "gpu/state_layouts.h"

#include <array>
#include <cstddef>
#include <utility>

#include "core/shared/light_tiles.h"
#include "core/shared/reservoir.h"
#include "core/shared/restir_di.h"
#include "core/shared/restir_gi.h"
#include "core/shared/world_cache.h"
#include "gpu/shaders/gbuffer.h"
#include "gpu/shaders/gi_bindings.h"

namespace gi::gpu {
namespace {

// dtype and component count of a member's declared type. Only the types the
// state structs use: another type fails to compile here, not in a reader.
template <class T>
struct FieldType;
template <>
struct FieldType<float> {
  static constexpr std::string_view dtype = "<f4";
  static constexpr std::uint32_t count = 1;
};
template <>
struct FieldType<std::uint32_t> {
  static constexpr std::string_view dtype = "<u4";
  static constexpr std::uint32_t count = 1;
};
template <>
struct FieldType<std::int32_t> {
  static constexpr std::string_view dtype = "<i4";
  static constexpr std::uint32_t count = 1;
};
template <int N, class C, glm::qualifier Q>
struct FieldType<glm::vec<N, C, Q>> {
  static constexpr std::string_view dtype = FieldType<C>::dtype;
  static constexpr std::uint32_t count = N;
};
template <class C, std::size_t N>
struct FieldType<C[N]> {
  static constexpr std::string_view dtype = FieldType<C>::dtype;
  static constexpr std::uint32_t count = std::uint32_t(N) * FieldType<C>::count;
};

struct Field {
  std::string_view name;
  std::uint32_t offset, bytes;
  std::string_view dtype;
  std::uint32_t count;
  std::string_view labels;
};

// offsetof with a nested member designator ("light.light_id") is what GCC and
// Clang accept for standard-layout structs, which every shared struct is.
#define GI_FIELD(S, member, labels)                                                                       \
  Field {                                                                                                 \
    #member, std::uint32_t(offsetof(S, member)), std::uint32_t(sizeof(std::declval<S&>().member)),         \
        FieldType<std::remove_cvref_t<decltype(std::declval<S&>().member)>>::dtype,                       \
        FieldType<std::remove_cvref_t<decltype(std::declval<S&>().member)>>::count, labels                \
  }

// The fields, in order, tile [0, size): each begins where the last ended and
// the last ends at sizeof, so a member added to the struct and not here (or
// padding the compiler inserted) fails the static_assert below.
template <std::size_t N>
constexpr bool covers(const std::array<Field, N>& fields, std::size_t size) {
  std::size_t end = 0;
  for (const Field& f : fields) {
    if (f.offset != end || f.bytes != 4u * f.count) return false;
    end = f.offset + f.bytes;
  }
  return end == size;
}

using namespace gi::shader;

constexpr std::array kLightSample{
    GI_FIELD(LightSample, light_id, "light"), GI_FIELD(LightSample, triangle_id, "triangle"),
    GI_FIELD(LightSample, seed, "seed"), GI_FIELD(LightSample, valid, "valid")};
static_assert(covers(kLightSample, sizeof(LightSample)), "LightSample's fields must cover the struct");

constexpr std::array kDiReservoir{
    GI_FIELD(DiReservoir, light.light_id, "light"), GI_FIELD(DiReservoir, light.triangle_id, "triangle"),
    GI_FIELD(DiReservoir, light.seed, "seed"), GI_FIELD(DiReservoir, light.valid, "valid"),
    GI_FIELD(DiReservoir, confidence_weight, "M"), GI_FIELD(DiReservoir, unbiased_contribution_weight, "W"),
    GI_FIELD(DiReservoir, pad0, ""), GI_FIELD(DiReservoir, pad1, "")};
static_assert(covers(kDiReservoir, sizeof(DiReservoir)), "DiReservoir's fields must cover the struct");

constexpr std::array kGiReservoir{GI_FIELD(GiReservoir, sample_position, "x y z M"),
                                  GI_FIELD(GiReservoir, sample_normal, "x y z -"),
                                  GI_FIELD(GiReservoir, radiance, "r g b W")};
static_assert(covers(kGiReservoir, sizeof(GiReservoir)), "GiReservoir's fields must cover the struct");

constexpr std::array kDiSurface{GI_FIELD(DiSurface, position_view_z, "x y z view_z"),
                                GI_FIELD(DiSurface, normal, "x y z -"), GI_FIELD(DiSurface, diffuse, "r g b -")};
static_assert(covers(kDiSurface, sizeof(DiSurface)), "DiSurface's fields must cover the struct");

constexpr std::array kGiSurface{GI_FIELD(GiSurface, position_view_z, "x y z view_z"),
                                GI_FIELD(GiSurface, normal, "x y z -"),
                                GI_FIELD(GiSurface, base_color, "r g b metallic")};
static_assert(covers(kGiSurface, sizeof(GiSurface)), "GiSurface's fields must cover the struct");

constexpr std::array kPackedLightSample{
    GI_FIELD(PackedLightSample, position_x, ""), GI_FIELD(PackedLightSample, position_y, ""),
    GI_FIELD(PackedLightSample, position_z, ""), GI_FIELD(PackedLightSample, normal, "octahedral"),
    GI_FIELD(PackedLightSample, radiance, "rgb9e5"), GI_FIELD(PackedLightSample, inverse_pdf, "")};
static_assert(covers(kPackedLightSample, sizeof(PackedLightSample)),
              "PackedLightSample's fields must cover the struct");

constexpr std::array kWorldCacheGeometry{GI_FIELD(WorldCacheGeometry, position, "x y z -"),
                                         GI_FIELD(WorldCacheGeometry, normal, "x y z -")};
static_assert(covers(kWorldCacheGeometry, sizeof(WorldCacheGeometry)),
              "WorldCacheGeometry's fields must cover the struct");

constexpr std::array kGBufferTexel{GI_FIELD(GBufferTexel, position_depth, "x y z t"),
                                   GI_FIELD(GBufferTexel, geometric_normal, "x y z hit"),
                                   GI_FIELD(GBufferTexel, shading_normal, "x y z brdf_model"),
                                   GI_FIELD(GBufferTexel, base_color_metallic, "r g b metallic"),
                                   GI_FIELD(GBufferTexel, emissive_roughness, "r g b roughness"),
                                   GI_FIELD(GBufferTexel, motion_reflectance, "dx dy valid reflectance")};
static_assert(covers(kGBufferTexel, sizeof(GBufferTexel)), "GBufferTexel's fields must cover the struct");

constexpr std::array kGiStats{GI_FIELD(GiStats, merges, ""),
                              GI_FIELD(GiStats, rejections, ""),
                              GI_FIELD(GiStats, max_accepted_j_bits, "float_bits"),
                              GI_FIELD(GiStats, nonfinite_jacobians, ""),
                              GI_FIELD(GiStats, nonfinite_reservoirs, ""),
                              GI_FIELD(GiStats, nonfinite_output, ""),
                              GI_FIELD(GiStats, temporal_edge_pixels, ""),
                              GI_FIELD(GiStats, temporal_edge_reused, ""),
                              GI_FIELD(GiStats, histogram, "")};
static_assert(covers(kGiStats, sizeof(GiStats)), "GiStats's fields must cover the struct");

constexpr std::array kGiCounters{GI_FIELD(GiCounters, specular_paths, ""), GI_FIELD(GiCounters, specular_segments, ""),
                                 GI_FIELD(GiCounters, spatial_pixels, ""), GI_FIELD(GiCounters, spatial_found, "")};
static_assert(covers(kGiCounters, sizeof(GiCounters)), "GiCounters's fields must cover the struct");

#undef GI_FIELD

template <std::size_t N>
StructLayout make(std::string_view name, std::size_t size, const std::array<Field, N>& fields) {
  StructLayout s{name, std::uint32_t(size), {}};
  for (const Field& f : fields) s.fields.push_back({f.name, f.offset, f.dtype, f.count, f.labels});
  return s;
}

}  // namespace

const std::vector<StructLayout>& struct_layouts() {
  static const std::vector<StructLayout> layouts = {
      make("LightSample", sizeof(LightSample), kLightSample),
      make("DiReservoir", sizeof(DiReservoir), kDiReservoir),
      make("GiReservoir", sizeof(GiReservoir), kGiReservoir),
      make("DiSurface", sizeof(DiSurface), kDiSurface),
      make("GiSurface", sizeof(GiSurface), kGiSurface),
      make("PackedLightSample", sizeof(PackedLightSample), kPackedLightSample),
      make("WorldCacheGeometry", sizeof(WorldCacheGeometry), kWorldCacheGeometry),
      make("GBufferTexel", sizeof(GBufferTexel), kGBufferTexel),
      make("GiStats", sizeof(GiStats), kGiStats),
      make("GiCounters", sizeof(GiCounters), kGiCounters),
  };
  return layouts;
}

const StructLayout* find_struct_layout(std::string_view layout) {
  const std::string_view name = layout.substr(0, layout.find(' '));
  for (const StructLayout& s : struct_layouts())
    if (s.name == name) return &s;
  return nullptr;
}

nlohmann::json layout_fields_json(std::string_view layout) {
  const StructLayout* s = find_struct_layout(layout);
  if (s == nullptr) return nullptr;
  nlohmann::json fields = nlohmann::json::array();
  for (const LayoutField& f : s->fields)
    fields.push_back({{"name", std::string(f.name)},
                      {"offset", f.offset},
                      {"dtype", std::string(f.dtype)},
                      {"count", f.count},
                      {"labels", std::string(f.labels)}});
  return fields;
}

}  // namespace gi::gpu
