#pragma once
// Small helpers shared by the link tests.
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "itp/link/frame.hpp"
#include "itp/link/crc32.hpp"
#include "itp/link/frame_decoder.hpp"

namespace link_test {

inline std::vector<std::uint8_t> wire_frame(itp::link::MessageType type, std::uint16_t seq,
                                            std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> out(itp::link::kMaxWireFrameBytes);
  const std::size_t n = itp::link::encode_frame(type, seq, payload, out);
  out.resize(n);
  return out;
}

inline std::vector<std::uint8_t> random_bytes(std::mt19937& rng, std::size_t n, int zero_percent) {
  std::vector<std::uint8_t> v(n);
  for (auto& b : v) {
    b = static_cast<int>(rng() % 100) < zero_percent ? 0u : static_cast<std::uint8_t>(rng());
  }
  return v;
}

// Feeds bytes; returns how many complete valid frames came out.
inline int feed(itp::link::FrameDecoder& dec, std::span<const std::uint8_t> bytes) {
  int frames = 0;
  for (std::uint8_t b : bytes) {
    if (dec.push(b) == itp::link::DecodeResult::kFrame) {
      ++frames;
    }
  }
  return frames;
}

}  // namespace link_test
