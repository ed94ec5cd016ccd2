#pragma once
// SHA-256 (FIPS 180-4), the hash under the link's message authentication
// (HMAC-SHA-256, itp/crypto/hmac_sha256.hpp). Fixed-size state, no heap, no
// lookup table indexed by data: its running time depends only on the message
// length, never on the bytes (nothing to learn from timing).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace itp::crypto {

inline constexpr std::size_t kSha256BlockBytes = 64;
inline constexpr std::size_t kSha256DigestBytes = 32;
using Sha256Digest = std::array<std::uint8_t, kSha256DigestBytes>;

class Sha256 {
 public:
  Sha256() { reset(); }
  void reset();
  void update(std::span<const std::uint8_t> bytes);
  void update(std::uint8_t byte);
  // Pads and returns the digest; call reset() before hashing anew.
  Sha256Digest finish();

 private:
  void compress();

  std::array<std::uint32_t, 8> h_{};                // chaining value
  std::array<std::uint8_t, kSha256BlockBytes> block_{};  // bytes of the block being filled
  std::size_t fill_ = 0;                            // [bytes] in block_
  std::uint64_t length_ = 0;                        // [bytes] hashed so far
};

Sha256Digest sha256(std::span<const std::uint8_t> bytes);

}  // namespace itp::crypto
