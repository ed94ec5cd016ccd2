#pragma once
// HMAC-SHA-256 (RFC 2104, FIPS 198-1): the link's message authentication
// code (docs/protocol.md, "Security"). A key is prepared once (its inner and
// outer hash states after K xor ipad and K xor opad), so each MAC costs the
// message's blocks plus two: about 4 400 Cortex-M7 instructions per 64 bytes
// (QEMU -icount; docs/protocol.md).
// No heap, no data-dependent table or branch; tags are compared in constant
// time.
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/crypto/constant_time.hpp"
#include "itp/crypto/sha256.hpp"

namespace itp::crypto {

// A key ready for HMAC. Copyable (two hash states, ~220 bytes).
class HmacKey {
 public:
  HmacKey() = default;
  explicit HmacKey(std::span<const std::uint8_t> key) { set(key); }
  // Any length; a key longer than one block is hashed first (RFC 2104).
  void set(std::span<const std::uint8_t> key);
  // Forgets the key (both states back to the empty hash).
  void clear();

 private:
  friend class Hmac;
  Sha256 inner_;  // after absorbing K xor 0x36..
  Sha256 outer_;  // after absorbing K xor 0x5c..
};

// One MAC computation: update() with the message, then finish().
class Hmac {
 public:
  explicit Hmac(const HmacKey& key) : inner_(key.inner_), outer_(key.outer_) {}
  void update(std::span<const std::uint8_t> bytes) { inner_.update(bytes); }
  void update(std::uint8_t byte) { inner_.update(byte); }
  Sha256Digest finish();

 private:
  Sha256 inner_;
  Sha256 outer_;
};

Sha256Digest hmac_sha256(const HmacKey& key, std::span<const std::uint8_t> message);

}  // namespace itp::crypto
