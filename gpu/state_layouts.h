// The fields of the structs a state buffer's rows hold (StateBuffer::layout
// names one, e.g. "DiReservoir (core/shared/reservoir.h)"), described from
// the struct definitions themselves: each field's offset is offsetof and its
// dtype and count come from its declared type (state_layouts.cpp), and a
// static_assert holds that the fields cover the struct without gap or
// overlap. A renamed field fails to compile, an added one fails the assert,
// so the description in a capture's manifest (and the Python reader and the
// inspector that read it) cannot drift from the code the shaders run.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi::gpu {

struct LayoutField {
  std::string_view name;    // the member, nested with '.': "light.light_id"
  std::uint32_t offset = 0; // bytes from the row's start
  std::string_view dtype;   // numpy dtype of one component: "<f4", "<u4", "<i4"
  std::uint32_t count = 1;  // components: 1 for a scalar, 4 for a vec4, N for uint[N]
  // What the components mean where the struct's comments say it (one word
  // each, space-separated; "" for none): "x y z M" for GiReservoir's
  // sample_position, whose w is the confidence weight.
  std::string_view labels;
};

struct StructLayout {
  std::string_view name;     // "DiReservoir"
  std::uint32_t size = 0;    // sizeof: one row's bytes
  std::vector<LayoutField> fields;
};

// Every struct a listed state buffer's rows can be.
const std::vector<StructLayout>& struct_layouts();

// The struct a StateBuffer::layout names (its first word), or nullptr when
// the layout is a description rather than a struct ("rgb sum, w samples").
const StructLayout* find_struct_layout(std::string_view layout);

// The manifest's "fields" of a buffer: [{name, offset, dtype, count, labels}]
// of its layout's struct, null when there is none.
nlohmann::json layout_fields_json(std::string_view layout);

}  // namespace gi::gpu
