#include "link/link_client.hpp"

#include <algorithm>
#include <array>
#include <thread>

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
  auto last_activity = Clock::now();  // last byte received or nudge sent
  bool mid_frame = false;             // the last byte received was not a delimiter
  std::array<std::uint8_t, 4096> rx{};
  const auto take_backlog = [&] {  // bytes read past an earlier reply come first
    const std::size_t k = std::min(backlog_.size(), rx.size());
    std::copy_n(backlog_.begin(), k, rx.begin());
    backlog_.erase(backlog_.begin(), backlog_.begin() + static_cast<std::ptrdiff_t>(k));
    return k;
  };
  std::size_t got = take_backlog();
  while (got > 0 || Clock::now() < deadline) {
    for (std::size_t i = 0; i < got; ++i) {
      mid_frame = rx[i] != 0u;
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
    got = take_backlog();
    if (got > 0) {
      continue;
    }
    if (Clock::now() >= deadline) {
      break;
    }
    if (mid_frame && pacing_.frame_settle.count() > 0) {
      // Let the rest of the frame pile up in the pipe instead of waking per byte.
      std::this_thread::sleep_for(std::min<Clock::duration>(pacing_.frame_settle, deadline - Clock::now()));
    }
    auto wait = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
    if (pacing_.nudge_after.count() > 0) {
      wait = std::min(wait, pacing_.nudge_after);
    }
    got = transport_.read_some(rx, std::max(wait, std::chrono::milliseconds(1)));
    const auto now = Clock::now();
    if (got > 0) {
      last_activity = now;
    } else if (pacing_.nudge_after.count() > 0 && now - last_activity >= pacing_.nudge_after) {
      static constexpr std::array<std::uint8_t, 1> kDelimiter{0u};
      if (!transport_.write_all(kDelimiter)) {
        break;  // peer gone
      }
      ++counters_.nudges;
      last_activity = now;
    }
  }
  ++counters_.timeouts;
  return std::nullopt;
}

void LinkClient::resync() {
  backlog_.clear();
  decoder_.push(0u);  // a delimiter ends any partial frame; counted if it was bad
}

}  // namespace hil
