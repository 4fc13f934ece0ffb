// `giharness inspect CAPTURE_DIR [--against OTHER|BASELINE.json] [--reference [--reference-spp N]] [--out FILE.html]`
// (docs/commands/inspect.md): one self-contained HTML page of a capture
// (reports/inspect_page.h), and the capture loaded for it.
#pragma once
#include <filesystem>
#include <optional>

#include <CLI/CLI.hpp>

#include "reports/capture_data.h"

namespace gi {

struct InspectOptions {
  std::filesystem::path capture;
  std::filesystem::path against;  // another capture folder or a baseline JSON, empty for none
  std::filesystem::path out;      // default <capture>/inspect.html
  bool reference = false;         // the Embree reference of the captured frame beside the output
  std::optional<std::uint32_t> reference_spp;  // default: the scenario's reference check's, else 256
};

// What the page adds beyond the capture: the comparison (a capture folder or
// a baseline JSON, told apart by the path: a file is a baseline), the
// reference, and a check's region (the nightly's failing check).
struct InspectExtras {
  std::filesystem::path against;
  bool reference = false;
  std::optional<std::uint32_t> reference_spp;
  // [x0, y0, x1, y1] inclusive pixels (null for none), and the region's mask
  // where the check wrote one: an EXR (relative to nothing: a path) and its layer.
  nlohmann::json region;
  std::filesystem::path region_mask_file;
  std::string region_mask_layer;
};

CLI::App* add_inspect_subcommand(CLI::App& app, InspectOptions& options);
int run_inspect(const InspectOptions& options);

// Reads a capture folder whole: the manifest (validated: replay/capture.h),
// every buffer's .npy and every layer of images.exr. InputError naming the
// file on anything missing or malformed.
CaptureData load_capture_data(const std::filesystem::path& dir);

// Writes the page of `capture` (with what `extras` asks for) to `out`,
// atomically. The page's size in bytes.
std::uintmax_t write_inspect_page(const std::filesystem::path& capture, const InspectExtras& extras,
                                  const std::filesystem::path& out);

}  // namespace gi
