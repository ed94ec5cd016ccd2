#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "frame_helpers.hpp"

using itp::link::FrameDecoder;
using itp::link::MessageType;

TEST_CASE("the decoder recovers after random garbage") {
  std::mt19937 rng(2024);
  FrameDecoder dec;
  int expected = 0;
  int received = 0;
  for (int trial = 0; trial < 500; ++trial) {
    // Garbage of any length and zero density, including runs longer than the
    // decoder's buffer, then one valid frame.
    const bool overlong = trial % 50 == 0;
    const std::size_t len = overlong ? itp::link::kMaxWireFrameBytes + 500 : rng() % 400;
    auto junk = link_test::random_bytes(rng, len, static_cast<int>(rng() % 10));
    if (overlong) {
      for (auto& b : junk) {
        b = b == 0u ? 0x5Au : b;  // no delimiter at all: the buffer must overflow
      }
    }
    link_test::feed(dec, junk);
    const auto payload = link_test::random_bytes(rng, rng() % 200, 10);
    const auto wire = link_test::wire_frame(MessageType::kPing, static_cast<std::uint16_t>(trial), payload);
    const int got = link_test::feed(dec, wire);
    CHECK(got == 1);
    CHECK(dec.frame().header.sequence == static_cast<std::uint16_t>(trial));
    ++expected;
    received += got;
  }
  CHECK(received == expected);
  CHECK(dec.counters().overflows >= 10);
  CHECK(dec.counters().dropped() > 0);
}

TEST_CASE("back-to-back frames share delimiters without loss") {
  std::mt19937 rng(8);
  std::vector<std::uint8_t> stream;
  for (int i = 0; i < 50; ++i) {
    const auto payload = link_test::random_bytes(rng, rng() % 64, 30);
    const auto wire = link_test::wire_frame(MessageType::kPong, static_cast<std::uint16_t>(i), payload);
    stream.insert(stream.end(), wire.begin(), wire.end());
  }
  FrameDecoder dec;
  CHECK(link_test::feed(dec, stream) == 50);
  CHECK(dec.counters().dropped() == 0);
}
