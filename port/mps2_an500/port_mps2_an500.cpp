// Port functions for the MPS2 AN500 under QEMU: UART0 carries the link, UART1
// the log, APB timer 0 is the counter (extended to 64 bits in software).
#include <cstring>

#include "mps2_an500.hpp"
#include "port/port.hpp"

extern "C" {
// Provided by mps2_an500.ld: the stack region [_sstack, _estack).
extern std::uint32_t _sstack[], _estack[];
}

namespace port {
namespace {

std::uint32_t g_last_low = 0;   // last 32-bit reading, to detect a wrap
std::uint64_t g_high = 0;       // wraps seen, << 32

void uart_put_blocking(mps2::CmsdkUart& uart, std::uint8_t byte) {
  for (int spin = 0; spin < 1000000 && (uart.state & mps2::kUartTxFull) != 0u; ++spin) {
  }
  uart.data = byte;
}

}  // namespace

void init() {
  auto& link = mps2::uart0();
  link.bauddiv = 16u;
  link.ctrl = mps2::kUartTxEnable | mps2::kUartRxEnable | mps2::kUartRxIntEnable | mps2::kUartTxIntEnable;
  // The receive and transmit interrupts only wake the core from WFI (idle()):
  // interrupts stay masked by PRIMASK and no handler ever runs. Both are
  // needed: a reply that fills the transmitter must wake the core when the
  // line drains, not only when the host sends the next byte.
  __asm volatile("cpsid i" ::: "memory");
  *reinterpret_cast<volatile std::uint32_t*>(mps2::kNvicIser0) = mps2::kUart0RxIrqBit | mps2::kUart0TxIrqBit;
  auto& log = mps2::uart1();
  log.bauddiv = 16u;
  log.ctrl = mps2::kUartTxEnable;

  auto& timer = mps2::timer0();
  timer.ctrl = 0u;
  timer.reload = 0xFFFFFFFFu;
  timer.value = 0xFFFFFFFFu;
  timer.ctrl = 1u;
}

std::uint64_t counter_ticks() {
  // The timer counts down; elapsed ticks = ~value. Callers read it at least
  // once per wrap period (about 171 s at 25 MHz), which the main loop does.
  const std::uint32_t low = ~mps2::timer0().value;
  if (low < g_last_low) {
    g_high += (std::uint64_t{1} << 32);
  }
  g_last_low = low;
  return g_high | low;
}

std::uint64_t counter_hz() { return mps2::kTimerHz; }

std::size_t serial_read(std::span<std::uint8_t> buffer) {
  auto& uart = mps2::uart0();
  std::size_t n = 0;
  while (n < buffer.size() && (uart.state & mps2::kUartRxFull) != 0u) {  // bounded by buffer
    buffer[n++] = static_cast<std::uint8_t>(uart.data);
  }
  return n;
}

std::size_t serial_write(std::span<const std::uint8_t> bytes) {
  auto& uart = mps2::uart0();
  std::size_t n = 0;
  while (n < bytes.size() && (uart.state & mps2::kUartTxFull) == 0u) {  // bounded by bytes
    uart.data = bytes[n++];
  }
  return n;
}

void log_line(const char* text) {
  const std::size_t len = std::strlen(text);
  for (std::size_t i = 0; i < len; ++i) {
    uart_put_blocking(mps2::uart1(), static_cast<std::uint8_t>(text[i]));
  }
  uart_put_blocking(mps2::uart1(), '\n');
}

void idle() {
  static_cast<void>(counter_ticks());  // keeps the 64-bit extension current
  // Sleep until a byte arrives or the transmitter has room again. Clear the
  // latched interrupts first; an event after the state check leaves its
  // interrupt pending, so WFI returns at once. Under QEMU this hands the host
  // thread to the serial back end instead of spinning. A waiting received
  // byte ends the wait only when the transmitter is not full: send_all()
  // does not read, it waits for room.
  auto& uart = mps2::uart0();
  uart.intstatus = mps2::kUartRxInt | mps2::kUartTxInt;
  *reinterpret_cast<volatile std::uint32_t*>(mps2::kNvicIcpr0) = mps2::kUart0RxIrqBit | mps2::kUart0TxIrqBit;
  const std::uint32_t state = uart.state;
  if ((state & mps2::kUartTxFull) != 0u || (state & mps2::kUartRxFull) == 0u) {
    __asm volatile("dsb\n\twfi" ::: "memory");
  }
}

std::uint32_t stack_size_bytes() {
  return static_cast<std::uint32_t>(_estack - _sstack) * sizeof(std::uint32_t);
}

// Scans up from the bottom for the first word the code has written over the
// start-up paint (startup.cpp). A word that happens to hold the pattern looks
// unused: the peak can read at most a few words low, never high.
std::uint32_t stack_peak_bytes() {
  const volatile std::uint32_t* word = _sstack;
  while (word < _estack && *word == mps2::kStackPaint) {  // bounded by the stack size
    ++word;
  }
  return static_cast<std::uint32_t>(_estack - word) * sizeof(std::uint32_t);
}

bool keep_running() { return true; }

bool link_key(std::span<std::uint8_t, kLinkKeyBytes> key) {
  volatile mps2::KeySlot& slot = mps2::key_slot();
  for (std::size_t i = 0; i < 4; ++i) {  // magic
    if (slot.magic[i] != mps2::kKeySlotMagic[i]) {
      return false;
    }
  }
  for (std::size_t i = 0; i < key.size(); ++i) {  // 16 bytes
    key[i] = slot.key[i];
  }
  return true;
}

bool boot_entropy(std::span<std::uint8_t, kBootEntropyBytes> entropy) {
  volatile mps2::KeySlot& slot = mps2::key_slot();
  std::uint8_t any = 0;
  for (std::size_t i = 0; i < entropy.size(); ++i) {  // 32 bytes, used once
    entropy[i] = slot.entropy[i];
    any = static_cast<std::uint8_t>(any | entropy[i]);
    slot.entropy[i] = 0;
  }
  return any != 0u && slot.magic[0] == mps2::kKeySlotMagic[0];
}

}  // namespace port
