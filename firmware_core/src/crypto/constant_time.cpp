#include "itp/crypto/constant_time.hpp"

namespace itp::crypto {

bool equal_constant_time(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
  if (a.size() != b.size()) {
    return false;
  }
  std::uint8_t diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {  // bounded by the length, no early exit
    diff = static_cast<std::uint8_t>(diff | (a[i] ^ b[i]));
  }
  return diff == 0u;
}

void secure_wipe(void* p, std::size_t bytes) {
  volatile std::uint8_t* v = static_cast<volatile std::uint8_t*>(p);
  for (std::size_t i = 0; i < bytes; ++i) {  // bounded by the object's size
    v[i] = 0u;
  }
}

}  // namespace itp::crypto
