// The firmware service at the frame level: Ping, errors, garbage, and that
// nothing secured is acted on without a session.
#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "../link/frame_helpers.hpp"
#include "heap_guard.hpp"
#include "itp/link/messages.hpp"
#include "service_link.hpp"

using namespace itp::link;

namespace {

// Feeds bytes to the service; returns the reply frames it produced, decoded
// (single-segment replies: type, sequence number and body).
std::vector<std::pair<FrameHeader, std::vector<std::uint8_t>>> exchange(app_test::Service& svc,
                                                                       std::span<const std::uint8_t> bytes) {
  std::vector<std::pair<FrameHeader, std::vector<std::uint8_t>>> replies;
  FrameDecoder dec;
  for (std::uint8_t b : bytes) {
    svc.on_byte(b);
    for (auto out = svc.next_frame(); !out.empty(); out = svc.next_frame()) {
      for (std::uint8_t r : out) {
        if (dec.push(r) == DecodeResult::kFrame) {
          replies.emplace_back(dec.frame().header, std::vector<std::uint8_t>(dec.frame().chunk.begin(), dec.frame().chunk.end()));
        }
      }
    }
  }
  return replies;
}

std::vector<std::uint8_t> ping_frame(std::uint32_t nonce, std::uint16_t seq) {
  std::array<std::uint8_t, kPingBytes> body{};
  encode(Ping{nonce}, body);
  return link_test::wire_frame(MessageType::kPing, seq, body);
}

}  // namespace

TEST_CASE("the firmware answers a Ping with a Pong that carries its build id") {
  auto svc = app_test::provisioned_service();
  const auto replies = exchange(*svc, ping_frame(1234, 42));
  REQUIRE(replies.size() == 1);
  CHECK(replies[0].first.type == MessageType::kPong);
  CHECK(replies[0].first.sequence == 42);
  Pong pong;
  REQUIRE(decode(replies[0].second, pong));
  CHECK(pong.nonce == 1234);
  CHECK(std::strcmp(pong.build_id.data(), "itplan-unit") == 0);
  CHECK(pong.counters.link.frames_ok == 1);
  CHECK(pong.counters.messages == 1);
}

TEST_CASE("unsupported and malformed requests get an Error reply, not silence or a crash") {
  auto svc = app_test::provisioned_service();
  const std::vector<std::uint8_t> body{1, 2, 3};
  auto replies = exchange(*svc, link_test::wire_frame(static_cast<MessageType>(0x55), 7, body));
  REQUIRE(replies.size() == 1);
  ErrorReply err;
  REQUIRE(replies[0].first.type == MessageType::kError);
  REQUIRE(decode(replies[0].second, err));
  CHECK(err.code == ErrorCode::kUnsupportedMessage);
  CHECK(err.request_type == 0x55);

  replies = exchange(*svc, link_test::wire_frame(MessageType::kPing, 8, body));  // 3-byte ping
  REQUIRE(replies.size() == 1);
  REQUIRE(decode(replies[0].second, err));
  CHECK(err.code == ErrorCode::kMalformedPayload);
}

TEST_CASE("a Scene without a session is refused with no_session, never planned") {
  auto svc = app_test::provisioned_service();
  std::vector<std::uint8_t> body(200, 0x33);  // freshness, body and tag of nobody's session
  const auto replies = exchange(*svc, link_test::wire_frame(MessageType::kPlanRequest, 3, body));
  REQUIRE(replies.size() == 1);
  CHECK(replies[0].first.type == MessageType::kAuthError);
  AuthErrorReply err;
  REQUIRE(decode(replies[0].second, err));
  CHECK(err.code == AuthStatus::kNoSession);
  CHECK(err.request_type == 0x20);
  CHECK(svc->counters().auth.no_session == 1);
  CHECK(svc->counters().auth.accepted == 0);
}

TEST_CASE("a firmware without a key refuses the handshake with no_key") {
  auto svc = std::make_unique<app_test::Service>();
  std::vector<std::uint8_t> nonce(kNonceBytes, 1);
  const auto replies = exchange(*svc, link_test::wire_frame(MessageType::kSessionOpen, 1, nonce));
  REQUIRE(replies.size() == 1);
  AuthErrorReply err;
  REQUIRE(decode(replies[0].second, err));
  CHECK(err.code == AuthStatus::kNoKey);
}

namespace {
std::uint32_t fake_peak() { return 1234u; }
}  // namespace

TEST_CASE("Diagnostics reports the port's stack probe, 0 / 0 without one, with no key or session") {
  auto svc = std::make_unique<app_test::Service>();  // not provisioned: Diagnostics is not authenticated
  const std::vector<std::uint8_t> empty;
  auto replies = exchange(*svc, link_test::wire_frame(MessageType::kDiagnosticsRequest, 3, empty));
  REQUIRE(replies.size() == 1);
  CHECK(replies[0].first.type == MessageType::kDiagnosticsReply);
  Diagnostics diag;
  REQUIRE(decode(replies[0].second, diag));
  CHECK(diag.stack_bytes == 0);
  CHECK(diag.stack_peak_bytes == 0);

  svc->set_stack_probe(itp::StackProbe{&fake_peak, 4096u});
  replies = exchange(*svc, link_test::wire_frame(MessageType::kDiagnosticsRequest, 4, empty));
  REQUIRE(replies.size() == 1);
  REQUIRE(decode(replies[0].second, diag));
  CHECK(diag.stack_bytes == 4096u);
  CHECK(diag.stack_peak_bytes == 1234u);

  const std::vector<std::uint8_t> body{1};  // the request has an empty body
  replies = exchange(*svc, link_test::wire_frame(MessageType::kDiagnosticsRequest, 5, body));
  REQUIRE(replies.size() == 1);
  ErrorReply err;
  REQUIRE(decode(replies[0].second, err));
  CHECK(err.code == ErrorCode::kMalformedPayload);
  CHECK(svc->counters().auth.no_key == 0);  // never went near the secure channel
}

TEST_CASE("garbage is counted and dropped, and the firmware keeps answering, without heap") {
  auto svc = app_test::provisioned_service();
  std::mt19937 rng(99);
  std::vector<std::vector<std::uint8_t>> inputs;
  for (int i = 0; i < 40; ++i) {
    inputs.push_back(link_test::random_bytes(rng, rng() % 3000, 3));
    inputs.push_back(ping_frame(static_cast<std::uint32_t>(i), static_cast<std::uint16_t>(i)));
  }
  int pongs = 0;
  {
    test_support::HeapGuard guard;  // the firmware side must not allocate
    for (const auto& chunk : inputs) {
      for (std::uint8_t b : chunk) {
        svc->on_byte(b);
        for (auto out = svc->next_frame(); !out.empty(); out = svc->next_frame()) {
          ++pongs;
        }
      }
    }
  }
  // Random bytes can form a frame only with a matching CRC (odds 2^-32), so
  // every reply is one of our pings' Pongs.
  CHECK(pongs == 40);
  CHECK(svc->counters().link.frames_ok == 40);
  CHECK(svc->counters().link.dropped() > 0);
}

TEST_CASE("a request polled before it is complete gets a Status naming the segments held") {
  auto svc = app_test::provisioned_service();
  auto out = std::make_unique<Outbox<4096>>();
  REQUIRE(out->stage(MessageType::kPlanRequest, 11, 500, 100, 0, true));
  std::vector<std::vector<std::uint8_t>> frames;
  std::vector<std::uint8_t> wire(kMaxWireFrameBytes);
  for (std::size_t n = out->next_frame(wire); n > 0; n = out->next_frame(wire)) {
    frames.emplace_back(wire.begin(), wire.begin() + static_cast<long>(n));
  }
  REQUIRE(frames.size() == 5);
  std::vector<std::uint8_t> sent;
  for (std::size_t i : {0u, 2u, 4u}) sent.insert(sent.end(), frames[i].begin(), frames[i].end());  // 4 polls
  const auto replies = exchange(*svc, sent);
  REQUIRE(replies.size() == 1);
  CHECK(replies[0].first.type == MessageType::kStatus);
  SegmentReport status;
  REQUIRE(decode(replies[0].second, status));
  CHECK(status.sequence == 11);
  CHECK(status.segments.test(0));
  CHECK_FALSE(status.segments.test(1));
  CHECK(status.segments.test(2));
  CHECK_FALSE(status.segments.test(3));
  CHECK(status.segments.test(4));
}
