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
  std::uint32_t nudges = 0;         // lone delimiters sent while a reply was late
};

// How the client waits for a reply (docs/protocol.md, "Host side").
struct ClientPacing {
  // With nothing received for this long, send a lone delimiter (0x00): the
  // firmware ignores it, and it pushes through request bytes that QEMU's serial
  // multiplexer may still hold (it only forwards buffered bytes when the UART
  // reads or a new byte arrives; see hil_sim/link/child_process.cpp).
  std::chrono::milliseconds nudge_after{100};
  // Once a reply has started but is not complete, wait this long before the
  // next read: QEMU's UART writes one byte per system call, and reading each
  // one as it comes costs a wake-up of this process per byte.
  std::chrono::microseconds frame_settle{500};
};

class LinkClient {
 public:
  explicit LinkClient(ByteTransport& transport, ClientPacing pacing = {})
      : transport_(transport), pacing_(pacing) {}

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
  ClientPacing pacing_;
  itp::link::FrameDecoder decoder_;
  ClientCounters counters_;
  std::uint16_t next_sequence_ = 1;
  std::vector<std::uint8_t> backlog_;  // bytes read past the last reply
};

}  // namespace hil
