#include "sim/link_endpoint.hpp"

#include <array>
#include <chrono>

#include "itp/link/planner_messages.hpp"
#include "link/child_process.hpp"
#include "link/link_client.hpp"

namespace hil::sim {
namespace {

class LinkEndpoint final : public PlannerEndpoint {
 public:
  LinkEndpoint(std::string target, const std::vector<std::string>& command)
      : target_(std::move(target)), child_(command, ""), client_(child_) {}

  void reset() override { reset_next_ = true; }

  EndpointResult plan(const itp::scene::Scene& scene, double now, itp::planner::Plan& out) override {
    EndpointResult res;
    itp::link::SceneHeader header;
    header.cycle = ++cycle_;
    header.now = now;
    header.reset = reset_next_;
    // The UART under QEMU is slow: thin the predictions to every 0.5 s (the
    // planner interpolates); the host link sends them all.
    const int stride = target_ == "qemu" ? 5 : 1;
    const std::size_t n = itp::link::encode_scene(header, scene, stride, body_);
    if (n == 0) {
      res.error = "scene does not fit a link message";
      return res;
    }
    const auto timeout = std::chrono::milliseconds(target_ == "qemu" ? 60000 : 5000);
    const auto reply = client_.request(itp::link::MessageType::kPlanRequest,
                                       std::span<const std::uint8_t>(body_.data(), n), timeout);
    std::uint32_t cycle = 0;
    if (!reply) {
      res.error = "no reply (timeout)";
      client_.resync();
      return res;
    }
    if (reply->type != itp::link::MessageType::kPlanReply || !itp::link::decode_plan(reply->payload, cycle, out) ||
        cycle != header.cycle) {
      res.error = "corrupt or unexpected reply";
      return res;
    }
    reset_next_ = false;
    res.ok = true;
    if (out.timing.tick_hz > 0) {
      const double ticks = static_cast<double>(out.timing.total);
      if (target_ == "qemu") {
        res.instructions = ticks * 1e9 / static_cast<double>(out.timing.tick_hz);  // icount shift=0: 1 ns per instruction
      } else {
        res.cycle_time_us = ticks * 1e6 / static_cast<double>(out.timing.tick_hz);
      }
    }
    return res;
  }

  std::string name() const override { return target_; }

  std::optional<itp::link::Diagnostics> diagnostics() override {
    const auto reply = client_.request(itp::link::MessageType::kDiagnosticsRequest, {},
                                       std::chrono::milliseconds(target_ == "qemu" ? 20000 : 5000));
    itp::link::Diagnostics diag;
    if (!reply || reply->type != itp::link::MessageType::kDiagnosticsReply ||
        !itp::link::decode(reply->payload, diag)) {
      return std::nullopt;
    }
    return diag;
  }

 private:
  std::string target_;
  ChildProcess child_;
  LinkClient client_;
  std::array<std::uint8_t, itp::config::kMaxPayloadBytes> body_{};
  std::uint32_t cycle_ = 0;
  bool reset_next_ = true;
};

}  // namespace

std::unique_ptr<PlannerEndpoint> make_link_endpoint(const std::string& target, const std::string& firmware,
                                                    std::string* error) {
  try {
    if (target == "qemu") {
      return std::make_unique<LinkEndpoint>(target, qemu_command(firmware.empty() ? ITP_DEFAULT_QEMU_FIRMWARE : firmware, ""));
    }
    if (target == "host") {
      return std::make_unique<LinkEndpoint>(target, host_firmware_command(firmware.empty() ? ITP_DEFAULT_HOST_FIRMWARE : firmware));
    }
    if (error != nullptr) *error = "unknown target '" + target + "'";
  } catch (const std::exception& e) {
    if (error != nullptr) *error = e.what();
  }
  return nullptr;
}

}  // namespace hil::sim
