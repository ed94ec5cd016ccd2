#pragma once
// Link frames, protocol version 2 (docs/protocol.md). A message (up to 65 535
// bytes) travels as 1..255 segments; each segment is one frame: a 10-byte
// header, the segment's bytes and a CRC-32, COBS-encoded between two 0x00
// delimiters. Segments keep a lost byte from costing a whole message: the
// receiver asks again for the segments it misses (Query / Status).
//
//   offset  size  field
//   0       1     protocol version (kProtocolVersion)
//   1       1     message type (MessageType)
//   2       2     sequence number, little endian (a reply carries its request's)
//   4       2     message length L, little endian
//   6       1     segment index i (0 .. n-1)
//   7       1     segment count n (1 .. 255)
//   8       1     flags (bit 0: poll, the sender's burst ends here)
//   9       1     answer segment size, in units of 8 bytes (0: the responder's largest)
//   10      c     bytes [i S, i S + c) of the message, S = ceil(L / n), c = min(S, L - i S)
//   10+c    4     CRC-32 of bytes [0, 10+c), little endian
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/config.hpp"
#include "itp/link/cobs.hpp"

namespace itp::link {

inline constexpr std::uint8_t kProtocolVersion = 2;
inline constexpr std::size_t kHeaderBytes = 10;
inline constexpr std::size_t kCrcBytes = 4;
inline constexpr std::size_t kMaxSegmentBytes = config::kMaxSegmentBytes;
inline constexpr std::size_t kMaxSegments = 255;
inline constexpr std::size_t kMaxMessageBytes = 0xFFFF;  // the length field's range
inline constexpr std::size_t kAnswerSegmentUnit = 8;     // [bytes] unit of the answer size field
inline constexpr std::size_t kMaxRawFrameBytes = kHeaderBytes + kMaxSegmentBytes + kCrcBytes;
// Encoded frame plus its two 0x00 delimiters: the largest thing on the wire.
inline constexpr std::size_t kMaxWireFrameBytes = cobs_max_encoded_size(kMaxRawFrameBytes) + 2;
inline constexpr std::uint8_t kFlagPoll = 1u;
static_assert(kMaxSegmentBytes >= 64 && kMaxSegmentBytes <= 255 * kAnswerSegmentUnit,
              "a segment size must be expressible in the answer size field");

enum class MessageType : std::uint8_t {
  kPing = 0x01,              // host -> firmware: liveness and counters (not authenticated)
  kPong = 0x02,
  kDiagnosticsRequest = 0x03,  // host -> firmware: stack size and painted peak (empty body; not authenticated)
  kDiagnosticsReply = 0x04,    // firmware -> host: Diagnostics
  kQpSolveRequest = 0x10,    // host -> firmware: solve this QP (test image only)
  kQpSolveReply = 0x11,
  kPlanRequest = 0x20,       // host -> firmware: a Scene; plan one cycle
  kPlanReply = 0x21,         // firmware -> host: the Plan
  kSessionOpen = 0x30,       // host -> firmware: a host nonce; starts the handshake
  kSessionChallenge = 0x31,  // firmware -> host: both nonces, tagged with the long-term key
  kSessionConfirm = 0x32,    // host -> firmware: both nonces, tagged with the long-term key
  kSessionAccept = 0x33,     // firmware -> host: the first message of the new session
  kQuery = 0x7C,             // host -> firmware: which segments do you hold / resend these
  kStatus = 0x7D,            // firmware -> host: the segments of a request received so far
  kAuthError = 0x7E,         // firmware -> host: a request was refused (AuthStatus)
  kError = 0x7F,             // firmware -> host: a request the firmware cannot serve
};

// Zero-initialised by default so that buffers holding one can live in .bss.
struct FrameHeader {
  std::uint8_t version = 0;
  MessageType type{};
  std::uint16_t sequence = 0;
  std::uint16_t message_length = 0;  // [bytes] L of the whole message
  std::uint8_t segment_index = 0;
  std::uint8_t segment_count = 1;
  std::uint8_t flags = 0;
  std::uint8_t answer_units = 0;     // answer segment size / kAnswerSegmentUnit (0: largest)
};

// --- Segment layout: a message of L bytes in n segments of S = ceil(L / n) --
// Every segment but the last holds S bytes, the last one the rest (> 0 unless L = 0).
constexpr std::size_t segment_size(std::size_t length, std::size_t count) {
  return count == 0 ? 0 : (length + count - 1) / count;
}
// The fewest segments of at most `max_segment` bytes (at least one).
constexpr std::size_t segments_for(std::size_t length, std::size_t max_segment) {
  return length == 0 || max_segment == 0 ? 1 : (length + max_segment - 1) / max_segment;
}
constexpr std::size_t segment_offset(std::size_t length, std::size_t count, std::size_t index) {
  return index * segment_size(length, count);
}
constexpr std::size_t segment_length(std::size_t length, std::size_t count, std::size_t index) {
  const std::size_t begin = segment_offset(length, count, index);
  const std::size_t s = segment_size(length, count);
  return begin >= length ? 0 : (length - begin < s ? length - begin : s);
}
// True when (L, n, i) describes a segment a sender following the rules can produce.
constexpr bool valid_layout(std::size_t length, std::size_t count, std::size_t index) {
  if (count < 1 || count > kMaxSegments || index >= count || length > kMaxMessageBytes) {
    return false;
  }
  if (length == 0) {
    return count == 1;
  }
  const std::size_t s = segment_size(length, count);
  return s <= kMaxSegmentBytes && (count - 1) * s < length;
}

// Encodes one segment (header.segment_index of header.segment_count) of
// `message` (header.message_length == message.size()) as a wire frame:
// 0x00, COBS bytes, 0x00. Returns the bytes written, 0 when the layout is
// invalid or `out` too small.
std::size_t encode_segment(const FrameHeader& header, std::span<const std::uint8_t> message,
                           std::span<std::uint8_t> out);

// A whole message of at most kMaxSegmentBytes as one frame (no poll, no answer size).
std::size_t encode_frame(MessageType type, std::uint16_t sequence,
                         std::span<const std::uint8_t> payload, std::span<std::uint8_t> out);

}  // namespace itp::link
