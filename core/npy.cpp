#include "core/npy.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string_view>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace gi {
namespace {

constexpr char kMagic[] = "\x93NUMPY";  // 6 bytes
constexpr std::size_t kMagicSize = 6;
constexpr std::size_t kAlignment = 64;  // numpy pads the header so the data is 64-byte aligned

struct DtypeInfo {
  const char* name;
  std::size_t size;
};
constexpr DtypeInfo kDtypes[] = {{"<f4", 4}, {"<f8", 8}, {"<u4", 4}, {"<i4", 4},
                                 {"<u8", 8}, {"<i8", 8}, {"|u1", 1}, {"<u2", 2}};

std::string shape_literal(const std::vector<std::uint64_t>& shape) {
  // Python tuple syntax: (), (3,), (2, 3)
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) s += ",";
  return s + ")";
}

// A tiny reader of the header dict numpy writes: {'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }
class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& name) : t_(text), name_(name) {}

  NpyArray parse() {
    NpyArray a;
    bool have_descr = false, have_order = false, have_shape = false;
    expect('{');
    while (true) {
      skip_space();
      if (peek() == '}') break;
      const std::string key = quoted();
      expect(':');
      if (key == "descr") {
        a.dtype = quoted();
        have_descr = true;
      } else if (key == "fortran_order") {
        skip_space();
        if (t_.substr(pos_, 5) == "False") pos_ += 5;
        else fail("'fortran_order': False (only C order is read)");
        have_order = true;
      } else if (key == "shape") {
        a.shape = tuple();
        have_shape = true;
      } else {
        fail("only the keys descr, fortran_order and shape, got '" + key + "'");
      }
      skip_space();
      if (peek() == ',') ++pos_;
    }
    if (!have_descr || !have_order || !have_shape) fail("a header with descr, fortran_order and shape");
    return a;
  }

 private:
  char peek() const { return pos_ < t_.size() ? t_[pos_] : '\0'; }
  void skip_space() {
    while (pos_ < t_.size() && (t_[pos_] == ' ' || t_[pos_] == '\n')) ++pos_;
  }
  void expect(char c) {
    skip_space();
    if (peek() != c) fail(std::string("'") + c + "' in the header");
    ++pos_;
  }
  std::string quoted() {
    skip_space();
    const char q = peek();
    if (q != '\'' && q != '"') fail("a quoted string in the header");
    const std::size_t end = t_.find(q, pos_ + 1);
    if (end == std::string_view::npos) fail("a closing quote in the header");
    std::string s(t_.substr(pos_ + 1, end - pos_ - 1));
    pos_ = end + 1;
    return s;
  }
  std::vector<std::uint64_t> tuple() {
    std::vector<std::uint64_t> v;
    expect('(');
    while (true) {
      skip_space();
      if (peek() == ')') break;
      if (peek() < '0' || peek() > '9') fail("a shape of non-negative integers");
      std::uint64_t n = 0;
      while (peek() >= '0' && peek() <= '9') {
        if (n > (~std::uint64_t{0} - 9) / 10) fail("a shape that fits 64 bits");
        n = n * 10 + std::uint64_t(peek() - '0');
        ++pos_;
      }
      v.push_back(n);
      skip_space();
      if (peek() == ',') ++pos_;
    }
    ++pos_;
    return v;
  }
  [[noreturn]] void fail(const std::string& expected) const { throw InputError(name_, "", "a .npy file: expected " + expected); }

  std::string_view t_;
  std::string name_;
  std::size_t pos_ = 0;
};

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path, std::size_t limit) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "a readable .npy file");
  std::vector<std::uint8_t> bytes;
  if (limit == 0) {
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } else {
    bytes.resize(limit);
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(limit));
    bytes.resize(static_cast<std::size_t>(in.gcount()));
  }
  return bytes;
}

}  // namespace

std::uint64_t NpyArray::element_count() const {
  std::uint64_t n = 1;
  for (std::uint64_t d : shape) n *= d;
  return n;
}

std::size_t npy_itemsize(const std::string& dtype) {
  for (const DtypeInfo& d : kDtypes)
    if (dtype == d.name) return d.size;
  throw std::invalid_argument("unsupported npy dtype '" + dtype + "'");
}

std::vector<std::uint8_t> encode_npy(const std::string& dtype, const std::vector<std::uint64_t>& shape,
                                     const void* data, std::size_t bytes) {
  std::uint64_t count = 1;
  for (std::uint64_t d : shape) count *= d;
  if (count * npy_itemsize(dtype) != bytes)
    throw std::invalid_argument("encode_npy: " + std::to_string(bytes) + " bytes for shape " + shape_literal(shape) +
                                " of " + dtype);
  std::string header = "{'descr': '" + dtype + "', 'fortran_order': False, 'shape': " + shape_literal(shape) + ", }";
  // Pad with spaces and end with '\n' so that preamble + header is a multiple of 64.
  const std::size_t preamble = kMagicSize + 2 + 2;
  const std::size_t total = (preamble + header.size() + 1 + kAlignment - 1) / kAlignment * kAlignment;
  header.append(total - preamble - header.size() - 1, ' ');
  header += '\n';
  if (header.size() > 0xFFFF) throw std::invalid_argument("encode_npy: header too long for format 1.0");
  std::vector<std::uint8_t> out;
  out.reserve(total + bytes);
  out.insert(out.end(), kMagic, kMagic + kMagicSize);
  out.push_back(1);  // version 1.0
  out.push_back(0);
  out.push_back(static_cast<std::uint8_t>(header.size() & 0xFF));
  out.push_back(static_cast<std::uint8_t>(header.size() >> 8));
  out.insert(out.end(), header.begin(), header.end());
  const auto* p = static_cast<const std::uint8_t*>(data);
  out.insert(out.end(), p, p + bytes);
  return out;
}

void write_npy(const std::filesystem::path& path, const std::string& dtype, const std::vector<std::uint64_t>& shape,
               const void* data, std::size_t bytes) {
  const std::vector<std::uint8_t> file = encode_npy(dtype, shape, data, bytes);
  write_text_file(path, std::string_view(reinterpret_cast<const char*>(file.data()), file.size()));
}

NpyArray decode_npy(const std::vector<std::uint8_t>& bytes, const std::string& name, bool header_only) {
  auto fail = [&](const std::string& expected) -> NpyArray { throw InputError(name, "", "a .npy file: expected " + expected); };
  if (bytes.size() < kMagicSize + 4 || std::memcmp(bytes.data(), kMagic, kMagicSize) != 0)
    return fail("the magic \\x93NUMPY");
  const std::uint8_t major = bytes[6];
  std::size_t header_len = 0, preamble = 0;
  if (major == 1) {
    header_len = bytes[8] | (std::size_t(bytes[9]) << 8);
    preamble = 10;
  } else if (major == 2 && bytes.size() >= 12) {
    header_len = bytes[8] | (std::size_t(bytes[9]) << 8) | (std::size_t(bytes[10]) << 16) |
                 (std::size_t(bytes[11]) << 24);
    preamble = 12;
  } else {
    return fail("format version 1.0 or 2.0");
  }
  if (bytes.size() < preamble + header_len) return fail("a complete header");
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()) + preamble, header_len);
  NpyArray a = HeaderParser(text, name).parse();
  std::size_t itemsize = 0;
  try {
    itemsize = npy_itemsize(a.dtype);
  } catch (const std::invalid_argument&) {
    return fail("a supported dtype (<f4 <f8 <u4 <i4 <u8 <i8 <u2 |u1), got '" + a.dtype + "'");
  }
  if (header_only) return a;
  const std::uint64_t count = a.element_count();
  if (count > (bytes.size() - preamble - header_len) / itemsize ||
      count * itemsize != bytes.size() - preamble - header_len)
    return fail("data of " + std::to_string(count) + " × " + std::to_string(itemsize) + " bytes after the header, got " +
                std::to_string(bytes.size() - preamble - header_len));
  a.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(preamble + header_len), bytes.end());
  return a;
}

NpyArray read_npy_header(const std::filesystem::path& path) {
  return decode_npy(read_bytes(path, 1 << 16), path.string(), /*header_only=*/true);
}

NpyArray read_npy(const std::filesystem::path& path) { return decode_npy(read_bytes(path, 0), path.string()); }

}  // namespace gi
