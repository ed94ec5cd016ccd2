#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "itp/link/crc32.hpp"

namespace {
// Independent reference: bit-at-a-time CRC-32 straight from the definition.
std::uint32_t crc32_bitwise(const std::vector<std::uint8_t>& data) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::uint8_t byte : data) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) {
      const std::uint32_t mask = 0u - (crc & 1u);
      crc = (crc >> 1) ^ (0xEDB88320u & mask);
    }
  }
  return ~crc;
}
}  // namespace

TEST_CASE("CRC-32 matches the standard check value") {
  const std::vector<std::uint8_t> digits{'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  CHECK(itp::link::crc32(digits) == 0xCBF43926u);
  CHECK(itp::link::crc32({}) == 0x00000000u);
}

TEST_CASE("CRC-32 table version agrees with the bitwise definition") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::uint8_t> data(rng() % 700);
    for (auto& b : data) {
      b = static_cast<std::uint8_t>(rng());
    }
    CHECK(itp::link::crc32(data) == crc32_bitwise(data));
  }
}

TEST_CASE("CRC-32 can be computed incrementally") {
  std::vector<std::uint8_t> data(100, 0xA5);
  itp::link::Crc32 crc;
  crc.update(std::span<const std::uint8_t>(data.data(), 40));
  crc.update(std::span<const std::uint8_t>(data.data() + 40, 60));
  CHECK(crc.value() == itp::link::crc32(data));
}
