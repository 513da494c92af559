#pragma once
// A tile's version: a 64-bit hash of its encoded bytes. The server's strong
// ETag and the live `tile` events carry the same value, so a browser can ask
// for exactly the version it was told about.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace seamap {

inline uint64_t TileVersion(std::string_view bytes) {
  // FNV-1a over 8-byte words (then the tail): fast, stable across builds and
  // platforms, unlike std::hash.
  uint64_t h = 14695981039346656037ull;
  constexpr uint64_t kPrime = 1099511628211ull;
  size_t i = 0;
  for (; i + 8 <= bytes.size(); i += 8) {
    uint64_t w = 0;
    for (int b = 0; b < 8; ++b) w |= uint64_t{static_cast<unsigned char>(bytes[i + b])} << (8 * b);
    h = (h ^ w) * kPrime;
    h ^= h >> 29;
  }
  for (; i < bytes.size(); ++i) h = (h ^ static_cast<unsigned char>(bytes[i])) * kPrime;
  return h ^ bytes.size();
}

inline uint64_t TileVersion(const std::vector<uint8_t>& bytes) {
  return TileVersion(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

// 16 lower-case hex digits.
inline std::string TileVersionHex(uint64_t version) {
  static const char* kDigits = "0123456789abcdef";
  std::string out(16, '0');
  for (int i = 15; i >= 0; --i, version >>= 4) out[i] = kDigits[version & 15];
  return out;
}

}  // namespace seamap
