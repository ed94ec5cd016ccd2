#pragma once
// CRC-32 (IEEE 802.3: reflected polynomial 0xEDB88320, initial value and final
// XOR 0xFFFFFFFF), the checksum of every link frame. Check value:
// crc32("123456789") == 0xCBF43926.
#include <cstdint>
#include <span>

namespace itp::link {

class Crc32 {
 public:
  void update(std::span<const std::uint8_t> bytes);
  void update(std::uint8_t byte);
  std::uint32_t value() const { return ~state_; }

 private:
  std::uint32_t state_ = 0xFFFFFFFFu;
};

std::uint32_t crc32(std::span<const std::uint8_t> bytes);

}  // namespace itp::link
