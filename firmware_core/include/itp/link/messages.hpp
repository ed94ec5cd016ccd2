#pragma once
// Message bodies carried in link frames, and their byte layouts
// (docs/protocol.md). Each encode returns the body size (0 if it does not
// fit); each decode returns false on a malformed body.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/config.hpp"
#include "itp/link/frame_decoder.hpp"
#include "itp/link/secure_channel.hpp"
#include "itp/link/segments.hpp"

namespace itp::link {

struct Ping {
  std::uint32_t nonce = 0;  // echoed in the Pong
};

// What the firmware counted since it started (reported in the Pong).
struct FirmwareCounters {
  LinkCounters link{};          // frames accepted and dropped by the decoder
  AuthCounters auth{};          // secured messages and handshakes
  std::uint32_t messages = 0;   // messages reassembled from their segments
  std::uint32_t too_large = 0;  // messages longer than the firmware can hold (dropped)
  std::uint32_t resent = 0;     // segments sent again on a Query
  std::uint32_t duplicates = 0; // complete repeats of the last request (answered again, not acted on)
};

struct Pong {
  std::uint32_t nonce = 0;
  std::uint8_t protocol_version = kProtocolVersion;
  std::array<char, config::kBuildIdBytes> build_id{};  // NUL-padded text
  FirmwareCounters counters{};
  std::uint64_t ticks = 0;    // the firmware's counter when it answered
  std::uint64_t tick_hz = 0;  // [ticks/s]; 0 when the firmware has no counter
};

enum class ErrorCode : std::uint8_t {
  kUnsupportedMessage = 1,  // a well-formed message of a type the firmware does not serve
  kMalformedPayload = 2,    // right type, body of the wrong size or content
  kTooLarge = 3,            // a message longer than the firmware's buffer for it
};

struct ErrorReply {
  ErrorCode code = ErrorCode::kUnsupportedMessage;
  std::uint8_t request_type = 0;
};

// The firmware refused an authenticated message type (docs/protocol.md, "Security").
struct AuthErrorReply {
  AuthStatus code = AuthStatus::kNoSession;
  std::uint8_t request_type = 0;
};

// Query (host -> firmware) and Status (firmware -> host) name a request by
// its type and sequence number and carry a set of segment indices: in a
// Query the reply segments the host still misses, in a Status the request
// segments the firmware holds.
struct SegmentReport {
  std::uint8_t type = 0;
  std::uint16_t sequence = 0;
  SegmentSet segments{};
};

// The firmware's resource use, measured on the target (docs/memory.md). A
// DiagnosticsRequest has an empty body.
struct Diagnostics {
  std::uint32_t stack_bytes = 0;       // size of the stack region; 0: not measured
  std::uint32_t stack_peak_bytes = 0;  // deepest stack use since reset (painted stack)
};

inline constexpr std::size_t kPingBytes = 4;
inline constexpr std::size_t kCounterWords = 6 + 8 + 4;
inline constexpr std::size_t kPongBytes = 4 + 1 + config::kBuildIdBytes + 4 * kCounterWords + 2 * 8;
inline constexpr std::size_t kErrorBytes = 2;
inline constexpr std::size_t kSegmentReportBytes = 3 + SegmentSet::kBytes;
inline constexpr std::size_t kDiagnosticsBytes = 8;

std::size_t encode(const Ping& msg, std::span<std::uint8_t> out);
std::size_t encode(const Pong& msg, std::span<std::uint8_t> out);
std::size_t encode(const ErrorReply& msg, std::span<std::uint8_t> out);
std::size_t encode(const AuthErrorReply& msg, std::span<std::uint8_t> out);
std::size_t encode(const SegmentReport& msg, std::span<std::uint8_t> out);
std::size_t encode(const Diagnostics& msg, std::span<std::uint8_t> out);
bool decode(std::span<const std::uint8_t> in, Ping& msg);
bool decode(std::span<const std::uint8_t> in, Pong& msg);
bool decode(std::span<const std::uint8_t> in, ErrorReply& msg);
bool decode(std::span<const std::uint8_t> in, AuthErrorReply& msg);
bool decode(std::span<const std::uint8_t> in, SegmentReport& msg);
bool decode(std::span<const std::uint8_t> in, Diagnostics& msg);

// Copies `text` into a fixed NUL-padded field, truncating if needed.
void set_build_id(Pong& msg, const char* text);

}  // namespace itp::link
