#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "frame_helpers.hpp"
#include "itp/link/cobs.hpp"

using itp::link::cobs_decode;
using itp::link::cobs_max_encoded_size;
using itp::link::CobsWriter;

namespace {
std::vector<std::uint8_t> encode(const std::vector<std::uint8_t>& raw) {
  std::vector<std::uint8_t> out(cobs_max_encoded_size(raw.size()));
  CobsWriter w(out);
  w.push(raw);
  const std::size_t n = w.finish();
  REQUIRE(n > 0);
  out.resize(n);
  return out;
}

void check_round_trip(const std::vector<std::uint8_t>& raw) {
  const auto enc = encode(raw);
  CHECK(enc.size() <= cobs_max_encoded_size(raw.size()));
  CHECK(std::find(enc.begin(), enc.end(), 0u) == enc.end());
  std::vector<std::uint8_t> dec(raw.size() + 8);
  const std::size_t n = cobs_decode(enc, dec);
  dec.resize(n);
  CHECK(dec == raw);
}
}  // namespace

TEST_CASE("COBS known encodings") {
  // Examples from the COBS definition (Cheshire & Baker).
  CHECK(encode({0x00}) == std::vector<std::uint8_t>{0x01, 0x01});
  CHECK(encode({0x00, 0x00}) == std::vector<std::uint8_t>{0x01, 0x01, 0x01});
  CHECK(encode({0x11, 0x22, 0x00, 0x33}) == std::vector<std::uint8_t>{0x03, 0x11, 0x22, 0x02, 0x33});
  CHECK(encode({0x11, 0x00, 0x00, 0x00}) == std::vector<std::uint8_t>{0x02, 0x11, 0x01, 0x01, 0x01});
}

TEST_CASE("COBS round trips around the 254-byte block boundary") {
  for (std::size_t n : {1u, 2u, 253u, 254u, 255u, 256u, 508u, 509u, 1000u}) {
    std::vector<std::uint8_t> ones(n, 0x42);
    check_round_trip(ones);
    std::vector<std::uint8_t> zeros(n, 0x00);
    check_round_trip(zeros);
  }
}

TEST_CASE("COBS round trips random data with varying zero density") {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 300; ++trial) {
    const auto raw = link_test::random_bytes(rng, 1 + rng() % 2000, static_cast<int>(rng() % 60));
    check_round_trip(raw);
  }
}

TEST_CASE("COBS decoder rejects malformed input") {
  std::vector<std::uint8_t> out(64);
  const std::vector<std::uint8_t> has_zero{0x03, 0x11, 0x00};
  CHECK(cobs_decode(has_zero, out) == 0);
  const std::vector<std::uint8_t> runs_past_end{0x05, 0x11, 0x22};
  CHECK(cobs_decode(runs_past_end, out) == 0);
  std::vector<std::uint8_t> small(1);
  const std::vector<std::uint8_t> valid{0x03, 0x11, 0x22};
  CHECK(cobs_decode(valid, small) == 0);
}

TEST_CASE("COBS writer reports an output buffer that is too small") {
  std::vector<std::uint8_t> raw(300, 0x7);
  std::vector<std::uint8_t> out(200);
  CobsWriter w(out);
  w.push(raw);
  CHECK(w.finish() == 0);
}
