#pragma once
// The port: the handful of free functions through which the firmware touches
// its platform. One implementation per target (port/host, port/mps2_an500),
// chosen at link time. firmware_core never includes this header.
#include <cstddef>
#include <cstdint>
#include <span>

namespace port {

void init();

// Monotonic counter and its rate. On mps2-an500 under `-icount shift=0` one
// tick is a fixed number of guest instructions (docs/port.md).
std::uint64_t counter_ticks();
std::uint64_t counter_hz();

// Non-blocking serial bytes: both return how many bytes they moved, maybe 0.
std::size_t serial_read(std::span<std::uint8_t> buffer);
std::size_t serial_write(std::span<const std::uint8_t> bytes);

// One line of diagnostics on a channel separate from the data link.
void log_line(const char* text);

// Called when there is nothing to do (no input), and while serial_write()
// accepts nothing: may wait briefly for input or for transmit space, and
// must return when either arrives.
void idle();

// The stack: its size and the deepest use since reset, in bytes. A target
// that paints its stack at start-up measures the peak from the paint; one
// that cannot (the host) returns 0 for both ("not measured").
std::uint32_t stack_size_bytes();
std::uint32_t stack_peak_bytes();

// False once the link is gone for good (host: the peer closed the pipe).
bool keep_running();

// Bytes of the link's long-term key: an AES-128 key (the link's MAC is
// AES-128-CMAC, docs/protocol.md).
inline constexpr std::size_t kLinkKeyBytes = 16;
// Bytes of boot entropy.
inline constexpr std::size_t kBootEntropyBytes = 32;

// The link's long-term key from the platform's key slot (on a product an
// HSM or secure storage; docs/port.md, "Key provisioning"). False when none
// is provisioned: the firmware then refuses every secured request.
bool link_key(std::span<std::uint8_t, kLinkKeyBytes> key);
// kBootEntropyBytes that differ on every boot (a TRNG, or an HSM's random source).
// False when there are none: the firmware then refuses every handshake.
bool boot_entropy(std::span<std::uint8_t, kBootEntropyBytes> entropy);

}  // namespace port
