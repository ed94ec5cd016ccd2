#include "itp/link/secure_channel.hpp"

#include "itp/crypto/constant_time.hpp"

namespace itp::link {
namespace {

constexpr std::uint8_t kLabelH2f[] = {'i', 't', 'p', 'l', 'a', 'n', '-', 'l', 'i', 'n', 'k',
                                      '-', 'v', '2', ' ', 'h', '2', 'f'};
constexpr std::uint8_t kLabelF2h[] = {'i', 't', 'p', 'l', 'a', 'n', '-', 'l', 'i', 'n', 'k',
                                      '-', 'v', '2', ' ', 'f', '2', 'h'};
constexpr std::uint8_t kLabelNonce[] = {'i', 't', 'p', 'l', 'a', 'n', '-', 'l', 'i', 'n', 'k',
                                        '-', 'v', '2', ' ', 'n', 'o', 'n', 'c', 'e'};

// The frame header fields a tag covers: version, type, sequence, message length.
void mac_header(crypto::Cmac& mac, MessageType type, std::uint16_t seq, std::size_t length) {
  const std::uint8_t h[6] = {kProtocolVersion, static_cast<std::uint8_t>(type),
                             static_cast<std::uint8_t>(seq & 0xFFu), static_cast<std::uint8_t>(seq >> 8),
                             static_cast<std::uint8_t>(length & 0xFFu),
                             static_cast<std::uint8_t>((length >> 8) & 0xFFu)};
  mac.update(h);
}

std::uint64_t read_u64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) {  // 8 bytes, little endian
    v = (v << 8) | p[i];
  }
  return v;
}

// CMAC as a PRF, NIST SP 800-108 counter mode, for one 128-bit output block:
// CMAC(K, [i = 1]_8 | label | 0x00 | context | [L = 128]_16, big endian).
// The context is given in two pieces (nonces, or entropy and counter).
crypto::CmacTag prf(const crypto::CmacKey& key, std::span<const std::uint8_t> label,
                    std::span<const std::uint8_t> context_a, std::span<const std::uint8_t> context_b) {
  constexpr std::uint8_t kCounter = 0x01u;
  constexpr std::uint8_t kSeparator = 0x00u;
  constexpr std::uint8_t kOutputBits[2] = {0x00u, 0x80u};
  crypto::Cmac mac(key);
  mac.update(kCounter);
  mac.update(label);
  mac.update(kSeparator);
  mac.update(context_a);
  mac.update(context_b);
  mac.update(kOutputBits);
  return mac.finish();
}

template <std::size_t N>
void copy_to(std::array<std::uint8_t, N>& dst, std::span<const std::uint8_t> src) {
  for (std::size_t i = 0; i < N; ++i) {  // N bytes
    dst[i] = src[i];
  }
}

// A handshake body (Challenge and Confirm alike): Nh ‖ Nf ‖ tag.
template <std::size_t N, std::size_t T>
void write_handshake(std::span<std::uint8_t> out, const std::array<std::uint8_t, N>& nh,
                     const std::array<std::uint8_t, N>& nf, const std::array<std::uint8_t, T>& tag) {
  for (std::size_t i = 0; i < N; ++i) {  // N bytes each
    out[i] = nh[i];
    out[N + i] = nf[i];
  }
  for (std::size_t i = 0; i < T; ++i) {  // T bytes
    out[2 * N + i] = tag[i];
  }
}

}  // namespace

const char* to_string(AuthStatus status) {
  switch (status) {
    case AuthStatus::kOk: return "ok";
    case AuthStatus::kBadTag: return "bad_tag";
    case AuthStatus::kStale: return "stale_freshness";
    case AuthStatus::kNoSession: return "no_session";
    case AuthStatus::kNoKey: return "no_key";
    case AuthStatus::kHandshakeRefused: return "handshake_refused";
    case AuthStatus::kMalformed: return "malformed";
  }
  return "unknown";
}

void SecureChannel::set_key(std::span<const std::uint8_t> key) {
  end_session();
  has_key_ = key.size() == kKeyBytes;
  if (has_key_) {
    long_term_.set(key.first<kKeyBytes>());
  } else {
    long_term_.wipe();
  }
}

void SecureChannel::set_entropy(std::span<const std::uint8_t> entropy) {
  has_entropy_ = entropy.size() == kEntropyBytes;
  if (has_entropy_) {
    copy_to(entropy_, entropy);
  }
}

void SecureChannel::end_session() {
  session_ = false;
  handshake_ = false;
  pending_keys_ = false;
  tx_key_.wipe();
  rx_key_.wipe();
  pending_tx_.wipe();
  pending_rx_.wipe();
  tx_fresh_ = 0;
  rx_fresh_ = 0;
}

AuthStatus SecureChannel::refuse(AuthStatus why) {
  switch (why) {
    case AuthStatus::kBadTag: ++counters_.bad_tag; break;
    case AuthStatus::kStale: ++counters_.stale; break;
    case AuthStatus::kNoSession: ++counters_.no_session; break;
    case AuthStatus::kMalformed: ++counters_.malformed; break;
    case AuthStatus::kNoKey: ++counters_.no_key; break;
    case AuthStatus::kHandshakeRefused: ++counters_.handshakes_refused; break;
    case AuthStatus::kOk: break;
  }
  return why;
}

std::size_t SecureChannel::seal(MessageType type, std::uint16_t seq, std::span<std::uint8_t> message,
                                std::size_t body_bytes) {
  const std::size_t length = body_bytes + kSecuredOverhead;
  if (!session_ || length > message.size() || length > kMaxMessageBytes) {
    return 0;
  }
  const std::uint64_t fresh = ++tx_fresh_;
  for (std::size_t i = 0; i < kFreshnessBytes; ++i) {  // 8 bytes, little endian
    message[i] = static_cast<std::uint8_t>(fresh >> (8 * i));
  }
  crypto::Cmac mac(tx_key_);
  mac_header(mac, type, seq, length);
  mac.update(message.first(kFreshnessBytes + body_bytes));
  mac.finish(message.subspan(kFreshnessBytes + body_bytes, kTagBytes));  // truncated tag
  return length;
}

AuthStatus SecureChannel::open(MessageType type, std::uint16_t seq, std::span<const std::uint8_t> message,
                               std::span<const std::uint8_t>& body) {
  body = {};
  if (!has_key_) {
    return refuse(AuthStatus::kNoKey);
  }
  if (message.size() < kSecuredOverhead) {
    return refuse(AuthStatus::kMalformed);
  }
  // The host checks the firmware's SessionAccept with the keys it derived
  // from the Challenge; the session starts only if that succeeds.
  const bool accept = role_ == Role::kHost && type == MessageType::kSessionAccept;
  if (accept ? !pending_keys_ : !session_) {
    return refuse(AuthStatus::kNoSession);
  }
  const std::size_t body_bytes = message.size() - kSecuredOverhead;
  crypto::Cmac mac(accept ? pending_rx_ : rx_key_);
  mac_header(mac, type, seq, message.size());
  mac.update(message.first(kFreshnessBytes + body_bytes));
  Tag tag{};
  mac.finish(tag);
  if (!crypto::equal_constant_time(std::span<const std::uint8_t>(tag.data(), kTagBytes),
                                   message.subspan(kFreshnessBytes + body_bytes, kTagBytes))) {
    return refuse(AuthStatus::kBadTag);
  }
  const std::uint64_t fresh = read_u64(message.data());
  if (accept) {
    tx_key_ = pending_tx_;
    rx_key_ = pending_rx_;
    pending_tx_.wipe();
    pending_rx_.wipe();
    tx_fresh_ = 0;
    rx_fresh_ = 0;
    session_ = true;
    pending_keys_ = false;
    handshake_ = false;
    ++counters_.handshakes;
  }
  if (fresh <= rx_fresh_) {
    return refuse(AuthStatus::kStale);
  }
  rx_fresh_ = fresh;
  body = message.subspan(kFreshnessBytes, body_bytes);
  ++counters_.accepted;
  return AuthStatus::kOk;
}

SecureChannel::Tag SecureChannel::handshake_tag(MessageType type, std::uint16_t seq, const Nonce& nh,
                                                const Nonce& nf) const {
  crypto::Cmac mac(long_term_);
  mac_header(mac, type, seq, kHandshakeBytes);
  mac.update(nh);
  mac.update(nf);
  Tag t{};
  mac.finish(t);  // truncated tag
  return t;
}

void SecureChannel::derive(const Nonce& nh, const Nonce& nf, crypto::CmacKey& tx, crypto::CmacKey& rx) const {
  static_assert(crypto::kCmacTagBytes == crypto::kAes128KeyBytes, "one PRF block is one session key");
  crypto::CmacTag k_h2f = prf(long_term_, kLabelH2f, nh, nf);
  crypto::CmacTag k_f2h = prf(long_term_, kLabelF2h, nh, nf);
  tx.set(role_ == Role::kHost ? k_h2f : k_f2h);
  rx.set(role_ == Role::kHost ? k_f2h : k_h2f);
  crypto::secure_wipe(k_h2f.data(), k_h2f.size());
  crypto::secure_wipe(k_f2h.data(), k_f2h.size());
}

std::size_t SecureChannel::start_handshake(std::span<const std::uint8_t> host_nonce, std::span<std::uint8_t> out) {
  if (host_nonce.size() != kNonceBytes || out.size() < kNonceBytes) {
    return 0;
  }
  copy_to(host_nonce_, host_nonce);
  handshake_ = true;
  pending_keys_ = false;
  for (std::size_t i = 0; i < kNonceBytes; ++i) {  // 16 bytes
    out[i] = host_nonce_[i];
  }
  return kNonceBytes;
}

AuthStatus SecureChannel::answer_challenge(std::uint16_t challenge_seq, std::span<const std::uint8_t> challenge,
                                           std::uint16_t confirm_seq, std::span<std::uint8_t> out) {
  if (!has_key_) {
    return refuse(AuthStatus::kNoKey);
  }
  if (challenge.size() != kHandshakeBytes || out.size() < kHandshakeBytes) {
    return refuse(AuthStatus::kMalformed);
  }
  Nonce nh{};
  Nonce nf{};
  copy_to(nh, challenge.first(kNonceBytes));
  copy_to(nf, challenge.subspan(kNonceBytes, kNonceBytes));
  const Tag expected = handshake_tag(MessageType::kSessionChallenge, challenge_seq, nh, nf);
  // Our nonce must come back (else it answers another handshake, maybe a replay).
  if (!handshake_ || !crypto::equal_constant_time(nh, host_nonce_) ||
      !crypto::equal_constant_time(expected, challenge.subspan(2 * kNonceBytes, kTagBytes))) {
    return refuse(AuthStatus::kHandshakeRefused);
  }
  fw_nonce_ = nf;
  derive(nh, nf, pending_tx_, pending_rx_);
  pending_keys_ = true;
  write_handshake(out, nh, nf, handshake_tag(MessageType::kSessionConfirm, confirm_seq, nh, nf));
  return AuthStatus::kOk;
}

AuthStatus SecureChannel::challenge(std::uint16_t seq, std::span<const std::uint8_t> open_body,
                                    std::span<std::uint8_t> out) {
  if (!has_key_ || !has_entropy_) {
    return refuse(AuthStatus::kNoKey);
  }
  if (open_body.size() != kNonceBytes || out.size() < kHandshakeBytes) {
    return refuse(AuthStatus::kMalformed);
  }
  copy_to(host_nonce_, open_body);
  // A fresh firmware nonce for every challenge: a Confirm recorded earlier
  // (this boot or another) names another nonce and is refused.
  ++nonces_made_;
  std::uint8_t counter[8];
  for (std::size_t i = 0; i < 8; ++i) {  // 8 bytes, little endian
    counter[i] = static_cast<std::uint8_t>(nonces_made_ >> (8 * i));
  }
  static_assert(crypto::kCmacTagBytes == kNonceBytes, "one PRF block is one nonce");
  fw_nonce_ = prf(long_term_, kLabelNonce, entropy_, counter);
  handshake_ = true;
  write_handshake(out, host_nonce_, fw_nonce_,
                  handshake_tag(MessageType::kSessionChallenge, seq, host_nonce_, fw_nonce_));
  return AuthStatus::kOk;
}

AuthStatus SecureChannel::confirm(std::uint16_t seq, std::span<const std::uint8_t> confirm_body) {
  if (!has_key_ || !has_entropy_) {
    return refuse(AuthStatus::kNoKey);
  }
  if (confirm_body.size() != kHandshakeBytes) {
    return refuse(AuthStatus::kMalformed);
  }
  const Tag expected = handshake_tag(MessageType::kSessionConfirm, seq, host_nonce_, fw_nonce_);
  if (!handshake_ || !crypto::equal_constant_time(confirm_body.first(kNonceBytes), host_nonce_) ||
      !crypto::equal_constant_time(confirm_body.subspan(kNonceBytes, kNonceBytes), fw_nonce_) ||
      !crypto::equal_constant_time(expected, confirm_body.subspan(2 * kNonceBytes, kTagBytes))) {
    return refuse(AuthStatus::kHandshakeRefused);
  }
  derive(host_nonce_, fw_nonce_, tx_key_, rx_key_);
  tx_fresh_ = 0;
  rx_fresh_ = 0;
  session_ = true;
  handshake_ = false;  // this nonce pair is spent
  ++counters_.handshakes;
  return AuthStatus::kOk;
}

}  // namespace itp::link
