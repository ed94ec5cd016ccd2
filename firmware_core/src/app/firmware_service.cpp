#include "itp/app/firmware_service.hpp"

#include "itp/link/messages.hpp"
#include "itp/link/planner_messages.hpp"
#include "itp/link/qp_messages.hpp"

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
    case link::MessageType::kDiagnosticsRequest: {
      if (!frame.payload.empty()) {
        break;
      }
      link::Diagnostics diag;
      diag.stack_bytes = stack_.size_bytes;
      diag.stack_peak_bytes = stack_.peak();
      return reply(link::MessageType::kDiagnosticsReply, seq, link::encode(diag, payload_));
    }
    case link::MessageType::kPlanRequest: {
      const std::size_t n = plan_cycle(frame.payload);
      if (n == 0) {
        break;
      }
      return reply(link::MessageType::kPlanReply, seq, n);
    }
    case link::MessageType::kQpSolveRequest: {
      const std::size_t n = solve_qp(frame.payload);
      if (n == 0) {
        break;
      }
      return reply(link::MessageType::kQpSolveReply, seq, n);
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

std::size_t FirmwareService::solve_qp(std::span<const std::uint8_t> request) {
  if (!link::decode_qp_request(request, qp_problem_)) {
    return 0;
  }
  const std::uint64_t t0 = ticks_.ticks();
  const qp::QpSettings<Scalar> settings{};
  qp::solve_cold(qp_problem_, qp_workspace_, settings, qp_result_);
  link::QpSolveReply out;
  out.ticks = ticks_.ticks() - t0;
  out.status = qp_result_.status;
  out.iterations = static_cast<std::uint16_t>(qp_result_.iterations);
  out.n = static_cast<std::uint16_t>(qp_problem_.n);
  out.objective = static_cast<double>(qp_result_.objective);
  for (int i = 0; i < qp_problem_.n; ++i) {  // n <= kPathVariables
    out.x[i] = static_cast<double>(qp_result_.x[i]);
  }
  return link::encode(out, payload_);
}

std::size_t FirmwareService::plan_cycle(std::span<const std::uint8_t> request) {
  link::SceneHeader header;
  if (!link::decode_scene(request, header, scene_)) {
    return 0;
  }
  if (header.reset) {
    planner_.reset();
  }
  planner_.plan(planner::PlanRequest{&scene_, static_cast<Scalar>(header.now)}, plan_);
  const double ox = scene_.reference_line.empty() ? 0.0 : static_cast<double>(scene_.reference_line[0].x);
  const double oy = scene_.reference_line.empty() ? 0.0 : static_cast<double>(scene_.reference_line[0].y);
  return link::encode_plan(header.cycle, ox, oy, plan_, payload_);
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
