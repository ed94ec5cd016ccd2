// libFuzzer target: FirmwareService with valid framing and a valid session,
// so that fuzzed bodies reach the Scene decoder, the validation and the
// planner. The harness performs the handshake, then reads the input as
// records:
//   [kind u8][length u16 LE][bytes]
//   kind & 3 == 0: a Scene body, sealed with the session key (so it is accepted)
//   kind & 3 == 1: the bytes as they are, onto the line
//   kind & 3 == 2: a Query body, as a frame
//   kind & 3 == 3: a plain message of type bytes[0] with body bytes[1..]
//   kind >> 2 picks the segment size (32 << (kind >> 2) % 6 bytes).
// Every reply must be valid; a Plan must open, decode and be finite, and an
// invalid_input Plan must carry no trajectory and origin 0.
#include "fuzz_support.hpp"

namespace {

using fuzz::link::MessageType;

std::uint16_t g_seq = 1;

bool handshake(fuzz::Service& svc, fuzz::Replies& out, fuzz::link::SecureChannel& host) {
  std::array<std::uint8_t, fuzz::link::kNonceBytes> nh{};
  nh.fill(0x11);
  std::array<std::uint8_t, fuzz::link::kHandshakeBytes> open{}, confirm{};
  host.start_handshake(nh, open);
  fuzz::send(svc, out, MessageType::kSessionOpen, g_seq, std::span<const std::uint8_t>(open.data(), fuzz::link::kNonceBytes), 1024);
  if (!out.complete || out.type != MessageType::kSessionChallenge) return false;
  const std::uint16_t challenge_seq = g_seq++;
  if (host.answer_challenge(challenge_seq, out.message, g_seq, confirm) != fuzz::link::AuthStatus::kOk) return false;
  out.complete = false;
  fuzz::send(svc, out, MessageType::kSessionConfirm, g_seq, confirm, 1024);
  std::span<const std::uint8_t> none;
  return out.complete && out.type == MessageType::kSessionAccept &&
         host.open(MessageType::kSessionAccept, g_seq++, out.message, none) == fuzz::link::AuthStatus::kOk;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static auto storage = std::make_unique<fuzz::Service>();
  static auto replies = std::make_unique<fuzz::Replies>();
  static const auto k = fuzz::key();
  static const std::array<std::uint8_t, 32> entropy{9, 8, 7};
  static std::vector<std::uint8_t> message(fuzz::link::kMaxMessageBytes);
  fuzz::Service* svc = &fuzz::restart(storage.get(), entropy);
  fuzz::Replies& out = *replies;
  out.reset();
  fuzz::link::SecureChannel host(fuzz::link::Role::kHost);
  host.set_key(k);
  g_seq = 1;
  fuzz::check(handshake(*svc, out, host));
  std::size_t i = 0;
  while (i + 3 <= size) {
    const std::uint8_t kind = data[i];
    const std::size_t len = std::min<std::size_t>(static_cast<std::size_t>(data[i + 1]) | (static_cast<std::size_t>(data[i + 2]) << 8), size - i - 3);
    const std::span<const std::uint8_t> bytes(data + i + 3, len);
    i += 3 + len;
    const std::size_t segment = std::size_t{32} << ((kind >> 2) % 6);
    out.complete = false;
    const std::uint16_t seq = g_seq++;
    switch (kind & 3) {
      case 0: {
        if (len + fuzz::link::kSecuredOverhead > message.size()) break;
        std::copy(bytes.begin(), bytes.end(), message.begin() + fuzz::link::kFreshnessBytes);
        const std::size_t n = host.seal(MessageType::kPlanRequest, seq, message, len);
        fuzz::send(*svc, out, MessageType::kPlanRequest, seq, std::span<const std::uint8_t>(message.data(), n), segment);
        // An accepted Scene is answered with a Plan or an Error, never refused.
        fuzz::check(out.complete && out.sequence == seq &&
                    (out.type == MessageType::kPlanReply || out.type == MessageType::kError));
        if (out.type == MessageType::kPlanReply) fuzz::check_plan(host, out);
        break;
      }
      case 1:
        fuzz::feed(*svc, out, bytes);
        break;
      case 2: {
        std::array<std::uint8_t, fuzz::link::kMaxWireFrameBytes> wire{};
        const std::size_t n = fuzz::link::encode_frame(MessageType::kQuery, seq, bytes.first(std::min<std::size_t>(len, 64)), wire);
        fuzz::feed(*svc, out, std::span<const std::uint8_t>(wire.data(), n));
        break;
      }
      case 3:
        if (len > 0) fuzz::send(*svc, out, static_cast<MessageType>(bytes[0]), seq, bytes.subspan(1), segment);
        break;
    }
  }
  return 0;
}
