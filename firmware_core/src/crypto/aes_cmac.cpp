#include "itp/crypto/aes_cmac.hpp"

#include "itp/crypto/constant_time.hpp"

namespace itp::crypto {
namespace {

// x · b in GF(2^128) with the polynomial x^128 + x^7 + x^2 + x + 1, the
// block read big-endian (SP 800-38B): a shift left by one bit; the bit shifted
// out selects 0x87 for the last byte through a mask, not a branch.
AesBlock times_x(const AesBlock& b) {
  AesBlock out{};
  const std::uint8_t carry_mask = static_cast<std::uint8_t>(0u - static_cast<unsigned>(b[0] >> 7));
  for (std::size_t i = 0; i + 1 < kAesBlockBytes; ++i) {  // 15 bytes
    out[i] = static_cast<std::uint8_t>((b[i] << 1) | (b[i + 1] >> 7));
  }
  out[kAesBlockBytes - 1] =
      static_cast<std::uint8_t>((static_cast<unsigned>(b[kAesBlockBytes - 1]) << 1u) ^ (carry_mask & 0x87u));
  return out;
}

}  // namespace

void CmacKey::set(std::span<const std::uint8_t, kAes128KeyBytes> key) {
  aes_.set_key(key);
  AesBlock l{};
  aes_.encrypt(l, l);
  k1_ = times_x(l);
  k2_ = times_x(k1_);
  secure_wipe(l.data(), l.size());
}

void CmacKey::wipe() {
  aes_.wipe();
  secure_wipe(k1_.data(), k1_.size());
  secure_wipe(k2_.data(), k2_.size());
}

void Cmac::absorb_block() {
  // C_i = AES_K(C_{i-1} ^ M_i); XOR commutes with the bit-plane layout.
  state_.xor_with(AesPlanes::load(block_));
  key_->aes_.encrypt(state_);
  fill_ = 0;
}

void Cmac::update(std::span<const std::uint8_t> bytes) {
  // A full block stays buffered until more bytes come: only then is it known
  // not to be the last one (which finish() treats with K1).
  std::size_t i = 0;
  while (i < bytes.size()) {  // each pass consumes >= 1 byte
    if (fill_ == kAesBlockBytes) {
      absorb_block();
    }
    const std::size_t room = kAesBlockBytes - fill_;
    const std::size_t n = room < bytes.size() - i ? room : bytes.size() - i;
    for (std::size_t k = 0; k < n; ++k) {  // <= 16 bytes
      block_[fill_ + k] = bytes[i + k];
    }
    fill_ += n;
    i += n;
  }
}

void Cmac::update(std::uint8_t byte) { update(std::span<const std::uint8_t>(&byte, 1)); }

CmacTag Cmac::finish() {
  // SP 800-38B 6.2: a complete last block is XORed with K1; an incomplete
  // one (the empty message included) is padded with 10* and XORed with K2.
  // Which one depends on the message length only.
  const bool complete = fill_ == kAesBlockBytes;
  const AesBlock& subkey = complete ? key_->k1_ : key_->k2_;
  for (std::size_t i = 0; i < kAesBlockBytes; ++i) {  // 16 bytes
    std::uint8_t m = 0;
    if (i < fill_) {
      m = block_[i];
    } else if (i == fill_) {
      m = 0x80u;
    }
    block_[i] = static_cast<std::uint8_t>(m ^ subkey[i]);
  }
  absorb_block();
  CmacTag tag{};
  state_.store(tag);
  wipe();
  return tag;
}

void Cmac::finish(std::span<std::uint8_t> tag) {
  CmacTag full = finish();
  for (std::size_t i = 0; i < tag.size() && i < kCmacTagBytes; ++i) {  // <= 16 bytes
    tag[i] = full[i];
  }
  secure_wipe(full.data(), full.size());
}

void Cmac::wipe() {
  secure_wipe(state_.plane.data(), sizeof(state_.plane));
  secure_wipe(block_.data(), block_.size());
  fill_ = 0;
}

CmacTag aes_cmac(const CmacKey& key, std::span<const std::uint8_t> message) {
  Cmac mac(key);
  mac.update(message);
  return mac.finish();
}

}  // namespace itp::crypto
