#include "itp/crypto/sha256.hpp"

namespace itp::crypto {
namespace {

// FIPS 180-4, 4.2.2: the first 32 bits of the fractional parts of the cube
// roots of the first 64 primes. Indexed by the round number only.
constexpr std::array<std::uint32_t, 64> kRound = {
    0x428a2f98u, 0x71374491u, 0xb5c0fbcfu, 0xe9b5dba5u, 0x3956c25bu, 0x59f111f1u, 0x923f82a4u,
    0xab1c5ed5u, 0xd807aa98u, 0x12835b01u, 0x243185beu, 0x550c7dc3u, 0x72be5d74u, 0x80deb1feu,
    0x9bdc06a7u, 0xc19bf174u, 0xe49b69c1u, 0xefbe4786u, 0x0fc19dc6u, 0x240ca1ccu, 0x2de92c6fu,
    0x4a7484aau, 0x5cb0a9dcu, 0x76f988dau, 0x983e5152u, 0xa831c66du, 0xb00327c8u, 0xbf597fc7u,
    0xc6e00bf3u, 0xd5a79147u, 0x06ca6351u, 0x14292967u, 0x27b70a85u, 0x2e1b2138u, 0x4d2c6dfcu,
    0x53380d13u, 0x650a7354u, 0x766a0abbu, 0x81c2c92eu, 0x92722c85u, 0xa2bfe8a1u, 0xa81a664bu,
    0xc24b8b70u, 0xc76c51a3u, 0xd192e819u, 0xd6990624u, 0xf40e3585u, 0x106aa070u, 0x19a4c116u,
    0x1e376c08u, 0x2748774cu, 0x34b0bcb5u, 0x391c0cb3u, 0x4ed8aa4au, 0x5b9cca4fu, 0x682e6ff3u,
    0x748f82eeu, 0x78a5636fu, 0x84c87814u, 0x8cc70208u, 0x90befffau, 0xa4506cebu, 0xbef9a3f7u,
    0xc67178f2u};

// FIPS 180-4, 5.3.3: the initial hash value.
constexpr std::array<std::uint32_t, 8> kInitial = {0x6a09e667u, 0xbb67ae85u, 0x3c6ef372u,
                                                   0xa54ff53au, 0x510e527fu, 0x9b05688cu,
                                                   0x1f83d9abu, 0x5be0cd19u};

constexpr std::uint32_t rotr(std::uint32_t x, int n) {
  return (x >> n) | (x << (32 - n));
}

}  // namespace

void Sha256::reset() {
  h_ = kInitial;
  fill_ = 0;
  length_ = 0;
}

// FIPS 180-4, 6.2.2: one 512-bit block into the chaining value.
void Sha256::compress() {
  std::array<std::uint32_t, 64> w{};
  for (std::size_t t = 0; t < 16; ++t) {  // the block's 16 big-endian words
    w[t] = (static_cast<std::uint32_t>(block_[4 * t]) << 24) |
           (static_cast<std::uint32_t>(block_[4 * t + 1]) << 16) |
           (static_cast<std::uint32_t>(block_[4 * t + 2]) << 8) |
           static_cast<std::uint32_t>(block_[4 * t + 3]);
  }
  for (std::size_t t = 16; t < 64; ++t) {  // message schedule
    const std::uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
    const std::uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
    w[t] = w[t - 16] + s0 + w[t - 7] + s1;
  }
  std::uint32_t a = h_[0], b = h_[1], c = h_[2], d = h_[3];
  std::uint32_t e = h_[4], f = h_[5], g = h_[6], h = h_[7];
  for (std::size_t t = 0; t < 64; ++t) {  // 64 rounds
    const std::uint32_t big_s1 = rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25);
    const std::uint32_t ch = (e & f) ^ (~e & g);
    const std::uint32_t t1 = h + big_s1 + ch + kRound[t] + w[t];
    const std::uint32_t big_s0 = rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22);
    const std::uint32_t maj = (a & b) ^ (a & c) ^ (b & c);
    const std::uint32_t t2 = big_s0 + maj;
    h = g;
    g = f;
    f = e;
    e = d + t1;
    d = c;
    c = b;
    b = a;
    a = t1 + t2;
  }
  h_[0] += a;
  h_[1] += b;
  h_[2] += c;
  h_[3] += d;
  h_[4] += e;
  h_[5] += f;
  h_[6] += g;
  h_[7] += h;
}

void Sha256::update(std::uint8_t byte) {
  block_[fill_++] = byte;
  ++length_;
  if (fill_ == block_.size()) {
    compress();
    fill_ = 0;
  }
}

void Sha256::update(std::span<const std::uint8_t> bytes) {
  std::size_t i = 0;
  while (i < bytes.size()) {  // each pass fills the block or ends the input
    const std::size_t n = bytes.size() - i < block_.size() - fill_ ? bytes.size() - i : block_.size() - fill_;
    for (std::size_t k = 0; k < n; ++k) {  // n <= 64
      block_[fill_ + k] = bytes[i + k];
    }
    fill_ += n;
    i += n;
    length_ += n;
    if (fill_ == block_.size()) {
      compress();
      fill_ = 0;
    }
  }
}

// FIPS 180-4, 5.1.1: a 1 bit, zeros up to 56 mod 64 bytes, the length in bits (64-bit big endian).
Sha256Digest Sha256::finish() {
  const std::uint64_t bits = length_ * 8u;
  update(std::uint8_t{0x80});
  while (fill_ != 56) {  // at most 63 bytes of padding
    update(std::uint8_t{0});
  }
  for (int i = 7; i >= 0; --i) {  // 8 length bytes
    update(static_cast<std::uint8_t>(bits >> (8 * i)));
  }
  Sha256Digest out{};
  for (std::size_t i = 0; i < 8; ++i) {  // 8 big-endian words
    out[4 * i] = static_cast<std::uint8_t>(h_[i] >> 24);
    out[4 * i + 1] = static_cast<std::uint8_t>(h_[i] >> 16);
    out[4 * i + 2] = static_cast<std::uint8_t>(h_[i] >> 8);
    out[4 * i + 3] = static_cast<std::uint8_t>(h_[i]);
  }
  return out;
}

Sha256Digest sha256(std::span<const std::uint8_t> bytes) {
  Sha256 h;
  h.update(bytes);
  return h.finish();
}

}  // namespace itp::crypto
