#include "itp/link/crc32.hpp"
#include "itp/link/frame.hpp"

namespace itp::link {
namespace {

void push_byte(CobsWriter& writer, Crc32& crc, std::uint8_t b) {
  writer.push(b);
  crc.update(b);
}

void push_u16(CobsWriter& writer, Crc32& crc, std::uint16_t v) {
  push_byte(writer, crc, static_cast<std::uint8_t>(v & 0xFFu));
  push_byte(writer, crc, static_cast<std::uint8_t>(v >> 8));
}

}  // namespace

std::size_t encode_segment(const FrameHeader& h, std::span<const std::uint8_t> message,
                           std::span<std::uint8_t> out) {
  if (message.size() != h.message_length ||
      !valid_layout(h.message_length, h.segment_count, h.segment_index) || out.size() < 3) {
    return 0;
  }
  // A leading delimiter ends whatever garbage preceded the frame, so the
  // receiver resynchronises on this very frame instead of the next one.
  out[0] = 0u;
  CobsWriter writer(out.subspan(1, out.size() - 2));  // keep one byte for the trailing delimiter
  Crc32 crc;
  push_byte(writer, crc, kProtocolVersion);
  push_byte(writer, crc, static_cast<std::uint8_t>(h.type));
  push_u16(writer, crc, h.sequence);
  push_u16(writer, crc, h.message_length);
  push_byte(writer, crc, h.segment_index);
  push_byte(writer, crc, h.segment_count);
  push_byte(writer, crc, h.flags);
  push_byte(writer, crc, h.answer_units);
  const std::span<const std::uint8_t> chunk =
      message.subspan(segment_offset(h.message_length, h.segment_count, h.segment_index),
                      segment_length(h.message_length, h.segment_count, h.segment_index));
  writer.push(chunk);
  crc.update(chunk);
  const std::uint32_t c = crc.value();
  const std::uint8_t tail[4] = {static_cast<std::uint8_t>(c), static_cast<std::uint8_t>(c >> 8),
                                static_cast<std::uint8_t>(c >> 16),
                                static_cast<std::uint8_t>(c >> 24)};
  writer.push(tail);
  const std::size_t encoded = writer.finish();
  if (encoded == 0) {
    return 0;
  }
  out[encoded + 1] = 0u;
  return encoded + 2;
}

std::size_t encode_frame(MessageType type, std::uint16_t sequence,
                         std::span<const std::uint8_t> payload, std::span<std::uint8_t> out) {
  if (payload.size() > kMaxSegmentBytes) {
    return 0;
  }
  FrameHeader h;
  h.type = type;
  h.sequence = sequence;
  h.message_length = static_cast<std::uint16_t>(payload.size());
  return encode_segment(h, payload, out);
}

}  // namespace itp::link
