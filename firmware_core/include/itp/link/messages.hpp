#pragma once
// Message bodies carried in link frames, and their byte layouts
// (docs/protocol.md). Each encode returns the payload size (0 if it does not
// fit); each decode returns false on a malformed body.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/config.hpp"
#include "itp/link/frame_decoder.hpp"

namespace itp::link {

struct Ping {
  std::uint32_t nonce = 0;  // echoed in the Pong
};

struct Pong {
  std::uint32_t nonce = 0;
  std::uint8_t protocol_version = kProtocolVersion;
  std::array<char, config::kBuildIdBytes> build_id{};  // NUL-padded text
  LinkCounters counters{};  // the firmware's receive counters
  std::uint64_t ticks = 0;    // the firmware's counter when it answered
  std::uint64_t tick_hz = 0;  // [ticks/s]; 0 when the firmware has no counter
};

enum class ErrorCode : std::uint8_t {
  kUnsupportedMessage = 1,  // a well-formed frame of a type the firmware does not serve
  kMalformedPayload = 2,    // right type, body of the wrong size or content
};

struct ErrorReply {
  ErrorCode code = ErrorCode::kUnsupportedMessage;
  std::uint8_t request_type = 0;
};

// The firmware's resource use, measured on the target (docs/memory.md). A
// DiagnosticsRequest has an empty body.
struct Diagnostics {
  std::uint32_t stack_bytes = 0;       // size of the stack region; 0: not measured
  std::uint32_t stack_peak_bytes = 0;  // deepest stack use since reset (painted stack)
};

inline constexpr std::size_t kPingBytes = 4;
inline constexpr std::size_t kPongBytes = 4 + 1 + config::kBuildIdBytes + 6 * 4 + 2 * 8;
inline constexpr std::size_t kErrorBytes = 2;
inline constexpr std::size_t kDiagnosticsBytes = 8;

std::size_t encode(const Ping& msg, std::span<std::uint8_t> out);
std::size_t encode(const Pong& msg, std::span<std::uint8_t> out);
std::size_t encode(const ErrorReply& msg, std::span<std::uint8_t> out);
std::size_t encode(const Diagnostics& msg, std::span<std::uint8_t> out);
bool decode(std::span<const std::uint8_t> in, Ping& msg);
bool decode(std::span<const std::uint8_t> in, Pong& msg);
bool decode(std::span<const std::uint8_t> in, ErrorReply& msg);
bool decode(std::span<const std::uint8_t> in, Diagnostics& msg);

// Copies `text` into a fixed NUL-padded field, truncating if needed.
void set_build_id(Pong& msg, const char* text);

}  // namespace itp::link
