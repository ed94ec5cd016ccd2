#pragma once
// The QP-check service of the test firmware image (an Extension of
// FirmwareService): solves a QpSolve request cold with the capacity of QP
// shape D and replies with status, iterations, objective, ticks and x, so
// that the host can check the target's arithmetic (hil_sim qp-check). It
// holds a second copy of a QP's problem and workspace (114 KiB for the path
// QP), which is why the production image leaves it out.
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/core/tick_source.hpp"
#include "itp/link/frame.hpp"
#include "itp/link/qp_messages.hpp"
#include "itp/link/secure_channel.hpp"
#include "itp/qp/qp.hpp"

namespace itp::app {

template <class D>
class QpCheckService {
 public:
  // A request may be larger than one message allows: those QPs are refused.
  static constexpr std::size_t kMaxRequestBytes =
      link::kMaxQpRequestBytes<D> + link::kSecuredOverhead <= link::kMaxMessageBytes
          ? link::kMaxQpRequestBytes<D>
          : link::kMaxMessageBytes - link::kSecuredOverhead;
  static constexpr std::size_t kMaxReplyBytes = link::kMaxQpReplyBytes<D>;

  static constexpr bool serves(link::MessageType type) { return type == link::MessageType::kQpSolveRequest; }

  std::size_t serve(link::MessageType, std::span<const std::uint8_t> request, std::span<std::uint8_t> out,
                    link::MessageType& reply_type, const TickSource& ticks) {
    if (!link::decode_qp_request(request, problem_)) {
      return 0;
    }
    const std::uint64_t t0 = ticks.ticks();
    const qp::QpSettings<typename D::Scalar> settings{};
    qp::solve_cold(problem_, workspace_, settings, result_);
    link::QpSolveReply<D> reply;
    reply.ticks = ticks.ticks() - t0;
    reply.status = result_.status;
    reply.iterations = static_cast<std::uint16_t>(result_.iterations);
    reply.n = static_cast<std::uint16_t>(problem_.n);
    reply.objective = static_cast<double>(result_.objective);
    for (int i = 0; i < problem_.n; ++i) {  // n <= D::kMaxVariables
      reply.x[i] = static_cast<double>(result_.x[i]);
    }
    reply_type = link::MessageType::kQpSolveReply;
    return link::encode(reply, out);
  }

 private:
  qp::QpProblem<D> problem_{};
  qp::QpWorkspace<D> workspace_{};
  qp::QpResult<D> result_{};
};

}  // namespace itp::app
