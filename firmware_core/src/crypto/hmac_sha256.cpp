#include "itp/crypto/hmac_sha256.hpp"

#include <array>

namespace itp::crypto {

void HmacKey::set(std::span<const std::uint8_t> key) {
  // RFC 2104: K is padded with zeros to one block (hashed first when longer).
  std::array<std::uint8_t, kSha256BlockBytes> k{};
  if (key.size() > k.size()) {
    const Sha256Digest d = sha256(key);
    for (std::size_t i = 0; i < d.size(); ++i) {  // 32 bytes
      k[i] = d[i];
    }
  } else {
    for (std::size_t i = 0; i < key.size(); ++i) {  // <= 64 bytes
      k[i] = key[i];
    }
  }
  std::array<std::uint8_t, kSha256BlockBytes> pad{};
  for (std::size_t i = 0; i < k.size(); ++i) {  // 64 bytes
    pad[i] = static_cast<std::uint8_t>(k[i] ^ 0x36u);
  }
  inner_.reset();
  inner_.update(pad);
  for (std::size_t i = 0; i < k.size(); ++i) {  // 64 bytes
    pad[i] = static_cast<std::uint8_t>(k[i] ^ 0x5Cu);
  }
  outer_.reset();
  outer_.update(pad);
  k.fill(0);
  pad.fill(0);
}

void HmacKey::clear() {
  inner_.reset();
  outer_.reset();
}

// HMAC(K, m) = H((K ^ opad) || H((K ^ ipad) || m)).
Sha256Digest Hmac::finish() {
  const Sha256Digest inner = inner_.finish();
  outer_.update(inner);
  return outer_.finish();
}

Sha256Digest hmac_sha256(const HmacKey& key, std::span<const std::uint8_t> message) {
  Hmac mac(key);
  mac.update(message);
  return mac.finish();
}

}  // namespace itp::crypto
