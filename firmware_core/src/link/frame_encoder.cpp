#include "itp/link/crc32.hpp"
#include "itp/link/frame.hpp"

namespace itp::link {
namespace {

void push_u16(CobsWriter& writer, Crc32& crc, std::uint16_t v) {
  const std::uint8_t bytes[2] = {static_cast<std::uint8_t>(v & 0xFFu),
                                 static_cast<std::uint8_t>(v >> 8)};
  writer.push(bytes);
  crc.update(bytes);
}

}  // namespace

std::size_t encode_frame(MessageType type, std::uint16_t sequence,
                         std::span<const std::uint8_t> payload, std::span<std::uint8_t> out) {
  if (payload.size() > config::kMaxPayloadBytes || out.size() < 3) {
    return 0;
  }
  // A leading delimiter ends whatever garbage preceded the frame, so the
  // receiver resynchronises on this very frame instead of the next one.
  out[0] = 0u;
  CobsWriter writer(out.subspan(1, out.size() - 2));  // keep one byte for the trailing delimiter
  Crc32 crc;
  const std::uint8_t head[2] = {kProtocolVersion, static_cast<std::uint8_t>(type)};
  writer.push(head);
  crc.update(head);
  push_u16(writer, crc, sequence);
  push_u16(writer, crc, static_cast<std::uint16_t>(payload.size()));
  writer.push(payload);
  crc.update(payload);
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

}  // namespace itp::link
