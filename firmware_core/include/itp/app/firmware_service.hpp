#pragma once
// The target-independent heart of the firmware: received bytes in, encoded
// reply frames out. The port's main loop moves bytes between the serial line
// and this object; everything else (framing, dispatch, replies) happens here,
// where the host tests can reach it without any port.
#include <array>
#include <cstdint>
#include <span>

#include "itp/core/stack_probe.hpp"
#include "itp/core/tick_source.hpp"
#include "itp/link/frame_decoder.hpp"
#include "itp/planner/planner.hpp"
#include "itp/qp/qp.hpp"
#include "itp/scene/scene.hpp"

namespace itp::app {

class FirmwareService {
 public:
  // The planner configuration this firmware is built for.
  using Config = DefaultConfig;
  // QpSolve service: the largest planner QP shape (the path QP).
  using TargetQpDims = qp::PathQpDims<Scalar, Config>;

  // The firmware constructs it in place in zeroed static storage (.bss).
  FirmwareService() = default;
  // `build_id` must outlive the service (a string literal in practice).
  void set_build_id(const char* build_id) { build_id_ = build_id; }
  // The port's counter, reported in Pong and used for per-stage timing.
  void set_tick_source(TickSource source) {
    ticks_ = source;
    planner_.set_tick_source(source);
  }

  // The port's stack measurement, reported in the Diagnostics reply.
  void set_stack_probe(StackProbe probe) { stack_ = probe; }

  // Feeds one received byte. Returns the encoded reply frame to send (a view
  // into an internal buffer, valid until the next call), or an empty span.
  std::span<const std::uint8_t> on_byte(std::uint8_t byte);

  const link::LinkCounters& counters() const { return decoder_.counters(); }
  std::uint32_t replies_sent() const { return replies_; }

 private:
  std::span<const std::uint8_t> dispatch(const link::FrameView& frame);
  std::size_t solve_qp(std::span<const std::uint8_t> request);
  std::size_t plan_cycle(std::span<const std::uint8_t> request);
  std::span<const std::uint8_t> reply(link::MessageType type, std::uint16_t sequence,
                                      std::size_t payload_size);

  const char* build_id_ = nullptr;
  TickSource ticks_{};
  StackProbe stack_{};
  link::FrameDecoder decoder_;
  std::array<std::uint8_t, config::kMaxPayloadBytes> payload_{};   // reply body
  std::array<std::uint8_t, link::kMaxWireFrameBytes> tx_{};          // encoded reply
  std::uint32_t replies_ = 0;

  // QpSolve service: the largest planner QP shape (the path QP).
  qp::QpProblem<TargetQpDims> qp_problem_{};
  qp::QpWorkspace<TargetQpDims> qp_workspace_{};
  qp::QpResult<TargetQpDims> qp_result_{};

  // Planning service: one cycle per Scene message.
  scene::BasicScene<Config> scene_{};
  planner::BasicPlanner<Config> planner_{};
  planner::BasicPlan<Config> plan_{};
};

}  // namespace itp::app
