#pragma once
// FNV-1a, 64 bits: the checksum of checkpoints and the fingerprint of scenes
// (not a cryptographic hash: it detects damage and changes, not tampering).
#include <cstdint>
#include <string_view>

namespace suffuse::detail {

// `h` continues a hash over the bytes before these (a file written piece by piece).
inline constexpr std::uint64_t fnv1a_basis = 14695981039346656037ull;
inline std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h = fnv1a_basis) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace suffuse::detail
