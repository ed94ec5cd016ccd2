#pragma once
// firmware_core never reads a clock by itself: the firmware injects the
// port's counter here, and library code that reports timing reads it through
// this struct. Without a source, ticks() is 0 and timing reads as "not measured".
#include <cstdint>

namespace itp {

struct TickSource {
  std::uint64_t (*now)() = nullptr;  // monotonic counter
  std::uint64_t hz = 0;              // [ticks/s]

  std::uint64_t ticks() const { return now != nullptr ? now() : 0u; }
};

}  // namespace itp
