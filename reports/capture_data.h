// A frame capture's contents in memory, as the inspector reads them
// (replay/capture.h documents the folder; app/inspect_command.cpp loads it):
// every buffer's bytes with the manifest's dtype, shape, layout and fields,
// and every layer of images.exr.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"

namespace gi {

struct CaptureBuffer {
  std::string name, dtype, layout;
  std::vector<std::uint64_t> shape;
  nlohmann::json fields;  // the manifest's field list (gpu/state_layouts.h), null without one
  std::vector<std::uint8_t> bytes;
};

struct CaptureLayer {
  std::string name;  // "output" for the EXR's unnamed R,G,B
  Image image;
};

struct CaptureData {
  std::filesystem::path dir;
  nlohmann::json manifest;
  std::uint32_t frame = 0;
  std::uint32_t width = 0, height = 0;  // the output image's
  std::vector<CaptureBuffer> buffers;
  std::vector<CaptureLayer> layers;

  const CaptureBuffer* find_buffer(const std::string& name) const {
    for (const CaptureBuffer& b : buffers)
      if (b.name == name) return &b;
    return nullptr;
  }
  const CaptureLayer* find_layer(const std::string& name) const {
    for (const CaptureLayer& l : layers)
      if (l.name == name) return &l;
    return nullptr;
  }
};

}  // namespace gi
