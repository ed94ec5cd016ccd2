// Start-up for the MPS2 AN500 (Cortex-M7): the vector table, and a reset
// handler that enables the FPU, copies .data, zeroes .bss, runs static
// constructors and calls main(). QEMU loads the ELF and boots from address 0.
#include <cstdint>

#include "mps2_an500.hpp"
#include "port/firmware_run.hpp"

extern "C" {
// Provided by mps2_an500.ld.
extern std::uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[], _sstack[], _estack[];
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();

void Reset_Handler();
void Fault_Handler();
void Default_Handler();
}

namespace {

void write_log_text(const char* text) {
  auto& uart = port::mps2::uart1();
  uart.ctrl = port::mps2::kUartTxEnable;
  for (int i = 0; i < 128 && text[i] != '\0'; ++i) {  // bounded message length
    uart.data = static_cast<std::uint8_t>(text[i]);
  }
}

}  // namespace

extern "C" void Reset_Handler() {
  // Paint the free stack (docs/memory.md): every word from the bottom up to
  // the current stack pointer, i.e. below this function's own frame, which is
  // live. port::stack_peak_bytes() finds the deepest word overwritten since.
  std::uint32_t* sp = nullptr;
  __asm volatile("mov %0, sp" : "=r"(sp));
  for (volatile std::uint32_t* word = _sstack; word < sp; ++word) {  // bounded by the stack size
    *word = port::mps2::kStackPaint;
  }

  // Enable CP10/CP11 (the FPU) before any floating-point instruction runs.
  *reinterpret_cast<volatile std::uint32_t*>(port::mps2::kCpacr) |= (0xFu << 20);
  __asm volatile("dsb\n\tisb" ::: "memory");

  const std::uint32_t* src = _sidata;
  for (std::uint32_t* dst = _sdata; dst < _edata; ++dst, ++src) {  // bounded by .data size
    *dst = *src;
  }
  for (std::uint32_t* dst = _sbss; dst < _ebss; ++dst) {  // bounded by .bss size
    *dst = 0u;
  }
  const auto count = static_cast<std::uint32_t>(__init_array_end - __init_array_start);
  for (std::uint32_t i = 0; i < count; ++i) {  // bounded by the constructor table
    __init_array_start[i]();
  }
  firmware_run();
  for (;;) {  // firmware_run() never returns on target; park the core if it does
    __asm volatile("wfi");
  }
}

extern "C" void Fault_Handler() {
  write_log_text("itplan firmware: fault\n");
  for (;;) {  // a fault is final; the host sees a timeout and counts it
  }
}

extern "C" void Default_Handler() {
  write_log_text("itplan firmware: unexpected interrupt\n");
  for (;;) {
  }
}

using Vector = void (*)();

// Initial stack pointer, then the 15 system exceptions; no device interrupts
// are used (the port polls), so the table stops there.
extern "C" __attribute__((section(".isr_vector"), used)) const Vector g_vectors[16] = {
    reinterpret_cast<Vector>(_estack),
    Reset_Handler,
    Default_Handler,  // NMI
    Fault_Handler,    // HardFault
    Fault_Handler,    // MemManage
    Fault_Handler,    // BusFault
    Fault_Handler,    // UsageFault
    nullptr, nullptr, nullptr, nullptr,
    Default_Handler,  // SVCall
    Default_Handler,  // DebugMonitor
    nullptr,
    Default_Handler,  // PendSV
    Default_Handler,  // SysTick
};
