#pragma once
// firmware_core does not know where its stack is: a port that paints its
// stack at start-up (port/mps2_an500/startup.cpp) injects a probe here, and the
// Diagnostics reply reports what it measured (docs/memory.md). Without a
// probe both figures read 0: "not measured".
#include <cstdint>

namespace itp {

struct StackProbe {
  std::uint32_t (*peak_bytes)() = nullptr;  // deepest use since reset, from the paint
  std::uint32_t size_bytes = 0;             // the stack region's size

  std::uint32_t peak() const { return peak_bytes != nullptr ? peak_bytes() : 0u; }
};

}  // namespace itp
