// The harness's buffer hash: 64 bits over a run of 32-bit words, built so the
// GPU computes it in parallel with the same bits as a CPU loop.
//
// The words are cut into chunks of WORD_HASH_CHUNK. Each chunk is hashed on
// its own by two MurmurHash3-x86-32 lanes (Appleby; distinct multipliers per
// lane) seeded with the chunk's index, so moving a word to another chunk
// changes the hash. The chunk hashes are added modulo 2^32 per lane: integer
// addition is associative and commutative, so integer atomics on the GPU, in
// whatever order the invocations run, give the sum a CPU loop gives. The two
// sums and the word count are finalised with MurmurHash3's fmix32.
//
// Not cryptographic; built to tell two runs' bits apart (a random change
// leaves both lanes' sums equal with probability about 2^-64).
// buffer_hash.comp is the GPU side; word_hash_bytes (C++ only) the CPU side.
#ifndef GI_SHARED_WORD_HASH_H
#define GI_SHARED_WORD_HASH_H
#include "host_device.h"

GI_SHADER_BEGIN

GI_CONST uint WORD_HASH_CHUNK = 16u;  // words per chunk (one GPU invocation's share)

GI_FN uint word_hash_rotl(uint x, uint r) { return (x << r) | (x >> (32u - r)); }

GI_FN uint word_hash_fmix(uint h) {
  h ^= h >> 16u;
  h *= 0x85ebca6bu;
  h ^= h >> 13u;
  h *= 0xc2b2ae35u;
  h ^= h >> 16u;
  return h;
}

// One MurmurHash3 block step of lane state h with word k (multipliers c1, c2).
GI_FN uint word_hash_step(uint h, uint k, uint c1, uint c2) {
  k *= c1;
  k = word_hash_rotl(k, 15u);
  k *= c2;
  h ^= k;
  h = word_hash_rotl(h, 13u);
  return h * 5u + 0xe6546b64u;
}

// A chunk's two lanes before its words: seeded with its index.
GI_FN uvec2 word_hash_chunk_begin(uint chunk) {
  uvec2 h;
  h.x = word_hash_fmix(chunk * 2u + 1u);
  h.y = word_hash_fmix(chunk * 2u + 2u) ^ 0x9e3779b9u;
  return h;
}

GI_FN uvec2 word_hash_chunk_add(uvec2 h, uint word) {
  uvec2 r;
  r.x = word_hash_step(h.x, word, 0xcc9e2d51u, 0x1b873593u);
  r.y = word_hash_step(h.y, word, 0x85ebca77u, 0xc2b2ae3du);
  return r;
}

// The chunk's contribution to the sums, after its `words` words.
GI_FN uvec2 word_hash_chunk_end(uvec2 h, uint words) {
  uvec2 r;
  r.x = word_hash_fmix(h.x ^ words);
  r.y = word_hash_fmix(h.y ^ (words * 0x27d4eb2fu));
  return r;
}

// The hash of `total_words` words from the per-lane sums of their chunks;
// x is the low 32 bits, y the high.
GI_FN uvec2 word_hash_finish(uvec2 sums, uint total_words) {
  uvec2 r;
  r.x = word_hash_fmix(sums.x ^ total_words);
  r.y = word_hash_fmix(sums.y + r.x * 0x9e3779b1u);
  return r;
}

GI_SHADER_END

#ifdef __cplusplus
#include <cstddef>
#include <cstring>
#include <string>

namespace gi::shader {

// Names this hash where hashes are kept (summary.json's "hashes", baselines):
// hashes of two schemes say nothing about each other's bits.
inline constexpr const char* WORD_HASH_SCHEME = "gi-word-hash-v1";
// What summaries, baselines and captures written before 2026-12-03 hashed
// with (XXH3-64 of the bytes, on the CPU); their records name no scheme.
inline constexpr const char* XXH3_HASH_SCHEME = "xxh3-64";

// The lane sums of `bytes` bytes (a whole number of words; a last partial
// word is zero-padded), as buffer_hash.comp accumulates them.
inline uvec2 word_hash_sums(const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  const std::size_t words = (bytes + 3) / 4;
  uvec2 sums(0u);
  for (std::size_t first = 0, chunk = 0; first < words; first += WORD_HASH_CHUNK, ++chunk) {
    const std::size_t n = words - first < WORD_HASH_CHUNK ? words - first : WORD_HASH_CHUNK;
    uvec2 h = word_hash_chunk_begin(uint(chunk));
    for (std::size_t i = 0; i < n; ++i) {
      uint w = 0;
      const std::size_t at = (first + i) * 4;
      std::memcpy(&w, p + at, bytes - at < 4 ? bytes - at : 4);
      h = word_hash_chunk_add(h, w);
    }
    sums += word_hash_chunk_end(h, uint(n));
  }
  return sums;
}

// The 64-bit hash as 16 hex digits (high word first).
inline std::string word_hash_hex(uvec2 hash) {
  static const char* digits = "0123456789abcdef";
  std::string s(16, '0');
  const unsigned long long v = (static_cast<unsigned long long>(hash.y) << 32) | hash.x;
  for (int i = 0; i < 16; ++i) s[15 - i] = digits[(v >> (4 * i)) & 15u];
  return s;
}

// The hash of `bytes` bytes, 16 hex digits: what the GPU gives for the same buffer.
inline std::string word_hash_bytes(const void* data, std::size_t bytes) {
  return word_hash_hex(word_hash_finish(word_hash_sums(data, bytes), uint((bytes + 3) / 4)));
}

}  // namespace gi::shader
#endif

#endif
