#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "frame_helpers.hpp"

using itp::link::DecodeResult;
using itp::link::FrameDecoder;
using itp::link::MessageType;

TEST_CASE("frames round trip through the streaming decoder") {
  std::mt19937 rng(11);
  FrameDecoder dec;
  const std::size_t sizes[] = {0, 1, 5, 253, 254, 255, 1000, itp::config::kMaxPayloadBytes};
  for (std::size_t size : sizes) {
    const auto payload = link_test::random_bytes(rng, size, 20);
    const auto seq = static_cast<std::uint16_t>(rng());
    const auto wire = link_test::wire_frame(MessageType::kPing, seq, payload);
    REQUIRE(!wire.empty());
    CHECK(wire.front() == 0u);
    CHECK(wire.back() == 0u);
    CHECK(wire.size() <= itp::link::kMaxWireFrameBytes);
    int frames = 0;
    for (std::uint8_t b : wire) {
      if (dec.push(b) == DecodeResult::kFrame) {
        ++frames;
        const auto& f = dec.frame();
        CHECK(f.header.version == itp::link::kProtocolVersion);
        CHECK(f.header.type == MessageType::kPing);
        CHECK(f.header.sequence == seq);
        CHECK(std::vector<std::uint8_t>(f.payload.begin(), f.payload.end()) == payload);
      }
    }
    CHECK(frames == 1);
  }
  CHECK(dec.counters().dropped() == 0);
}

TEST_CASE("a payload longer than the maximum is refused by the encoder") {
  std::vector<std::uint8_t> big(itp::config::kMaxPayloadBytes + 1);
  std::vector<std::uint8_t> out(itp::link::kMaxWireFrameBytes + 64);
  CHECK(itp::link::encode_frame(MessageType::kPing, 1, big, out) == 0);
  std::vector<std::uint8_t> tiny(8);
  std::vector<std::uint8_t> payload(20, 1);
  CHECK(itp::link::encode_frame(MessageType::kPing, 1, payload, tiny) == 0);
}

TEST_CASE("every single-bit flip of a valid frame is rejected, and the next frame still decodes") {
  std::mt19937 rng(5);
  for (std::size_t size : {0u, 4u, 60u, 300u}) {
    const auto payload = link_test::random_bytes(rng, size, 25);
    const auto wire = link_test::wire_frame(MessageType::kPong, 77, payload);
    const auto next = link_test::wire_frame(MessageType::kPing, 78, payload);
    for (std::size_t byte = 0; byte < wire.size(); ++byte) {
      for (int bit = 0; bit < 8; ++bit) {
        auto bad = wire;
        bad[byte] = static_cast<std::uint8_t>(bad[byte] ^ (1u << bit));
        FrameDecoder dec;
        CHECK_MESSAGE(link_test::feed(dec, bad) == 0, "flip at byte ", byte, " bit ", bit);
        CHECK(link_test::feed(dec, next) == 1);
      }
    }
  }
}

TEST_CASE("every truncation of a valid frame is rejected, and the next frame still decodes") {
  std::mt19937 rng(6);
  const auto payload = link_test::random_bytes(rng, 120, 25);
  const auto wire = link_test::wire_frame(MessageType::kPong, 9, payload);
  const auto next = link_test::wire_frame(MessageType::kPing, 10, payload);
  for (std::size_t keep = 0; keep + 1 < wire.size(); ++keep) {
    std::vector<std::uint8_t> cut(wire.begin(), wire.begin() + static_cast<long>(keep));
    cut.push_back(0u);  // the line goes quiet and the next delimiter arrives
    FrameDecoder dec;
    CHECK_MESSAGE(link_test::feed(dec, cut) == 0, "kept ", keep, " bytes");
    CHECK(link_test::feed(dec, next) == 1);
  }
}

TEST_CASE("rejections are counted by reason") {
  FrameDecoder dec;
  const std::vector<std::uint8_t> payload{1, 2, 3};
  auto wire = link_test::wire_frame(MessageType::kPing, 1, payload);

  auto bad_crc = wire;
  bad_crc[wire.size() - 2] ^= 0x01u;  // last CRC byte
  if (bad_crc[wire.size() - 2] == 0u) {
    bad_crc[wire.size() - 2] = 0x33u;
  }
  link_test::feed(dec, bad_crc);
  CHECK(dec.counters().crc_errors == 1);

  const std::vector<std::uint8_t> short_frame{0x00, 0x03, 0x01, 0x02, 0x00};
  link_test::feed(dec, short_frame);
  CHECK(dec.counters().length_errors == 1);

  const std::vector<std::uint8_t> bad_cobs{0x00, 0x09, 0x01, 0x02, 0x00};
  link_test::feed(dec, bad_cobs);
  CHECK(dec.counters().cobs_errors == 1);

  // A valid CRC over a header with another version number.
  std::vector<std::uint8_t> raw{2, 1, 1, 0, 0, 0};
  const std::uint32_t c = itp::link::crc32(raw);
  for (int i = 0; i < 4; ++i) {
    raw.push_back(static_cast<std::uint8_t>(c >> (8 * i)));
  }
  std::vector<std::uint8_t> enc(32);
  itp::link::CobsWriter w(enc);
  w.push(raw);
  enc.resize(w.finish());
  enc.insert(enc.begin(), 0u);
  enc.push_back(0u);
  link_test::feed(dec, enc);
  CHECK(dec.counters().version_errors == 1);

  CHECK(link_test::feed(dec, wire) == 1);
  CHECK(dec.counters().frames_ok == 1);
  CHECK(dec.counters().dropped() == 4);
}
