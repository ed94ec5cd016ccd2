#include <doctest/doctest.h>

#include <array>
#include <cstring>
#include <string>

#include "itp/link/messages.hpp"

using namespace itp::link;

TEST_CASE("Pong encodes and decodes every field") {
  Pong pong;
  pong.nonce = 0xDEADBEEFu;
  set_build_id(pong, "itplan-test-build");
  pong.counters.link.frames_ok = 5;
  pong.counters.link.crc_errors = 2;
  pong.counters.link.overflows = 1;
  pong.counters.auth.bad_tag = 7;
  pong.counters.auth.stale = 8;
  pong.counters.duplicates = 9;
  pong.ticks = 0x0123456789ABCDEFull;
  pong.tick_hz = 25000000u;
  std::array<std::uint8_t, kPongBytes> buf{};
  REQUIRE(encode(pong, buf) == kPongBytes);
  Pong back;
  REQUIRE(decode(buf, back));
  CHECK(back.nonce == 0xDEADBEEFu);
  CHECK(std::strcmp(back.build_id.data(), "itplan-test-build") == 0);
  CHECK(back.counters.link.frames_ok == 5);
  CHECK(back.counters.link.crc_errors == 2);
  CHECK(back.counters.link.overflows == 1);
  CHECK(back.counters.link.dropped() == 3);
  CHECK(back.counters.auth.bad_tag == 7);
  CHECK(back.counters.auth.stale == 8);
  CHECK(back.counters.auth.refused() == 15);
  CHECK(back.counters.duplicates == 9);
  CHECK(back.ticks == 0x0123456789ABCDEFull);
  CHECK(back.tick_hz == 25000000u);
}

TEST_CASE("Diagnostics encodes and decodes both fields") {
  Diagnostics diag{26112u, 20480u};
  std::array<std::uint8_t, kDiagnosticsBytes> buf{};
  REQUIRE(encode(diag, buf) == kDiagnosticsBytes);
  Diagnostics back;
  REQUIRE(decode(buf, back));
  CHECK(back.stack_bytes == 26112u);
  CHECK(back.stack_peak_bytes == 20480u);
  std::array<std::uint8_t, kDiagnosticsBytes - 1> short_body{};
  CHECK_FALSE(decode(short_body, back));
}

TEST_CASE("message decoders reject bodies of the wrong size") {
  std::array<std::uint8_t, 3> short_ping{};
  Ping ping;
  CHECK_FALSE(decode(short_ping, ping));
  std::array<std::uint8_t, 5> long_ping{};
  CHECK_FALSE(decode(long_ping, ping));
  std::array<std::uint8_t, kPongBytes - 1> short_pong{};
  Pong pong;
  CHECK_FALSE(decode(short_pong, pong));
}

TEST_CASE("an overlong build id is truncated and stays NUL-terminated") {
  Pong pong;
  std::string id(200, 'x');
  set_build_id(pong, id.c_str());
  CHECK(pong.build_id.back() == '\0');
  CHECK(std::strlen(pong.build_id.data()) == pong.build_id.size() - 1);
}

TEST_CASE("encoders report a buffer that is too small") {
  Pong pong;
  std::array<std::uint8_t, 10> small{};
  CHECK(encode(pong, small) == 0);
}
