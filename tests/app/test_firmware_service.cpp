#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "../link/frame_helpers.hpp"
#include "heap_guard.hpp"
#include "itp/app/firmware_service.hpp"
#include "itp/link/messages.hpp"

using namespace itp::link;

namespace {

// Feeds bytes to the service; returns the reply frames it produced, decoded.
std::vector<std::pair<FrameHeader, std::vector<std::uint8_t>>> exchange(
    itp::app::FirmwareService& svc, std::span<const std::uint8_t> bytes) {
  std::vector<std::pair<FrameHeader, std::vector<std::uint8_t>>> replies;
  FrameDecoder dec;
  for (std::uint8_t b : bytes) {
    const auto out = svc.on_byte(b);
    for (std::uint8_t r : out) {
      if (dec.push(r) == DecodeResult::kFrame) {
        replies.emplace_back(dec.frame().header,
                             std::vector<std::uint8_t>(dec.frame().payload.begin(), dec.frame().payload.end()));
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
  auto svc = std::make_unique<itp::app::FirmwareService>();
  svc->set_build_id("itplan-unit");
  const auto replies = exchange(*svc, ping_frame(1234, 42));
  REQUIRE(replies.size() == 1);
  CHECK(replies[0].first.type == MessageType::kPong);
  CHECK(replies[0].first.sequence == 42);
  Pong pong;
  REQUIRE(decode(replies[0].second, pong));
  CHECK(pong.nonce == 1234);
  CHECK(std::strcmp(pong.build_id.data(), "itplan-unit") == 0);
  CHECK(pong.counters.frames_ok == 1);
}

TEST_CASE("unsupported and malformed requests get an Error reply, not silence or a crash") {
  auto svc = std::make_unique<itp::app::FirmwareService>();
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

namespace {
std::uint32_t fake_peak() { return 1234u; }
}  // namespace

TEST_CASE("Diagnostics reports the port's stack probe; 0 / 0 without one") {
  auto svc = std::make_unique<itp::app::FirmwareService>();
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
}

TEST_CASE("garbage is counted and dropped, and the firmware keeps answering, without heap") {
  auto svc = std::make_unique<itp::app::FirmwareService>();
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
        if (!svc->on_byte(b).empty()) {
          ++pongs;
        }
      }
    }
  }
  // Random bytes can form a frame of an unknown type only with a matching
  // CRC (odds 2^-32), so every reply is one of our pings' Pongs.
  CHECK(pongs == 40);
  CHECK(svc->counters().frames_ok == 40);
  CHECK(svc->counters().dropped() > 0);
}
