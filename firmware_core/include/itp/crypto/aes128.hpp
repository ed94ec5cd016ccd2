#pragma once
// AES-128 block encryption (FIPS 197), bitsliced and constant time: the
// cipher under the link's MAC (AES-128-CMAC, itp/crypto/aes_cmac.hpp).
//
// Why bitsliced: a table-driven AES (T-tables, or an S-box array indexed by
// state bytes) reads memory at addresses that depend on key and data; on a
// core with a data cache (the Cortex-M7) the access times leak the key. Here
// the 16 state bytes are held as 8 bit planes (plane b holds bit b of every
// byte), and SubBytes is a Boolean circuit over the planes (Boyar and
// Peralta's 113-gate S-box circuit, 32 AND), so every byte goes through the
// same instructions: no table, no secret-dependent branch or address, no
// multiplication whose time depends on data. Key expansion uses the same
// circuit. Running time depends only on how many blocks are encrypted.
//
// Layout of a plane: state byte j (input byte j, row j % 4, column j / 4)
// sits at bit j; the 16 bits are repeated in the upper half-word, so that a
// rotation of the 16-bit pattern is one 32-bit rotation (ShiftRows,
// MixColumns).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace itp::crypto {

inline constexpr std::size_t kAesBlockBytes = 16;
inline constexpr std::size_t kAes128KeyBytes = 16;
inline constexpr std::size_t kAes128Rounds = 10;
using AesBlock = std::array<std::uint8_t, kAesBlockBytes>;

// A block in bit planes (see above): plane b, bit j = bit b of byte j.
struct AesPlanes {
  std::array<std::uint32_t, 8> plane{};

  static AesPlanes load(std::span<const std::uint8_t, kAesBlockBytes> bytes);
  void store(std::span<std::uint8_t, kAesBlockBytes> bytes) const;
  // XOR of two blocks is XOR of their planes.
  void xor_with(const AesPlanes& other) {
    for (std::size_t b = 0; b < plane.size(); ++b) {  // 8 planes
      plane[b] ^= other.plane[b];
    }
  }
};

// An expanded AES-128 key (11 round keys in bit planes, 176 bytes). The
// destructor and wipe() overwrite the round keys.
class Aes128 {
 public:
  Aes128() = default;
  explicit Aes128(std::span<const std::uint8_t, kAes128KeyBytes> key) { set_key(key); }
  Aes128(const Aes128&) = default;
  Aes128& operator=(const Aes128&) = default;
  ~Aes128() { wipe(); }

  void set_key(std::span<const std::uint8_t, kAes128KeyBytes> key);
  void wipe();

  // Encrypts in place, in bit planes (CMAC chains blocks without leaving them).
  void encrypt(AesPlanes& state) const;
  // Encrypts one block of bytes (`in` and `out` may be the same).
  void encrypt(std::span<const std::uint8_t, kAesBlockBytes> in, std::span<std::uint8_t, kAesBlockBytes> out) const;

 private:
  // Round key r, plane b: 16 bits (the repeated upper half is added on use).
  std::array<std::array<std::uint16_t, 8>, kAes128Rounds + 1> round_keys_{};
};

// The S-box circuit on its own, on 8 bit planes (bit b of each input byte in
// planes[b]; any number of bytes, one per bit position). For tests and the key schedule.
void aes_sub_bytes_planes(std::array<std::uint32_t, 8>& planes);

}  // namespace itp::crypto
