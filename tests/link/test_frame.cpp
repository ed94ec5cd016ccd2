#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "frame_helpers.hpp"

using itp::link::DecodeResult;
using itp::link::FrameDecoder;
using itp::link::MessageType;

TEST_CASE("frames round trip through the streaming decoder") {
  std::mt19937 rng(11);
  FrameDecoder dec;
  const std::size_t sizes[] = {0, 1, 5, 253, 254, 255, 1000, itp::link::kMaxSegmentBytes};
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
        CHECK(f.header.segment_count == 1);
        CHECK(f.header.message_length == payload.size());
        CHECK(std::vector<std::uint8_t>(f.chunk.begin(), f.chunk.end()) == payload);
      }
    }
    CHECK(frames == 1);
  }
  CHECK(dec.counters().dropped() == 0);
}

TEST_CASE("a single-frame payload longer than a segment is refused by the encoder") {
  std::vector<std::uint8_t> big(itp::link::kMaxSegmentBytes + 1);
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
  std::vector<std::uint8_t> raw{3, 1, 1, 0, 0, 0, 0, 1, 0, 0};
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

namespace {

// A raw frame (header fields given) with a correct CRC, COBS-encoded.
std::vector<std::uint8_t> raw_frame(std::uint16_t length, std::uint8_t index, std::uint8_t count, std::size_t chunk) {
  std::vector<std::uint8_t> raw{itp::link::kProtocolVersion, 0x20, 5, 0,
                                static_cast<std::uint8_t>(length & 0xFF), static_cast<std::uint8_t>(length >> 8),
                                index, count, 0, 0};
  raw.resize(raw.size() + chunk, 0x11);
  const std::uint32_t c = itp::link::crc32(raw);
  for (int i = 0; i < 4; ++i) raw.push_back(static_cast<std::uint8_t>(c >> (8 * i)));
  std::vector<std::uint8_t> enc(raw.size() + 16);
  itp::link::CobsWriter w(enc);
  w.push(raw);
  enc.resize(w.finish());
  enc.insert(enc.begin(), 0u);
  enc.push_back(0u);
  return enc;
}

}  // namespace

TEST_CASE("every segment of a message encodes and decodes with its layout") {
  std::mt19937 rng(21);
  for (std::size_t length : {1u, 31u, 32u, 33u, 1000u, 2751u, 9963u}) {
    for (std::size_t max_segment : {32u, 100u, 1024u}) {
      const auto message = link_test::random_bytes(rng, length, 10);
      const std::size_t s = std::max<std::size_t>(max_segment, (length + 254) / 255);  // <= 255 segments
      const std::size_t count = itp::link::segments_for(length, s);
      std::vector<std::uint8_t> rebuilt(length, 0xEE);
      FrameDecoder dec;
      std::vector<std::uint8_t> out(itp::link::kMaxWireFrameBytes);
      for (std::size_t i = 0; i < count; ++i) {
        itp::link::FrameHeader h;
        h.type = MessageType::kPlanRequest;
        h.sequence = 3;
        h.message_length = static_cast<std::uint16_t>(length);
        h.segment_index = static_cast<std::uint8_t>(i);
        h.segment_count = static_cast<std::uint8_t>(count);
        const std::size_t n = itp::link::encode_segment(h, message, out);
        REQUIRE(n > 0);
        REQUIRE(link_test::feed(dec, std::span<const std::uint8_t>(out.data(), n)) == 1);
        const auto& f = dec.frame();
        CHECK(f.header.segment_index == i);
        CHECK(f.chunk.size() <= s);
        std::copy(f.chunk.begin(), f.chunk.end(), rebuilt.begin() + static_cast<long>(itp::link::segment_offset(length, count, i)));
      }
      CHECK(rebuilt == message);
    }
  }
}

TEST_CASE("frames whose segment layout is impossible are length errors") {
  FrameDecoder dec;
  CHECK(link_test::feed(dec, raw_frame(10, 0, 1, 10)) == 1);  // the valid one
  CHECK(link_test::feed(dec, raw_frame(10, 0, 1, 9)) == 0);   // chunk shorter than the length says
  CHECK(link_test::feed(dec, raw_frame(10, 1, 1, 10)) == 0);  // index beyond the count
  CHECK(link_test::feed(dec, raw_frame(10, 0, 0, 10)) == 0);  // no segments
  CHECK(link_test::feed(dec, raw_frame(9, 0, 6, 2)) == 0);    // 6 x 2 bytes for 9: an empty last segment
  CHECK(link_test::feed(dec, raw_frame(2049, 1, 2, 1024)) == 0);  // S = 1025, above the segment maximum
  CHECK(link_test::feed(dec, raw_frame(0, 0, 2, 0)) == 0);    // an empty message in two segments
  CHECK(dec.counters().length_errors == 6);
  CHECK(link_test::feed(dec, raw_frame(2000, 1, 2, 1000)) == 1);  // the second of two
}
