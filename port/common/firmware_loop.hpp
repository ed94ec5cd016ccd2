#pragma once
// The firmware's main loop, the same on every target and image: it uses only
// the port API and moves bytes between the serial line and a service
// (itp::app::FirmwareService of the image's choosing).
#include <array>
#include <cstddef>
#include <cstdint>
#include <new>
#include <span>

#include "itp/core/stack_probe.hpp"
#include "itp/core/tick_source.hpp"
#include "itp/link/frame.hpp"
#include "port/port.hpp"

namespace port_image {

inline void send_all(std::span<const std::uint8_t> bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size() && port::keep_running()) {  // each pass sends >= 1 byte or idles
    const std::size_t n = port::serial_write(bytes.subspan(sent));
    if (n == 0) {
      port::idle();  // returns when transmit space (or input) arrives
    }
    sent += n;
  }
}

// Constructs the service in `storage` (zeroed static bytes, .bss: a
// constant-initialised object with non-zero defaults would be copied into
// .data, costing flash and start-up time), provisions it from the port's key
// slot and runs until the port reports the link gone (host) or forever (target).
template <class Service>
void run(std::byte* storage, const char* build_id) {
  port::init();
  Service* service = ::new (storage) Service();  // placement: no heap
  service->set_build_id(build_id);
  service->set_tick_source(itp::TickSource{&port::counter_ticks, port::counter_hz()});
  service->set_stack_probe(itp::StackProbe{&port::stack_peak_bytes, port::stack_size_bytes()});
  std::array<std::uint8_t, port::kLinkKeyBytes> key{};
  std::array<std::uint8_t, port::kBootEntropyBytes> entropy{};
  const bool have_key = port::link_key(key);
  const bool have_entropy = port::boot_entropy(entropy);
  service->provision(have_key ? std::span<const std::uint8_t>(key) : std::span<const std::uint8_t>(),
                     have_entropy ? std::span<const std::uint8_t>(entropy) : std::span<const std::uint8_t>());
  key.fill(0);
  entropy.fill(0);
  port::log_line(have_key ? "itplan firmware ready" : "itplan firmware ready (no link key: secured requests refused)");
  std::array<std::uint8_t, 64> rx{};
  while (port::keep_running()) {  // the superloop: runs for the life of the device
    const std::size_t n = port::serial_read(rx);
    if (n == 0) {
      port::idle();
      continue;
    }
    for (std::size_t i = 0; i < n; ++i) {  // n <= rx.size()
      service->on_byte(rx[i]);
      // A reply has at most kMaxSegments frames, plus one Status.
      for (std::size_t k = 0; k <= itp::link::kMaxSegments; ++k) {
        const std::span<const std::uint8_t> frame = service->next_frame();
        if (frame.empty()) {
          break;
        }
        send_all(frame);
      }
    }
  }
}

}  // namespace port_image
