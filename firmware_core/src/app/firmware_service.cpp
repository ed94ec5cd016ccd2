#include "itp/app/firmware_service.hpp"

#include "itp/link/messages.hpp"

namespace itp::app {

std::span<const std::uint8_t> FirmwareService::on_byte(std::uint8_t byte) {
  if (decoder_.push(byte) != link::DecodeResult::kFrame) {
    return {};  // pending, or a bad frame that the decoder counted and dropped
  }
  return dispatch(decoder_.frame());
}

std::span<const std::uint8_t> FirmwareService::dispatch(const link::FrameView& frame) {
  const std::uint16_t seq = frame.header.sequence;
  switch (frame.header.type) {
    case link::MessageType::kPing: {
      link::Ping ping;
      if (!link::decode(frame.payload, ping)) {
        break;
      }
      link::Pong pong;
      pong.nonce = ping.nonce;
      link::set_build_id(pong, build_id_ != nullptr ? build_id_ : "");
      pong.counters = decoder_.counters();
      pong.ticks = ticks_.ticks();
      pong.tick_hz = ticks_.hz;
      return reply(link::MessageType::kPong, seq, link::encode(pong, payload_));
    }
    default: {
      link::ErrorReply err{link::ErrorCode::kUnsupportedMessage,
                           static_cast<std::uint8_t>(frame.header.type)};
      return reply(link::MessageType::kError, seq, link::encode(err, payload_));
    }
  }
  link::ErrorReply err{link::ErrorCode::kMalformedPayload,
                       static_cast<std::uint8_t>(frame.header.type)};
  return reply(link::MessageType::kError, seq, link::encode(err, payload_));
}

std::span<const std::uint8_t> FirmwareService::reply(link::MessageType type,
                                                     std::uint16_t sequence,
                                                     std::size_t payload_size) {
  const std::size_t n = link::encode_frame(
      type, sequence, std::span<const std::uint8_t>(payload_.data(), payload_size), tx_);
  if (n == 0) {
    return {};
  }
  ++replies_;
  return std::span<const std::uint8_t>(tx_.data(), n);
}

}  // namespace itp::app
