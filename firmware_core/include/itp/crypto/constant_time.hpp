#pragma once
// Constant-time helpers for the link's cryptography: tag comparison without
// an early exit, and overwriting key material so that the compiler cannot
// drop the stores.
#include <cstddef>
#include <cstdint>
#include <span>

namespace itp::crypto {

// True when a and b have the same length and bytes; the time taken depends
// on the length only, not on where they differ.
bool equal_constant_time(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b);

// Overwrites `bytes` bytes at `p` with zeros through a volatile pointer (the
// stores stay even when the object dies right after).
void secure_wipe(void* p, std::size_t bytes);

}  // namespace itp::crypto
