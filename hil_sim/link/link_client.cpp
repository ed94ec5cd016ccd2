#include "link/link_client.hpp"

#include <algorithm>
#include <array>

#include "itp/link/frame.hpp"

namespace hil {

using Clock = std::chrono::steady_clock;

std::optional<Reply> LinkClient::request(itp::link::MessageType type,
                                         std::span<const std::uint8_t> payload,
                                         std::chrono::milliseconds timeout) {
  static std::array<std::uint8_t, itp::link::kMaxWireFrameBytes> wire{};
  const std::uint16_t seq = next_sequence_++;
  const std::size_t n = itp::link::encode_frame(type, seq, payload, wire);
  if (n == 0) {
    return std::nullopt;
  }
  ++counters_.requests;
  if (!transport_.write_all(std::span<const std::uint8_t>(wire.data(), n))) {
    return std::nullopt;
  }
  const auto deadline = Clock::now() + timeout;
  std::array<std::uint8_t, 4096> rx{};
  std::size_t got = std::min(backlog_.size(), rx.size());
  std::copy_n(backlog_.begin(), got, rx.begin());
  backlog_.erase(backlog_.begin(), backlog_.begin() + static_cast<std::ptrdiff_t>(got));
  while (got > 0 || Clock::now() < deadline) {
    for (std::size_t i = 0; i < got; ++i) {
      if (decoder_.push(rx[i]) != itp::link::DecodeResult::kFrame) {
        continue;
      }
      const auto& frame = decoder_.frame();
      if (frame.header.sequence != seq) {
        ++counters_.stale_replies;
        continue;
      }
      ++counters_.replies;
      backlog_.insert(backlog_.begin(), rx.begin() + static_cast<std::ptrdiff_t>(i + 1),
                      rx.begin() + static_cast<std::ptrdiff_t>(got));
      return Reply{frame.header.type,
                   std::vector<std::uint8_t>(frame.payload.begin(), frame.payload.end())};
    }
    got = 0;
    if (Clock::now() >= deadline) {
      break;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    got = transport_.read_some(rx, std::max(left, std::chrono::milliseconds(1)));
  }
  ++counters_.timeouts;
  return std::nullopt;
}

void LinkClient::resync() {
  backlog_.clear();
  decoder_.push(0u);  // a delimiter ends any partial frame; counted if it was bad
}

}  // namespace hil
