#pragma once
// Link frames (docs/protocol.md): a 6-byte header, the payload and a CRC-32,
// COBS-encoded, with one 0x00 delimiter before and one after.
//
//   offset  size  field
//   0       1     protocol version (kProtocolVersion)
//   1       1     message type (MessageType)
//   2       2     sequence number, little endian
//   4       2     payload length N, little endian (<= kMaxPayloadBytes)
//   6       N     payload
//   6+N     4     CRC-32 of bytes [0, 6+N), little endian
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/config.hpp"
#include "itp/link/cobs.hpp"

namespace itp::link {

inline constexpr std::uint8_t kProtocolVersion = 1;
inline constexpr std::size_t kHeaderBytes = 6;
inline constexpr std::size_t kCrcBytes = 4;
inline constexpr std::size_t kMaxRawFrameBytes = kHeaderBytes + config::kMaxPayloadBytes + kCrcBytes;
// Encoded frame plus its two 0x00 delimiters: the largest thing on the wire.
inline constexpr std::size_t kMaxWireFrameBytes = cobs_max_encoded_size(kMaxRawFrameBytes) + 2;
static_assert(config::kMaxPayloadBytes <= 0xFFFFu, "payload length is a 16-bit field");

enum class MessageType : std::uint8_t {
  kPing = 0x01,
  kPong = 0x02,
  kQpSolveRequest = 0x10,  // host -> firmware: solve this QP on the target
  kQpSolveReply = 0x11,
  kPlanRequest = 0x20,  // host -> firmware: a Scene; plan one cycle
  kPlanReply = 0x21,    // firmware -> host: the Plan
  kDiagnosticsRequest = 0x30,  // host -> firmware: report resource use (empty body)
  kDiagnosticsReply = 0x31,    // firmware -> host: Diagnostics
  kError = 0x7F,  // reply to a request the firmware cannot serve
};

// Zero-initialised by default so that buffers holding one can live in .bss.
struct FrameHeader {
  std::uint8_t version = 0;
  MessageType type{};
  std::uint16_t sequence = 0;
  std::uint16_t payload_length = 0;
};

// Encodes a complete wire frame (0x00, COBS bytes, 0x00) into `out`.
// Returns the number of bytes written, or 0 if the payload is too long or
// `out` too small.
std::size_t encode_frame(MessageType type, std::uint16_t sequence,
                         std::span<const std::uint8_t> payload, std::span<std::uint8_t> out);

}  // namespace itp::link
