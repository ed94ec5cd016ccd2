#pragma once
// The simulator's end of the link: frames requests, matches replies by
// sequence number, and counts what went wrong instead of failing hard.
#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "itp/link/frame_decoder.hpp"
#include "link/byte_transport.hpp"

namespace hil {

struct Reply {
  itp::link::MessageType type{};
  std::vector<std::uint8_t> payload;
};

struct ClientCounters {
  std::uint32_t requests = 0;
  std::uint32_t replies = 0;
  std::uint32_t timeouts = 0;
  std::uint32_t stale_replies = 0;  // a valid frame with another sequence number
};

class LinkClient {
 public:
  explicit LinkClient(ByteTransport& transport) : transport_(transport) {}

  // Sends one request and waits for the reply with the same sequence number.
  // Returns nullopt on timeout or when the peer is gone.
  std::optional<Reply> request(itp::link::MessageType type, std::span<const std::uint8_t> payload,
                               std::chrono::milliseconds timeout);
  // Discards unread bytes and any half-received frame (after a timeout).
  void resync();
  // Sends raw bytes as they are (fault injection).
  bool send_raw(std::span<const std::uint8_t> bytes) { return transport_.write_all(bytes); }

  const itp::link::LinkCounters& rx_counters() const { return decoder_.counters(); }
  const ClientCounters& counters() const { return counters_; }

 private:
  ByteTransport& transport_;
  itp::link::FrameDecoder decoder_;
  ClientCounters counters_;
  std::uint16_t next_sequence_ = 1;
  std::vector<std::uint8_t> backlog_;  // bytes read past the last reply
};

}  // namespace hil
