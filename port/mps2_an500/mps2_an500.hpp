#pragma once
// Memory-mapped peripherals of the Arm MPS2 AN500 image (Cortex-M7) that the
// port uses, as QEMU's `-M mps2-an500` models them.
#include <cstdint>

namespace port::mps2 {

inline constexpr std::uintptr_t kTimer0Base = 0x40000000u;  // CMSDK APB timer 0
inline constexpr std::uintptr_t kUart0Base = 0x40004000u;   // data link (-serial #1)
inline constexpr std::uintptr_t kUart1Base = 0x40005000u;   // log lines (-serial #2)
inline constexpr std::uintptr_t kCpacr = 0xE000ED88u;       // coprocessor access control

// Peripheral clock of the APB timers: 25 MHz. Under `-icount shift=0` the
// guest runs one instruction per virtual nanosecond, so one tick = 40 instructions.
inline constexpr std::uint32_t kTimerHz = 25000000u;

struct CmsdkUart {
  volatile std::uint32_t data;       // 0x00
  volatile std::uint32_t state;      // 0x04 bit0 TX full, bit1 RX full
  volatile std::uint32_t ctrl;       // 0x08 bit0 TX enable, bit1 RX enable
  volatile std::uint32_t intstatus;  // 0x0C
  volatile std::uint32_t bauddiv;    // 0x10
};

struct CmsdkTimer {
  volatile std::uint32_t ctrl;       // 0x00 bit0 enable
  volatile std::uint32_t value;      // 0x04 counts down at kTimerHz
  volatile std::uint32_t reload;     // 0x08
  volatile std::uint32_t intstatus;  // 0x0C
};

inline constexpr std::uint32_t kUartTxFull = 1u << 0;
inline constexpr std::uint32_t kUartRxFull = 1u << 1;
inline constexpr std::uint32_t kUartTxEnable = 1u << 0;
inline constexpr std::uint32_t kUartRxEnable = 1u << 1;
inline constexpr std::uint32_t kUartTxIntEnable = 1u << 2;
inline constexpr std::uint32_t kUartRxIntEnable = 1u << 3;
inline constexpr std::uint32_t kUartTxInt = 1u << 0;  // INTSTATUS, write 1 to clear
inline constexpr std::uint32_t kUartRxInt = 1u << 1;  // INTSTATUS, write 1 to clear

// NVIC: UART0's receive interrupt is device IRQ 0 on this image, its
// transmit interrupt (the transmit buffer emptied) IRQ 1.
inline constexpr std::uintptr_t kNvicIser0 = 0xE000E100u;
inline constexpr std::uintptr_t kNvicIcpr0 = 0xE000E280u;
inline constexpr std::uint32_t kUart0RxIrqBit = 1u << 0;
inline constexpr std::uint32_t kUart0TxIrqBit = 1u << 1;

// The key slot (docs/port.md, "Key provisioning"): 256 bytes at the top of
// SSRAM2/3 that the linker script keeps free and the reset handler never
// clears. On this QEMU machine it stands in for an HSM: hil_sim has QEMU's
// generic loader write the link key and this boot's entropy there before the
// core starts (-device loader,file=...,addr=kKeySlotAddress,force-raw=on).
inline constexpr std::uintptr_t kKeySlotAddress = 0x203FFF00u;
struct KeySlot {
  std::uint8_t magic[4];     // "ITPK" when provisioned
  std::uint8_t key[16];      // the link's long-term key (AES-128)
  std::uint8_t entropy[32];  // differs on every boot
};
inline constexpr std::uint8_t kKeySlotMagic[4] = {'I', 'T', 'P', 'K'};

// Start-up paints every free stack word with this pattern; the first word
// from the bottom that differs marks the deepest use (docs/memory.md).
inline constexpr std::uint32_t kStackPaint = 0x5AC4C0DEu;

inline CmsdkUart& uart0() { return *reinterpret_cast<CmsdkUart*>(kUart0Base); }
inline CmsdkUart& uart1() { return *reinterpret_cast<CmsdkUart*>(kUart1Base); }
inline volatile KeySlot& key_slot() { return *reinterpret_cast<volatile KeySlot*>(kKeySlotAddress); }
inline CmsdkTimer& timer0() { return *reinterpret_cast<CmsdkTimer*>(kTimer0Base); }

}  // namespace port::mps2
