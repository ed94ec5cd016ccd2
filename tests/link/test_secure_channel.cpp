// The SecOC-style secure channel (itp/link/secure_channel.hpp): the
// handshake establishes a session at both ends, sealed messages open at the
// other end only, once, in order; everything else is refused and counted.
// Tags and key derivation are checked against an independent computation
// (OpenSSL's AES-128-CMAC of the documented byte layouts).
#include <doctest/doctest.h>

#include <array>
#include <string>
#include <vector>

#include "itp/link/secure_channel.hpp"
#include "openssl_cmac.hpp"

using namespace itp::link;

namespace {

std::array<std::uint8_t, kKeyBytes> key_of(std::uint8_t seed) {
  std::array<std::uint8_t, kKeyBytes> k{};
  for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<std::uint8_t>(seed * 31 + i);
  return k;
}

std::array<std::uint8_t, kEntropyBytes> entropy_of(std::uint8_t seed) {
  std::array<std::uint8_t, kEntropyBytes> e{};
  for (std::size_t i = 0; i < e.size(); ++i) e[i] = static_cast<std::uint8_t>(seed * 31 + i);
  return e;
}

// Appends bytes one by one (GCC 12's -Warray-bounds misfires on vector::insert at -O3).
template <class Range>
void append(std::vector<std::uint8_t>& v, const Range& bytes) {
  for (const auto b : bytes) v.push_back(static_cast<std::uint8_t>(b));
}

// OpenSSL 3's AES-128-CMAC (tests/support/openssl_cmac.hpp).
std::array<std::uint8_t, 16> openssl_cmac(const std::uint8_t* key, const std::vector<std::uint8_t>& msg) {
  return itp_test::openssl_cmac(key, msg.data(), msg.size());
}

struct Pair {
  SecureChannel host{Role::kHost};
  SecureChannel fw{Role::kFirmware};
  explicit Pair(std::uint8_t key_seed = 1, std::uint8_t entropy_seed = 7) {
    host.set_key(key_of(key_seed));
    fw.set_key(key_of(key_seed));
    fw.set_entropy(entropy_of(entropy_seed));
  }
  // Runs the handshake with the given sequence numbers; true when both ends are in session.
  bool handshake(std::uint16_t open_seq = 1, std::uint16_t confirm_seq = 2) {
    std::array<std::uint8_t, kNonceBytes> nonce{};
    nonce[0] = static_cast<std::uint8_t>(open_seq);
    std::array<std::uint8_t, kHandshakeBytes> open{}, challenge{}, confirm{};
    const std::size_t n = host.start_handshake(nonce, open);
    if (fw.challenge(open_seq, std::span<const std::uint8_t>(open.data(), n), challenge) != AuthStatus::kOk) return false;
    if (host.answer_challenge(open_seq, challenge, confirm_seq, confirm) != AuthStatus::kOk) return false;
    if (fw.confirm(confirm_seq, confirm) != AuthStatus::kOk) return false;
    std::array<std::uint8_t, kSecuredOverhead> accept{};
    const std::size_t m = fw.seal(MessageType::kSessionAccept, confirm_seq, accept, 0);
    std::span<const std::uint8_t> body;
    return m == kSecuredOverhead &&
           host.open(MessageType::kSessionAccept, confirm_seq, accept, body) == AuthStatus::kOk &&
           host.in_session() && fw.in_session();
  }
};

std::vector<std::uint8_t> seal(SecureChannel& ch, MessageType type, std::uint16_t seq, const std::vector<std::uint8_t>& body) {
  std::vector<std::uint8_t> msg(body.size() + kSecuredOverhead);
  std::copy(body.begin(), body.end(), msg.begin() + kFreshnessBytes);
  REQUIRE(ch.seal(type, seq, msg, body.size()) == msg.size());
  return msg;
}

AuthStatus open(SecureChannel& ch, MessageType type, std::uint16_t seq, const std::vector<std::uint8_t>& msg) {
  std::span<const std::uint8_t> body;
  return ch.open(type, seq, msg, body);
}

}  // namespace

TEST_CASE("a handshake establishes a session, and sealed messages open at the other end") {
  Pair p;
  REQUIRE(p.handshake());
  const std::vector<std::uint8_t> body{1, 2, 3, 4, 5};
  const auto req = seal(p.host, MessageType::kPlanRequest, 10, body);
  std::span<const std::uint8_t> opened;
  REQUIRE(p.fw.open(MessageType::kPlanRequest, 10, req, opened) == AuthStatus::kOk);
  CHECK(std::vector<std::uint8_t>(opened.begin(), opened.end()) == body);
  const auto rep = seal(p.fw, MessageType::kPlanReply, 10, body);
  CHECK(open(p.host, MessageType::kPlanReply, 10, rep) == AuthStatus::kOk);
  CHECK(p.fw.counters().accepted == 1);
  CHECK(p.fw.counters().handshakes == 1);
  CHECK(p.host.counters().handshakes == 1);
}

TEST_CASE("the tag is AES-128-CMAC of header, freshness and body under the session key, truncated to 8 bytes") {
  // Independent check of the documented layouts: with a session key computed
  // by OpenSSL's CMAC from K and both nonces (SP 800-108 counter mode),
  // OpenSSL's CMAC gives our tag.
  Pair p;
  std::array<std::uint8_t, kNonceBytes> nh{};
  nh.fill(0x42);
  std::array<std::uint8_t, kHandshakeBytes> open_body{}, challenge{}, confirm{};
  p.host.start_handshake(nh, open_body);
  REQUIRE(p.fw.challenge(1, std::span<const std::uint8_t>(open_body.data(), kNonceBytes), challenge) == AuthStatus::kOk);
  REQUIRE(p.host.answer_challenge(1, challenge, 2, confirm) == AuthStatus::kOk);
  REQUIRE(p.fw.confirm(2, confirm) == AuthStatus::kOk);
  std::array<std::uint8_t, kSecuredOverhead> accept{};
  REQUIRE(p.fw.seal(MessageType::kSessionAccept, 2, accept, 0) == kSecuredOverhead);
  std::span<const std::uint8_t> none;
  REQUIRE(p.host.open(MessageType::kSessionAccept, 2, accept, none) == AuthStatus::kOk);
  const auto k = key_of(1);
  const std::string label = "itplan-link-v2 h2f";
  std::vector<std::uint8_t> kdf{0x01};  // counter i = 1
  append(kdf, label);
  kdf.push_back(0x00);
  append(kdf, std::span<const std::uint8_t>(challenge.data(), 2 * kNonceBytes));  // Nh | Nf
  append(kdf, std::array<std::uint8_t, 2>{0x00, 0x80});  // L = 128 bits, big endian
  const auto k_h2f = openssl_cmac(k.data(), kdf);
  const std::vector<std::uint8_t> body{9, 8, 7};
  const auto msg = seal(p.host, MessageType::kPlanRequest, 0x1234, body);
  std::vector<std::uint8_t> mac_input{kProtocolVersion, 0x20, 0x34, 0x12, static_cast<std::uint8_t>(msg.size()), 0};
  append(mac_input, std::span<const std::uint8_t>(msg.data(), msg.size() - kTagBytes));
  auto tag = openssl_cmac(k_h2f.data(), mac_input);
  CHECK(std::equal(msg.end() - static_cast<long>(kTagBytes), msg.end(), tag.begin()));
  CHECK(msg[0] == 1);  // the first freshness value of the session, little endian
  // The challenge tag: CMAC(K, header of the Challenge (type 0x31, seq 1, length 40) | Nh | Nf).
  std::vector<std::uint8_t> ch_input{kProtocolVersion, 0x31, 1, 0, kHandshakeBytes, 0};
  append(ch_input, std::span<const std::uint8_t>(challenge.data(), 2 * kNonceBytes));
  tag = openssl_cmac(k.data(), ch_input);
  CHECK(std::equal(challenge.begin() + 2 * kNonceBytes, challenge.end(), tag.begin()));
  // The firmware's nonce: the same PRF, label "itplan-link-v2 nonce", context
  // boot entropy | n (u64 LE, the first nonce of this boot: n = 1).
  const std::string nonce_label = "itplan-link-v2 nonce";
  std::vector<std::uint8_t> nonce_input{0x01};
  append(nonce_input, nonce_label);
  nonce_input.push_back(0x00);
  const auto e = entropy_of(7);
  append(nonce_input, e);
  append(nonce_input, std::array<std::uint8_t, 10>{1, 0, 0, 0, 0, 0, 0, 0, 0x00, 0x80});
  const auto nf = openssl_cmac(k.data(), nonce_input);
  CHECK(std::equal(challenge.begin() + kNonceBytes, challenge.begin() + 2 * kNonceBytes, nf.begin()));
  // Keys of another length are no key.
  SecureChannel long_key(Role::kHost);
  long_key.set_key(std::vector<std::uint8_t>(32, 1));
  CHECK_FALSE(long_key.has_key());
}

TEST_CASE("replays, reorderings, other sessions, reflections and wrong keys are refused") {
  Pair p;
  REQUIRE(p.handshake());
  const std::vector<std::uint8_t> body(40, 0x5A);
  const auto m1 = seal(p.host, MessageType::kPlanRequest, 1, body);
  const auto m2 = seal(p.host, MessageType::kPlanRequest, 2, body);
  CHECK(open(p.fw, MessageType::kPlanRequest, 2, m2) == AuthStatus::kOk);
  CHECK(open(p.fw, MessageType::kPlanRequest, 2, m2) == AuthStatus::kStale);  // replay
  CHECK(open(p.fw, MessageType::kPlanRequest, 1, m1) == AuthStatus::kStale);  // older, late
  // The same bytes under another header: type and sequence number are covered.
  const auto m3 = seal(p.host, MessageType::kPlanRequest, 3, body);
  CHECK(open(p.fw, MessageType::kPlanRequest, 4, m3) == AuthStatus::kBadTag);
  CHECK(open(p.fw, MessageType::kQpSolveRequest, 3, m3) == AuthStatus::kBadTag);
  // Reflection: the firmware's own message sent back to it.
  const auto r = seal(p.fw, MessageType::kPlanRequest, 5, body);
  CHECK(open(p.fw, MessageType::kPlanRequest, 5, r) == AuthStatus::kBadTag);
  // A new session: messages of the old one no longer open.
  const auto old = seal(p.host, MessageType::kPlanRequest, 6, body);
  REQUIRE(p.handshake(7, 8));
  CHECK(open(p.fw, MessageType::kPlanRequest, 6, old) == AuthStatus::kBadTag);
  // Another key altogether.
  Pair q(2);
  REQUIRE(q.handshake());
  const auto foreign = seal(q.host, MessageType::kPlanRequest, 9, body);
  CHECK(open(p.fw, MessageType::kPlanRequest, 9, foreign) == AuthStatus::kBadTag);
  CHECK(p.fw.counters().stale == 2);
  CHECK(p.fw.counters().bad_tag == 5);
}

TEST_CASE("a replayed or forged handshake cannot establish a session") {
  Pair p;
  std::array<std::uint8_t, kNonceBytes> nh{};
  std::array<std::uint8_t, kHandshakeBytes> open_body{}, challenge{}, confirm{};
  p.host.start_handshake(nh, open_body);
  REQUIRE(p.fw.challenge(1, std::span<const std::uint8_t>(open_body.data(), kNonceBytes), challenge) == AuthStatus::kOk);
  REQUIRE(p.host.answer_challenge(1, challenge, 2, confirm) == AuthStatus::kOk);
  REQUIRE(p.fw.confirm(2, confirm) == AuthStatus::kOk);
  // The recorded Open and Confirm, replayed: the firmware's new nonce differs.
  std::array<std::uint8_t, kHandshakeBytes> challenge2{};
  REQUIRE(p.fw.challenge(1, std::span<const std::uint8_t>(open_body.data(), kNonceBytes), challenge2) == AuthStatus::kOk);
  CHECK_FALSE(std::equal(challenge.begin(), challenge.end(), challenge2.begin()));
  CHECK(p.fw.confirm(2, confirm) == AuthStatus::kHandshakeRefused);
  // A firmware booted again with the same entropy source would repeat its nonces: the
  // port's entropy must differ per boot (documented); with different entropy they differ.
  Pair rebooted(1, 8);
  std::array<std::uint8_t, kHandshakeBytes> challenge3{};
  REQUIRE(rebooted.fw.challenge(1, std::span<const std::uint8_t>(open_body.data(), kNonceBytes), challenge3) == AuthStatus::kOk);
  CHECK(rebooted.fw.confirm(2, confirm) == AuthStatus::kHandshakeRefused);
  // A Confirm with a flipped tag bit, and one without a challenge.
  Pair f;
  f.host.start_handshake(nh, open_body);
  REQUIRE(f.fw.challenge(1, std::span<const std::uint8_t>(open_body.data(), kNonceBytes), challenge) == AuthStatus::kOk);
  REQUIRE(f.host.answer_challenge(1, challenge, 2, confirm) == AuthStatus::kOk);
  for (std::size_t bit = 0; bit < 8 * kTagBytes; ++bit) {
    auto bad = confirm;
    bad[2 * kNonceBytes + bit / 8] = static_cast<std::uint8_t>(bad[2 * kNonceBytes + bit / 8] ^ (1u << (bit % 8)));
    CHECK(f.fw.confirm(2, bad) == AuthStatus::kHandshakeRefused);
  }
  CHECK_FALSE(f.fw.in_session());
  SecureChannel fresh(Role::kFirmware);
  fresh.set_key(key_of(1));
  fresh.set_entropy(entropy_of(7));
  CHECK(fresh.confirm(2, confirm) == AuthStatus::kHandshakeRefused);
  // A host does not answer a challenge for a nonce it did not send.
  SecureChannel other_host(Role::kHost);
  other_host.set_key(key_of(1));
  CHECK(other_host.answer_challenge(1, challenge, 2, confirm) == AuthStatus::kHandshakeRefused);
}

TEST_CASE("without key, entropy or session nothing is accepted") {
  SecureChannel fw(Role::kFirmware);
  std::array<std::uint8_t, kHandshakeBytes> out{};
  std::array<std::uint8_t, kNonceBytes> nh{};
  CHECK(fw.challenge(1, nh, out) == AuthStatus::kNoKey);
  fw.set_key(key_of(1));
  CHECK(fw.challenge(1, nh, out) == AuthStatus::kNoKey);  // no entropy: nonces could repeat
  fw.set_entropy(entropy_of(3));
  CHECK(fw.challenge(1, nh, out) == AuthStatus::kOk);
  std::vector<std::uint8_t> msg(kSecuredOverhead + 4, 0);
  CHECK(open(fw, MessageType::kPlanRequest, 1, msg) == AuthStatus::kNoSession);
  CHECK(fw.seal(MessageType::kPlanReply, 1, msg, 4) == 0);
  std::vector<std::uint8_t> tiny(kSecuredOverhead - 1, 0);
  CHECK(open(fw, MessageType::kPlanRequest, 1, tiny) == AuthStatus::kMalformed);
}
