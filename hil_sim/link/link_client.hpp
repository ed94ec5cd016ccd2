#pragma once
// The simulator's end of the link (docs/protocol.md): sends a request as
// segments, asks for what went missing (Query) and resends what the firmware
// reports missing (Status) until the reply is complete or the deadline
// passes; seals secured requests and opens secured replies with a session it
// establishes on demand. Counts what went wrong instead of failing hard.
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "itp/link/frame_decoder.hpp"
#include "itp/link/secure_channel.hpp"
#include "itp/link/segments.hpp"
#include "link/byte_transport.hpp"

namespace hil {

struct Reply {
  itp::link::MessageType type{};
  std::uint16_t sequence = 0;
  std::vector<std::uint8_t> payload;  // the body (secured replies: opened, without freshness and tag)
};

struct ClientCounters {
  std::uint32_t requests = 0;
  std::uint32_t replies = 0;
  std::uint32_t timeouts = 0;        // requests that reached their deadline without a reply
  std::uint32_t stale_replies = 0;   // a valid frame with another sequence number
  std::uint32_t nudges = 0;          // lone delimiters sent while a reply was late
  std::uint32_t queries = 0;         // Query messages sent (a reply was late or incomplete)
  std::uint32_t statuses = 0;        // Status messages received
  std::uint32_t segments_resent = 0; // request segments sent again
  std::uint32_t auth_refused = 0;    // secured replies that did not open (dropped)
  std::uint32_t auth_errors = 0;     // AuthError replies (the firmware refused a request)
  std::uint32_t sessions = 0;        // sessions established
};

// How the client waits (docs/protocol.md, "Host side").
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
  // Quiet time after a request before asking (Query): long enough for the
  // firmware to plan, so that a slow reply is not sent twice.
  std::chrono::milliseconds first_gap{50};
  // Quiet time before asking again once the firmware has answered something.
  std::chrono::milliseconds gap{10};
  // Segment sizes [bytes]: the client starts at the largest, halves it after
  // an exchange that lost segments and doubles it after one that did not.
  std::size_t max_segment = itp::link::kMaxSegmentBytes;
  std::size_t min_segment = 32;
};

class LinkClient {
 public:
  explicit LinkClient(ByteTransport& transport, ClientPacing pacing = {});
  ~LinkClient();

  // The long-term link key (kKeyBytes); ends any session.
  void set_key(std::span<const std::uint8_t> key);

  // Sends one request and waits until `deadline` for the reply with the same
  // sequence number. Secured types are sealed (a session is established
  // first if there is none, and again after the firmware reports it lost).
  // Returns nullopt on timeout, when the peer is gone, or when no session
  // can be had; an AuthError or Error reply is returned as such.
  std::optional<Reply> request(itp::link::MessageType type, std::span<const std::uint8_t> body,
                               std::chrono::milliseconds deadline);
  // The handshake on its own (request() does it when needed).
  bool open_session(std::chrono::milliseconds deadline);
  bool in_session() const;
  // Discards unread bytes and any half-received frame.
  void resync();
  // Sends raw bytes as they are (fault injection).
  bool send_raw(std::span<const std::uint8_t> bytes) { return transport_.write_all(bytes); }

  const itp::link::LinkCounters& rx_counters() const { return decoder_.counters(); }
  const ClientCounters& counters() const { return counters_; }
  const itp::link::AuthCounters& auth_counters() const;
  std::size_t segment_size() const { return segment_; }

 private:
  using Clock = std::chrono::steady_clock;
  std::optional<Reply> exchange(itp::link::MessageType type, std::span<const std::uint8_t> body,
                                Clock::time_point deadline);
  bool handshake(Clock::time_point deadline);
  bool send_queued();

  struct Boxes;  // the message buffers (64 KiB each): on the heap, not the caller's stack
  ByteTransport& transport_;
  ClientPacing pacing_;
  std::unique_ptr<Boxes> boxes_;
  itp::link::FrameDecoder decoder_;
  ClientCounters counters_;
  std::uint16_t next_sequence_ = 1;
  std::size_t segment_;
  std::vector<std::uint8_t> backlog_;  // bytes read past the last reply
};

}  // namespace hil
