// The firmware's main loop, the same on every target: it uses only the port
// API and moves bytes between the serial line and the FirmwareService.
#include <array>
#include <cstddef>
#include <new>
#include <cstdint>

#include "itp/app/firmware_service.hpp"
#include "port/firmware_run.hpp"
#include "port/port.hpp"

namespace {

// Static storage for the service, which owns large fixed buffers that do not
// belong on the stack. Raw zeroed bytes (.bss) constructed in place at start-up:
// a constant-initialised object with non-zero defaults would be copied into
// .data, costing flash and start-up time for hundreds of KiB of zeros.
alignas(itp::app::FirmwareService) std::byte g_service_storage[sizeof(itp::app::FirmwareService)];
itp::app::FirmwareService* g_service = nullptr;

void send_all(std::span<const std::uint8_t> bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size() && port::keep_running()) {  // each pass sends >= 1 byte or idles
    const std::size_t n = port::serial_write(bytes.subspan(sent));
    if (n == 0) {
      port::idle();
    }
    sent += n;
  }
}

}  // namespace

// Runs until the port reports the link gone (host) or forever (target). The
// target's reset handler calls this directly; hosts enter through main().
void firmware_run() {
  port::init();
  g_service = ::new (g_service_storage) itp::app::FirmwareService();  // placement: no heap
  g_service->set_build_id(ITP_BUILD_ID);
  g_service->set_tick_source(itp::TickSource{&port::counter_ticks, port::counter_hz()});
  g_service->set_stack_probe(itp::StackProbe{&port::stack_peak_bytes, port::stack_size_bytes()});
  port::log_line("itplan firmware " ITP_BUILD_ID " ready");
  std::array<std::uint8_t, 64> rx{};
  while (port::keep_running()) {  // the superloop: runs for the life of the device
    const std::size_t n = port::serial_read(rx);
    if (n == 0) {
      port::idle();
      continue;
    }
    for (std::size_t i = 0; i < n; ++i) {  // n <= rx.size()
      const std::span<const std::uint8_t> reply = g_service->on_byte(rx[i]);
      if (!reply.empty()) {
        send_all(reply);
      }
    }
  }
}

int main() {
  firmware_run();
  return 0;
}
