// core/npy.h: the .npy files of captures must open with numpy.load.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "core/errors.h"
#include "core/npy.h"
#include "tests/test_support.h"

namespace gi {
namespace {

std::string header_text(const std::vector<std::uint8_t>& file) {
  const std::size_t len = file[8] | (std::size_t(file[9]) << 8);
  return std::string(file.begin() + 10, file.begin() + 10 + static_cast<std::ptrdiff_t>(len));
}

// numpy 1.x `np.save` of np.zeros((2, 3), np.float32) writes exactly this
// preamble and header (128 bytes: the data starts 64-byte aligned).
TEST(Npy, HeaderIsByteForByteWhatNumpyWrites) {
  const float zeros[6] = {};
  const auto file = encode_npy("<f4", {2, 3}, zeros, sizeof zeros);
  std::string expected = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
  expected.append(128 - 10 - expected.size() - 1, ' ');
  expected += '\n';
  ASSERT_EQ(file.size(), 128u + sizeof zeros);
  EXPECT_EQ(std::string(file.begin(), file.begin() + 8), std::string("\x93NUMPY\x01\x00", 8));
  EXPECT_EQ(file[8], 118);
  EXPECT_EQ(file[9], 0);
  EXPECT_EQ(header_text(file), expected);
}

TEST(Npy, OneDimensionalShapeIsAPythonOneTuple) {
  const std::uint32_t v[3] = {1, 2, 3};
  EXPECT_NE(header_text(encode_npy("<u4", {3}, v, sizeof v)).find("'shape': (3,), }"), std::string::npos);
  EXPECT_NE(header_text(encode_npy("<u4", {}, v, 4)).find("'shape': (), }"), std::string::npos);
}

TEST(Npy, RoundTripsThroughAFile) {
  test::TempDir dir("npy");
  std::vector<float> data(4 * 3 * 2);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = float(i) * 0.5f - 3.0f;
  const auto path = dir.path() / "a.npy";
  write_npy(path, "<f4", {4, 3, 2}, data.data(), data.size() * sizeof(float));
  const NpyArray header = read_npy_header(path);
  EXPECT_EQ(header.dtype, "<f4");
  EXPECT_EQ(header.shape, (std::vector<std::uint64_t>{4, 3, 2}));
  EXPECT_TRUE(header.data.empty());
  const NpyArray a = read_npy(path);
  ASSERT_EQ(a.data.size(), data.size() * sizeof(float));
  EXPECT_EQ(std::memcmp(a.data.data(), data.data(), a.data.size()), 0);
}

TEST(Npy, DataIsAlignedTo64BytesForAnyHeaderLength) {
  for (const auto& shape : std::vector<std::vector<std::uint64_t>>{{0}, {0, 7}, {0, 123456789, 11, 5}}) {
    const auto f = encode_npy("<u8", shape, nullptr, 0);
    EXPECT_EQ(f.size() % 64, 0u);
    EXPECT_EQ(f.back(), '\n');
  }
}

TEST(Npy, SizeMismatchIsRefusedOnWrite) {
  const float v[2] = {};
  EXPECT_THROW(encode_npy("<f4", {3}, v, sizeof v), std::invalid_argument);
  EXPECT_THROW(encode_npy("<c8", {2}, v, sizeof v), std::invalid_argument);
}

TEST(Npy, BadFilesAreInputErrorsNamingTheFile) {
  const float v[2] = {1, 2};
  std::vector<std::uint8_t> good = encode_npy("<f4", {2}, v, sizeof v);
  auto truncated = good;
  truncated.pop_back();
  EXPECT_THROW(decode_npy(truncated, "t.npy"), InputError);
  auto magic = good;
  magic[1] = 'X';
  EXPECT_THROW(decode_npy(magic, "m.npy"), InputError);
  std::vector<std::uint8_t> fortran = good;
  const std::string h = header_text(good);
  const std::size_t at = h.find("False");
  std::memcpy(fortran.data() + 10 + at, "True ", 5);
  try {
    decode_npy(fortran, "f.npy");
    FAIL() << "Fortran order accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "f.npy");
    EXPECT_NE(std::string(e.what()).find("fortran_order"), std::string::npos);
  }
  EXPECT_THROW(read_npy("/nonexistent/x.npy"), InputError);
}

}  // namespace
}  // namespace gi
