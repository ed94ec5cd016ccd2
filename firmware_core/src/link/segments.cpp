#include "itp/link/segments.hpp"

#include <bit>

namespace itp::link {

void SegmentSet::fill_first(std::size_t count) {
  clear();
  for (std::size_t i = 0; i < count && i < 8 * kBytes; ++i) {  // <= 256
    set(i);
  }
}

std::size_t SegmentSet::count() const {
  std::size_t n = 0;
  for (const std::uint8_t b : bits_) {  // 32 bytes
    n += static_cast<std::size_t>(std::popcount(b));
  }
  return n;
}

SegmentSet SegmentSet::missing(std::size_t count) const {
  SegmentSet out;
  for (std::size_t i = 0; i < count && i < 8 * kBytes; ++i) {  // <= 256
    if (!test(i)) {
      out.set(i);
    }
  }
  return out;
}

}  // namespace itp::link
