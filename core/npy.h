// NumPy .npy files (format version 1.0, read also 2.0), so that a capture's
// buffers open with `numpy.load` (docs/design.md §9). Little-endian, C order only;
// the element type is a numpy dtype string ("<f4", "<u4", "<i4", "<u8",
// "<f8", "|u1"). Debian's libxtensor-dev has an .npy reader/writer, but only
// for xtensor arrays, a header-only dependency for some hundred lines here;
// the format is a 10-byte preamble plus a Python-literal header, and the
// reader must name the file and what was wrong on a bad one (InputError).
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace gi {

struct NpyArray {
  std::string dtype;                 // e.g. "<f4"
  std::vector<std::uint64_t> shape;  // C order; {} is a scalar
  std::vector<std::uint8_t> data;    // element_count() · itemsize bytes

  std::uint64_t element_count() const;
};

// Bytes of one element of a supported dtype; throws std::invalid_argument otherwise.
std::size_t npy_itemsize(const std::string& dtype);

// The whole file (preamble, header padded so that the data starts on a
// 64-byte boundary, as numpy writes it, then the data).
std::vector<std::uint8_t> encode_npy(const std::string& dtype, const std::vector<std::uint64_t>& shape,
                                     const void* data, std::size_t bytes);
// Throws std::invalid_argument when bytes ≠ product(shape) · itemsize.
void write_npy(const std::filesystem::path& path, const std::string& dtype, const std::vector<std::uint64_t>& shape,
               const void* data, std::size_t bytes);

// Only the header (no data read): dtype and shape. Throws gi::InputError
// naming the file on anything that is not a C-order .npy of a supported dtype.
NpyArray read_npy_header(const std::filesystem::path& path);
NpyArray read_npy(const std::filesystem::path& path);
// Same from bytes in memory; `name` is what errors call it.
NpyArray decode_npy(const std::vector<std::uint8_t>& bytes, const std::string& name, bool header_only = false);

}  // namespace gi
