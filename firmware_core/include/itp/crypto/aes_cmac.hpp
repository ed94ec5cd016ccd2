#pragma once
// AES-128-CMAC (NIST SP 800-38B, RFC 4493): the link's message
// authentication code (docs/protocol.md, "Security"), and, as a PRF, its key
// derivation (SP 800-108 counter mode, link/secure_channel.cpp).
//
// A key is prepared once (the expanded AES key and the subkeys K1, K2); a MAC
// then costs one AES encryption per started 16-byte block of the message (at
// least one). The chaining value stays in bit planes between blocks
// (itp/crypto/aes128.hpp), so only message blocks are converted. No heap, no
// table, no branch on key or data: the time depends on the message length
// only. Key material is overwritten by the destructors (or wipe()).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/crypto/aes128.hpp"

namespace itp::crypto {

inline constexpr std::size_t kCmacTagBytes = 16;
using CmacTag = std::array<std::uint8_t, kCmacTagBytes>;

// A key ready for CMAC: the AES-128 round keys and the subkeys (~210 bytes).
class CmacKey {
 public:
  CmacKey() = default;
  explicit CmacKey(std::span<const std::uint8_t, kAes128KeyBytes> key) { set(key); }
  CmacKey(const CmacKey&) = default;
  CmacKey& operator=(const CmacKey&) = default;
  ~CmacKey() { wipe(); }

  // SP 800-38B 6.1: L = AES_K(0^128), K1 = L·x, K2 = K1·x in GF(2^128)
  // (shift left by one bit, and XOR 0x87 into the last byte when the bit
  // shifted out was 1, by a mask rather than a branch).
  void set(std::span<const std::uint8_t, kAes128KeyBytes> key);
  // Overwrites round keys and subkeys (a wiped key still computes, with the
  // all-zero round keys: callers track whether a key is set).
  void wipe();

 private:
  friend class Cmac;
  Aes128 aes_;
  AesBlock k1_{};  // for a complete last block
  AesBlock k2_{};  // for a padded last block
};

// One MAC computation: construct with a key (init), update() with the
// message in any pieces, then finish(). The key must outlive the Cmac.
class Cmac {
 public:
  explicit Cmac(const CmacKey& key) : key_(&key) {}
  Cmac(const Cmac&) = delete;
  Cmac& operator=(const Cmac&) = delete;
  ~Cmac() { wipe(); }

  void update(std::span<const std::uint8_t> bytes);
  void update(std::uint8_t byte);
  // The tag over everything given to update(). Call once.
  CmacTag finish();
  // The first tag.size() (<= 16) bytes of the tag: a truncated MAC.
  void finish(std::span<std::uint8_t> tag);

 private:
  void absorb_block();  // the buffered block, not the last one
  void wipe();

  const CmacKey* key_;
  AesPlanes state_{};        // chaining value C_i (starts at 0)
  AesBlock block_{};         // bytes of the block not yet absorbed
  std::size_t fill_ = 0;     // [bytes] in block_, 0..16
};

CmacTag aes_cmac(const CmacKey& key, std::span<const std::uint8_t> message);

}  // namespace itp::crypto
