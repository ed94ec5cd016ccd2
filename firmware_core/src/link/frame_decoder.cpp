#include "itp/link/frame_decoder.hpp"

#include "itp/link/crc32.hpp"

namespace itp::link {
namespace {

std::uint16_t read_u16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

std::uint32_t read_u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

}  // namespace

const char* to_string(DecodeResult result) {
  switch (result) {
    case DecodeResult::kPending: return "pending";
    case DecodeResult::kFrame: return "frame";
    case DecodeResult::kEmpty: return "empty";
    case DecodeResult::kCobsError: return "cobs_error";
    case DecodeResult::kLengthError: return "length_error";
    case DecodeResult::kCrcError: return "crc_error";
    case DecodeResult::kVersionError: return "version_error";
    case DecodeResult::kOverflow: return "overflow";
  }
  return "unknown";
}

void FrameDecoder::reset() {
  fill_ = 0;
  discarding_ = false;
  frame_ = FrameView{};
}

DecodeResult FrameDecoder::push(std::uint8_t byte) {
  if (byte == 0u) {
    if (discarding_) {
      discarding_ = false;
      fill_ = 0;
      return DecodeResult::kPending;  // the overflow was already counted
    }
    return finish_frame();
  }
  if (discarding_) {
    return DecodeResult::kPending;
  }
  if (fill_ == buffer_.size()) {
    discarding_ = true;
    fill_ = 0;
    ++counters_.overflows;
    return DecodeResult::kOverflow;
  }
  buffer_[fill_++] = byte;
  return DecodeResult::kPending;
}

DecodeResult FrameDecoder::finish_frame() {
  const std::size_t encoded = fill_;
  fill_ = 0;
  if (encoded == 0) {
    return DecodeResult::kEmpty;
  }
  const std::span<std::uint8_t> buf(buffer_.data(), encoded);
  const std::size_t raw = cobs_decode(buf, buf);
  if (raw == 0) {
    ++counters_.cobs_errors;
    return DecodeResult::kCobsError;
  }
  const std::uint8_t* p = buffer_.data();
  if (raw < kHeaderBytes + kCrcBytes) {
    ++counters_.length_errors;
    return DecodeResult::kLengthError;
  }
  // The CRC is the last 4 bytes and covers everything before them in every
  // protocol version, so a frame of another version is told from noise.
  const std::size_t checked = raw - kCrcBytes;
  if (crc32(std::span<const std::uint8_t>(p, checked)) != read_u32(p + checked)) {
    ++counters_.crc_errors;
    return DecodeResult::kCrcError;
  }
  if (p[0] != kProtocolVersion) {
    ++counters_.version_errors;
    return DecodeResult::kVersionError;
  }
  const std::uint16_t length = read_u16(p + 4);
  const std::uint8_t index = p[6];
  const std::uint8_t count = p[7];
  const std::size_t chunk = checked - kHeaderBytes;
  if (!valid_layout(length, count, index) || chunk != segment_length(length, count, index)) {
    ++counters_.length_errors;
    return DecodeResult::kLengthError;
  }
  frame_.header.version = p[0];
  frame_.header.type = static_cast<MessageType>(p[1]);
  frame_.header.sequence = read_u16(p + 2);
  frame_.header.message_length = length;
  frame_.header.segment_index = index;
  frame_.header.segment_count = count;
  frame_.header.flags = p[8];
  frame_.header.answer_units = p[9];
  frame_.chunk = std::span<const std::uint8_t>(p + kHeaderBytes, chunk);
  ++counters_.frames_ok;
  return DecodeResult::kFrame;
}

}  // namespace itp::link
