#pragma once
// A byte pipe to a firmware: a child process (host firmware or QEMU) or, later,
// an in-process loopback. Host-side code: ordinary C++.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>

namespace hil {

class ByteTransport {
 public:
  virtual ~ByteTransport() = default;
  // Writes every byte or returns false (peer gone).
  virtual bool write_all(std::span<const std::uint8_t> bytes) = 0;
  // Waits up to `timeout` for at least one byte; returns how many were read.
  virtual std::size_t read_some(std::span<std::uint8_t> buffer,
                                std::chrono::milliseconds timeout) = 0;
};

}  // namespace hil
