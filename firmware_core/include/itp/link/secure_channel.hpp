#pragma once
// Authenticated, replay-proof messages in the manner of AUTOSAR SecOC
// (docs/protocol.md, "Security"). A secured message is
//
//   freshness (u64 LE) | body | tag (first 8 bytes of AES-128-CMAC)
//
// where the tag covers the frame header's version, type, sequence number and
// message length, the freshness value and the body, under this session's key
// for the direction. A receiver accepts a message only with a valid tag and a
// freshness value above the last one it accepted (a counter per direction,
// gaps allowed: messages get lost).
//
// A session starts with a handshake under the long-term key K, which both
// nonces make fresh; a replayed handshake cannot complete:
//   host -> SessionOpen     Nh
//   fw   -> SessionChallenge Nh | Nf | tag_K(header, Nh, Nf)
//   host -> SessionConfirm  Nh | Nf | tag_K(header, Nh, Nf)   (another type in the header)
//   fw   -> SessionAccept   secured with the new firmware-to-host key, empty body
// tag_K is the truncated AES-128-CMAC under K. Session keys come from CMAC as
// a PRF in SP 800-108 counter mode (one 128-bit block, so i = 1):
//   K_dir = CMAC(K, 0x01 | "itplan-link-v2 h2f" or "... f2h" | 0x00 | Nh | Nf | 0x0080).
// The firmware's nonce is the same PRF with label "itplan-link-v2 nonce" and
// context boot entropy | n (u64 LE), unique per boot as long as the port's
// entropy is.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/crypto/aes_cmac.hpp"
#include "itp/link/frame.hpp"

namespace itp::link {

inline constexpr std::size_t kKeyBytes = 16;        // long-term link key K (AES-128)
inline constexpr std::size_t kEntropyBytes = 32;    // per-boot entropy from the port
inline constexpr std::size_t kNonceBytes = 16;
inline constexpr std::size_t kFreshnessBytes = 8;
inline constexpr std::size_t kTagBytes = 8;         // truncated AES-128-CMAC (64 bits)
inline constexpr std::size_t kSecuredOverhead = kFreshnessBytes + kTagBytes;
inline constexpr std::size_t kHandshakeBytes = 2 * kNonceBytes + kTagBytes;  // Challenge, Confirm

// The message types that travel secured (every other type is a plain body).
constexpr bool is_secured(MessageType type) {
  return type == MessageType::kPlanRequest || type == MessageType::kPlanReply ||
         type == MessageType::kQpSolveRequest || type == MessageType::kQpSolveReply ||
         type == MessageType::kSessionAccept;
}

// Why a message was refused (AuthError code on the wire; 0 never travels).
enum class AuthStatus : std::uint8_t {
  kOk = 0,
  kBadTag = 1,            // the tag does not match: forged, corrupted or another session's
  kStale = 2,             // freshness not above the last accepted: a replay or reordering
  kNoSession = 3,         // no session yet (or it was lost): do the handshake
  kNoKey = 4,             // this end holds no key: it cannot authenticate anything
  kHandshakeRefused = 5,  // a Challenge or Confirm that does not check out
  kMalformed = 6,         // too short to hold freshness and tag, or a handshake body of the wrong size
};
const char* to_string(AuthStatus status);

struct AuthCounters {
  std::uint32_t accepted = 0;            // secured messages opened
  std::uint32_t bad_tag = 0;
  std::uint32_t stale = 0;
  std::uint32_t no_session = 0;
  std::uint32_t handshakes = 0;          // sessions established
  std::uint32_t handshakes_refused = 0;  // Challenge / Confirm that did not check out
  std::uint32_t malformed = 0;           // too short for freshness and tag, bad handshake size
  std::uint32_t no_key = 0;              // refused because this end holds no key (or no entropy)

  std::uint32_t refused() const {
    return bad_tag + stale + no_session + handshakes_refused + malformed + no_key;
  }
};

enum class Role : std::uint8_t { kHost, kFirmware };

class SecureChannel {
 public:
  explicit SecureChannel(Role role) : role_(role) {}

  // The long-term key K (kKeyBytes; any other length: no key). Ends any
  // session and handshake.
  void set_key(std::span<const std::uint8_t> key);
  // Firmware: entropy that differs on every boot (the port's TRNG or HSM).
  // Without it the firmware refuses every handshake (kNoKey).
  void set_entropy(std::span<const std::uint8_t> entropy);
  bool has_key() const { return has_key_; }
  bool in_session() const { return session_; }
  void end_session();

  // Seals in place: the caller wrote the body at message[kFreshnessBytes,
  // kFreshnessBytes + body_bytes); writes the next freshness value in front
  // and the tag behind. Returns the message length, 0 without a session
  // (kSessionAccept: the firmware's new one) or room.
  std::size_t seal(MessageType type, std::uint16_t sequence, std::span<std::uint8_t> message,
                   std::size_t body_bytes);
  // Checks a received secured message; on kOk `body` views its body and its
  // freshness value is consumed. Counted in counters().
  AuthStatus open(MessageType type, std::uint16_t sequence, std::span<const std::uint8_t> message,
                  std::span<const std::uint8_t>& body);

  // --- Handshake, host side ---------------------------------------------
  // The SessionOpen body (kNonceBytes) for a fresh random `host_nonce`.
  std::size_t start_handshake(std::span<const std::uint8_t> host_nonce, std::span<std::uint8_t> out);
  // Checks the firmware's Challenge (sent with `challenge_seq`) and writes the
  // Confirm body (to be sent with `confirm_seq`). The new keys wait until the
  // firmware's SessionAccept opens with them.
  AuthStatus answer_challenge(std::uint16_t challenge_seq, std::span<const std::uint8_t> challenge,
                              std::uint16_t confirm_seq, std::span<std::uint8_t> out);

  // --- Handshake, firmware side -----------------------------------------
  // Answers a SessionOpen body (sequence `seq`) with a Challenge body in `out`.
  AuthStatus challenge(std::uint16_t seq, std::span<const std::uint8_t> open_body,
                       std::span<std::uint8_t> out);
  // Checks a Confirm (sequence `seq`); on kOk the new session is in force
  // (both freshness counters at 0) and seal(kSessionAccept) answers it.
  AuthStatus confirm(std::uint16_t seq, std::span<const std::uint8_t> confirm_body);

  const AuthCounters& counters() const { return counters_; }
  // The last freshness value accepted from the peer (0: none in this session).
  std::uint64_t last_received_freshness() const { return rx_fresh_; }

 private:
  using Nonce = std::array<std::uint8_t, kNonceBytes>;
  using Tag = std::array<std::uint8_t, kTagBytes>;

  Tag handshake_tag(MessageType type, std::uint16_t seq, const Nonce& nh, const Nonce& nf) const;
  void derive(const Nonce& nh, const Nonce& nf, crypto::CmacKey& tx, crypto::CmacKey& rx) const;
  AuthStatus refuse(AuthStatus why);

  Role role_;
  crypto::CmacKey long_term_;
  bool has_key_ = false;
  // The session in force.
  crypto::CmacKey tx_key_;
  crypto::CmacKey rx_key_;
  std::uint64_t tx_fresh_ = 0;  // last freshness value sent
  std::uint64_t rx_fresh_ = 0;  // last freshness value accepted
  bool session_ = false;
  // Handshake in progress: both nonces; the host's candidate keys.
  Nonce host_nonce_{};
  Nonce fw_nonce_{};
  bool handshake_ = false;
  crypto::CmacKey pending_tx_;
  crypto::CmacKey pending_rx_;
  bool pending_keys_ = false;
  // Firmware nonce source.
  std::array<std::uint8_t, kEntropyBytes> entropy_{};
  bool has_entropy_ = false;  // without it a firmware refuses handshakes (its nonces could repeat)
  std::uint64_t nonces_made_ = 0;
  AuthCounters counters_{};
};

}  // namespace itp::link
