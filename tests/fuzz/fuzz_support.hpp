#pragma once
// Shared by the firmware-service fuzz targets: a provisioned service, the
// host's end of a session with it, and checks on everything it sends back
// (every reply frame decodes; a Plan opens, decodes and is finite; an
// invalid_input Plan carries no trajectory and origin 0).
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <new>
#include <span>
#include <vector>

#include "itp/app/firmware_service.hpp"
#include "itp/link/messages.hpp"
#include "itp/link/planner_messages.hpp"

namespace fuzz {

using Service = itp::app::FirmwareService<itp::DefaultConfig>;
namespace link = itp::link;

inline void check(bool ok) {
  if (!ok) __builtin_trap();
}

inline std::array<std::uint8_t, link::kKeyBytes> key() {
  std::array<std::uint8_t, link::kKeyBytes> k{};
  for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<std::uint8_t>(0x5A ^ (7 * i));
  return k;
}

// Drains the service's output into `frames`; checks that every byte stream
// it sends is made of valid frames.
struct Replies {
  link::FrameDecoder decoder;
  link::Inbox<link::kMaxMessageBytes> inbox;
  int frames = 0;
  // The last complete reply message.
  link::MessageType type{};
  std::uint16_t sequence = 0;
  std::vector<std::uint8_t> message;
  bool complete = false;

  // Ready for the next input (without building a new 64 KiB inbox).
  void reset() {
    decoder.reset();
    decoder.push(0u);
    inbox.clear();
    frames = 0;
    complete = false;
    message.clear();
  }

  void drain(Service& svc) {
    for (std::size_t k = 0; k < 2 * link::kMaxSegments + 4; ++k) {
      const std::span<const std::uint8_t> f = svc.next_frame();
      if (f.empty()) return;
      check(f.front() == 0u && f.back() == 0u);
      int here = 0;
      for (std::uint8_t b : f) {
        if (decoder.push(b) == link::DecodeResult::kFrame) {
          ++here;
          if (inbox.add(decoder.frame()) == link::InboxResult::kComplete) {
            type = inbox.type();
            sequence = inbox.sequence();
            message.assign(inbox.message().begin(), inbox.message().end());
            complete = true;
            inbox.clear();
          }
        }
      }
      check(here == 1);  // one whole, valid frame per call
      ++frames;
    }
    check(false);  // more frames than any reply has
  }
};

// A freshly started firmware in place (no 440 KB temporary on the stack).
inline Service& restart(Service* storage, std::span<const std::uint8_t> entropy) {
  storage->~Service();
  Service* svc = ::new (storage) Service();
  const auto k = key();
  svc->provision(k, entropy);
  return *svc;
}

inline void feed(Service& svc, Replies& out, std::span<const std::uint8_t> bytes) {
  for (std::uint8_t b : bytes) {
    svc.on_byte(b);
    out.drain(svc);
  }
}

// Sends one message through an Outbox in segments of `segment` bytes.
inline void send(Service& svc, Replies& out, link::MessageType type, std::uint16_t seq,
                 std::span<const std::uint8_t> message, std::size_t segment) {
  static link::Outbox<link::kMaxMessageBytes> box;
  std::array<std::uint8_t, link::kMaxWireFrameBytes> wire{};
  std::copy(message.begin(), message.end(), box.buffer().begin());
  if (!box.stage(type, seq, message.size(), segment, static_cast<std::uint8_t>(segment / 8), true)) return;
  for (std::size_t n = box.next_frame(wire); n > 0; n = box.next_frame(wire)) {
    feed(svc, out, std::span<const std::uint8_t>(wire.data(), n));
  }
}

// A Plan reply must open and decode; what it says must be finite, and an
// invalid_input plan repeats nothing.
inline void check_plan(link::SecureChannel& host, const Replies& r) {
  std::span<const std::uint8_t> body;
  check(host.open(link::MessageType::kPlanReply, r.sequence, r.message, body) == link::AuthStatus::kOk);
  static itp::planner::Plan plan;
  link::PlanHeader ph;
  check(link::decode_plan(body, ph, plan));
  check(std::isfinite(ph.origin_x) && std::isfinite(ph.origin_y));
  if (plan.status == itp::PlanStatus::kInvalidInput) {
    check(plan.trajectory.empty() && ph.origin_x == 0.0 && ph.origin_y == 0.0);
  }
  for (const auto& p : plan.trajectory) {
    for (double v : {p.t, p.x, p.y, p.heading, p.kappa, p.v, p.a, p.s, p.l}) check(std::isfinite(v));
  }
}

}  // namespace fuzz
