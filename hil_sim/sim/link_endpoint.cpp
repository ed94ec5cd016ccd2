#include "sim/link_endpoint.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "itp/link/crc32.hpp"
#include "itp/link/messages.hpp"
#include "itp/link/planner_messages.hpp"
#include "link/fault_injection.hpp"
#include "link/firmware_process.hpp"
#include "link/link_client.hpp"
#include "sim/scene_convert.hpp"

namespace hil::sim {
namespace {

ClientPacing pacing_for(const std::string& target) {
  ClientPacing p;
  if (target == "qemu") {
    // A QEMU planning cycle takes tens (rarely hundreds) of milliseconds of
    // wall time, and its UART writes a byte every few microseconds: ask after
    // half a second of silence following a request (a rare long cycle then
    // has its reply sent twice), and after 30 ms once the reply is flowing.
    p.first_gap = std::chrono::milliseconds(500);
    p.gap = std::chrono::milliseconds(30);
  }
  return p;
}

// The predictions the qemu target sends: every stride-th sample, the largest
// stride that keeps them at most 0.5 s apart (default configuration: every
// 5th of 0.1 s; road: every 2nd of 0.2 s).
template <class Cfg>
int qemu_prediction_stride() {
  return std::max(1, static_cast<int>(std::floor(0.5 / prediction_step<Cfg>() + 1e-9)));
}

template <class Cfg>
class LinkEndpoint final : public BasicPlannerEndpoint<Cfg> {
 public:
  LinkEndpoint(std::string target, const std::string& firmware, const LinkOptions& options)
      : target_(std::move(target)),
        key_(link_key_from(options.key_file)),
        firmware_(target_, firmware, key_),
        faulty_(options.faults.any() ? std::make_unique<FaultyTransport>(firmware_.process(), options.faults) : nullptr),
        client_(faulty_ ? static_cast<ByteTransport&>(*faulty_) : firmware_.process(), pacing_for(target_)),
        deadline_(options.deadline.count() > 0 ? options.deadline
                                               : std::chrono::milliseconds(target_ == "qemu" ? 20000 : 1000)) {
    client_.set_key(key_);
  }

  void reset() override { reset_next_ = true; }

  EndpointResult plan(const itp::scene::BasicScene<Cfg>& scene, double now, itp::planner::BasicPlan<Cfg>& out) override {
    EndpointResult res;
    itp::link::SceneHeader header;
    header.cycle = ++cycle_;
    header.now = now;
    header.reset = reset_next_;
    // The UART under QEMU is slow: thin the predictions to every 0.5 s or
    // less (the planner interpolates); the host link sends them all.
    const int stride = target_ == "qemu" ? qemu_prediction_stride<Cfg>() : 1;
    const std::size_t n = itp::link::encode_scene(header, scene, stride, body_);
    if (n == 0) {
      res.error = "scene does not fit a link message";
      return res;
    }
    const std::span<const std::uint8_t> body(body_.data(), n);
    const auto reply = client_.request(itp::link::MessageType::kPlanRequest, body, deadline_);
    if (!reply) {
      res.error = "no reply before the deadline";
      client_.resync();
      return res;
    }
    if (reply->type == itp::link::MessageType::kAuthError) {
      itp::link::AuthErrorReply err;
      res.error = std::string("refused by the firmware: ") +
                  (itp::link::decode(reply->payload, err) ? itp::link::to_string(err.code) : "?");
      return res;
    }
    itp::link::PlanHeader ph;
    if (reply->type != itp::link::MessageType::kPlanReply || !itp::link::decode_plan(reply->payload, ph, out) ||
        ph.cycle != header.cycle) {
      res.error = "corrupt or unexpected reply";
      return res;
    }
    // The firmware echoes the CRC-32 of the Scene it planned: a scene that
    // changed on the way and was still accepted would show here.
    res.scene_mismatch = ph.scene_crc != itp::link::crc32(body);
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

  nlohmann::json link_statistics() const override {
    const ClientCounters& c = client_.counters();
    const itp::link::LinkCounters& rx = client_.rx_counters();
    const itp::link::AuthCounters& a = client_.auth_counters();
    nlohmann::json j = {{"requests", c.requests},         {"replies", c.replies},
                        {"timeouts", c.timeouts},         {"stale_replies", c.stale_replies},
                        {"queries", c.queries},           {"statuses", c.statuses},
                        {"segments_resent", c.segments_resent}, {"replies_refused", c.auth_refused},
                        {"auth_errors", c.auth_errors},   {"sessions", c.sessions},
                        {"frames_received", rx.frames_ok}, {"frames_dropped", rx.dropped()},
                        {"secured_replies_accepted", a.accepted}, {"final_segment_size", client_.segment_size()}};
    if (faulty_) {
      j["faults_to_firmware"] = faulty_->to_firmware().faults();
      j["faults_to_host"] = faulty_->to_host().faults();
      j["bytes_to_firmware"] = faulty_->to_firmware().bytes;
      j["bytes_to_host"] = faulty_->to_host().bytes;
    }
    return j;
  }

 private:
  std::string target_;
  LinkKey key_;
  FirmwareProcess firmware_;
  std::unique_ptr<FaultyTransport> faulty_;
  LinkClient client_;
  std::chrono::milliseconds deadline_;
  std::array<std::uint8_t, itp::link::kMaxSceneBytes<Cfg>> body_{};
  std::uint32_t cycle_ = 0;
  bool reset_next_ = true;
};

}  // namespace

std::string default_firmware(const std::string& target, SimConfig config) {
  const bool road = config == SimConfig::kRoad;
  if (target == "qemu") return road ? ITP_DEFAULT_QEMU_ROAD_FIRMWARE : ITP_DEFAULT_QEMU_FIRMWARE;
  return road ? ITP_DEFAULT_HOST_ROAD_FIRMWARE : ITP_DEFAULT_HOST_FIRMWARE;
}

template <class Cfg>
std::unique_ptr<BasicPlannerEndpoint<Cfg>> make_link_endpoint(const std::string& target, const std::string& firmware,
                                                              std::string* error, const LinkOptions& options) {
  try {
    if (target == "qemu" || target == "host") {
      const std::string image = firmware.empty() ? default_firmware(target, sim_config_of<Cfg>()) : firmware;
      return std::make_unique<LinkEndpoint<Cfg>>(target, image, options);
    }
    if (error != nullptr) *error = "unknown target '" + target + "'";
  } catch (const std::exception& e) {
    if (error != nullptr) *error = e.what();
  }
  return nullptr;
}

#define HIL_SIM_INSTANTIATE_LINK(Cfg)                                                                        \
  template std::unique_ptr<BasicPlannerEndpoint<Cfg>> make_link_endpoint<Cfg>(const std::string&,         \
                                                                              const std::string&, std::string*, \
                                                                              const LinkOptions&);
HIL_SIM_FOR_EACH_CONFIG(HIL_SIM_INSTANTIATE_LINK)
#undef HIL_SIM_INSTANTIATE_LINK

}  // namespace hil::sim
