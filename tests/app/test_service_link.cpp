// The simulator's LinkClient against the firmware service in process: the
// handshake, a planning cycle that matches the planner run directly on the
// scene the firmware decoded, and recovery from lost segments both ways.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "../planner/scene_builder.hpp"
#include "itp/configurations.hpp"
#include "itp/link/crc32.hpp"
#include "itp/link/planner_messages.hpp"
#include "itp/planner/planner.hpp"
#include "link/fault_injection.hpp"
#include "link/link_client.hpp"
#include "service_link.hpp"

using namespace itp::link;
using app_test::ServiceTransport;

namespace {

std::vector<std::uint8_t> scene_body(double now, bool reset, std::uint32_t cycle,
                                     const std::function<void(itp::scene::Scene&)>& mutate = {}) {
  auto scene = std::make_unique<itp::scene::Scene>(planner_test::road_scene(1, 0));
  planner_test::add_static(*scene, 1, 40, 0.2);
  planner_test::add_mover(*scene, 2, 60, 3.5, 0, 6);
  for (auto& p : scene->dynamic_obstacles[0].trajectory) p.t += now;  // predictions in scene time
  if (mutate) mutate(*scene);
  std::vector<std::uint8_t> body(kMaxSceneBytes<itp::DefaultConfig>);
  body.resize(encode_scene(SceneHeader{cycle, now, reset}, *scene, 1, body));
  return body;
}

// The scene body with its `now` field (f64 at offset 4) replaced: values the
// encoder would not produce from a sane scene, as a broken sender would.
std::vector<std::uint8_t> with_now(std::vector<std::uint8_t> body, double now) {
  const auto bits = std::bit_cast<std::uint64_t>(now);
  for (int i = 0; i < 8; ++i) body[4 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(bits >> (8 * i));
  return body;
}

struct PlannedReply {
  std::unique_ptr<itp::planner::Plan> plan = std::make_unique<itp::planner::Plan>();
  PlanHeader header;
};

PlannedReply plan_over(hil::LinkClient& client, const std::vector<std::uint8_t>& body) {
  const auto reply = client.request(MessageType::kPlanRequest, body, std::chrono::seconds(10));
  REQUIRE(reply);
  REQUIRE(reply->type == MessageType::kPlanReply);
  PlannedReply out;
  REQUIRE(decode_plan(reply->payload, out.header, *out.plan));
  return out;
}

// The planner run directly on the scene as the firmware decodes it.
std::unique_ptr<itp::planner::Plan> reference_plan(const std::vector<std::uint8_t>& body) {
  auto wire = std::make_unique<itp::scene::Scene>();
  SceneHeader h;
  REQUIRE(decode_scene(body, h, *wire));
  auto planner = std::make_unique<itp::planner::Planner>();
  auto plan = std::make_unique<itp::planner::Plan>();
  planner->plan({wire.get(), h.now}, *plan);
  return plan;
}

hil::ClientPacing fast_pacing() {
  hil::ClientPacing p;
  p.first_gap = std::chrono::milliseconds(5);
  p.gap = std::chrono::milliseconds(2);
  p.nudge_after = std::chrono::milliseconds(0);
  p.frame_settle = std::chrono::microseconds(0);
  return p;
}

}  // namespace

TEST_CASE("the client opens a session and the firmware plans the Scene it was sent") {
  auto svc = app_test::provisioned_service();
  ServiceTransport link(*svc);
  hil::LinkClient client(link, fast_pacing());
  client.set_key(app_test::test_key());
  const auto body = scene_body(0.0, true, 1);
  const auto reply = client.request(MessageType::kPlanRequest, body, std::chrono::seconds(10));
  REQUIRE(reply);
  REQUIRE(reply->type == MessageType::kPlanReply);
  CHECK(client.counters().sessions == 1);
  auto plan = std::make_unique<itp::planner::Plan>();
  PlanHeader ph;
  REQUIRE(decode_plan(reply->payload, ph, *plan));
  CHECK(ph.cycle == 1);
  CHECK(ph.scene_crc == crc32(body));
  const auto expected = reference_plan(body);
  CHECK(plan->status == expected->status);
  REQUIRE(plan->trajectory.size() == expected->trajectory.size());
  for (std::size_t k = 0; k < plan->trajectory.size(); ++k) {
    CHECK(plan->trajectory[k].x == doctest::Approx(expected->trajectory[k].x).epsilon(1e-6));
    CHECK(plan->trajectory[k].v == doctest::Approx(expected->trajectory[k].v).epsilon(1e-5));
  }
  CHECK(svc->counters().auth.accepted == 1);
}

TEST_CASE("a client with the wrong key gets no session and no plan") {
  auto svc = app_test::provisioned_service(1);
  ServiceTransport link(*svc);
  hil::LinkClient client(link, fast_pacing());
  client.set_key(app_test::test_key(2));
  const auto reply = client.request(MessageType::kPlanRequest, scene_body(0.0, true, 1), std::chrono::milliseconds(300));
  CHECK_FALSE(reply);
  CHECK(client.counters().sessions == 0);
  CHECK(svc->counters().auth.accepted == 0);
  CHECK_FALSE(svc->in_session());
}

TEST_CASE("lost request and reply segments are asked for and resent until the plan arrives") {
  auto svc = app_test::provisioned_service();
  ServiceTransport link(*svc);
  hil::ClientPacing pacing = fast_pacing();
  pacing.max_segment = 64;  // many segments, so that losses hit every part
  hil::LinkClient client(link, pacing);
  client.set_key(app_test::test_key());
  REQUIRE(client.open_session(std::chrono::seconds(5)));
  int frame_no = 0;
  int lost = 0;
  link.set_filter([&](ServiceTransport::Direction, const FrameView& f) {
    // Every third segment of a Scene or Plan is lost the first time it is seen.
    const bool payload = f.header.type == MessageType::kPlanRequest || f.header.type == MessageType::kPlanReply;
    const bool lose = payload && (frame_no++ % 3 == 0) && f.header.segment_index % 2 == 0;
    lost += lose ? 1 : 0;
    return lose;
  });
  for (std::uint32_t cycle = 1; cycle <= 3; ++cycle) {
    const auto body = scene_body(0.1 * cycle, cycle == 1, cycle);
    const auto reply = client.request(MessageType::kPlanRequest, body, std::chrono::seconds(10));
    REQUIRE(reply);
    REQUIRE(reply->type == MessageType::kPlanReply);
    auto plan = std::make_unique<itp::planner::Plan>();
    PlanHeader ph;
    REQUIRE(decode_plan(reply->payload, ph, *plan));
    CHECK(ph.cycle == cycle);
    CHECK(ph.scene_crc == crc32(body));
  }
  CHECK(lost > 5);
  CHECK(client.counters().segments_resent > 0);   // the firmware's Status named what it missed
  CHECK(svc->counters().resent > 0);              // the client's Query named what it missed
  CHECK(svc->counters().auth.accepted == 3);      // each Scene planned exactly once
  CHECK(client.counters().timeouts == 0);
}

TEST_CASE("with shared QP storage the request is reassembled in the planner's storage, segments lost or not") {
  // LowRamConfig: the default sizes, the QPs sharing one storage, which the
  // inbox borrows between cycles (app/firmware_service.hpp).
  using LowRamService = itp::app::FirmwareService<itp::LowRamConfig>;
  static_assert(LowRamService::kInboxInQpStorage && !app_test::Service::kInboxInQpStorage);
  auto svc = app_test::provisioned_service<LowRamService>();
  app_test::BasicServiceTransport<LowRamService> link(*svc);
  hil::ClientPacing pacing = fast_pacing();
  pacing.max_segment = 64;
  hil::LinkClient client(link, pacing);
  client.set_key(app_test::test_key());
  REQUIRE(client.open_session(std::chrono::seconds(5)));
  int frame_no = 0;
  link.set_filter([&](auto, const FrameView& f) {
    return f.header.type == MessageType::kPlanRequest && (frame_no++ % 4 == 0) && f.header.segment_index % 2 == 0;
  });
  // The planner on the host, fed the same scenes in the same order.
  auto planner = std::make_unique<itp::planner::BasicPlanner<itp::LowRamConfig>>();
  for (std::uint32_t cycle = 1; cycle <= 4; ++cycle) {
    const auto body = scene_body(0.1 * cycle, cycle == 1, cycle);
    const PlannedReply got = plan_over(client, body);
    CHECK(got.header.scene_crc == crc32(body));
    auto wire = std::make_unique<itp::scene::BasicScene<itp::LowRamConfig>>();
    SceneHeader h;
    REQUIRE(decode_scene(body, h, *wire));
    const auto& expected = planner->plan({wire.get(), h.now});
    CHECK(got.plan->status == expected.status);
    REQUIRE(got.plan->trajectory.size() == expected.trajectory.size());
    for (std::size_t k = 0; k < expected.trajectory.size(); ++k) {
      CHECK(got.plan->trajectory[k].x == doctest::Approx(expected.trajectory[k].x).epsilon(1e-6));
      CHECK(got.plan->trajectory[k].v == doctest::Approx(expected.trajectory[k].v).epsilon(1e-5));
    }
  }
  CHECK(client.counters().segments_resent > 0);
  CHECK(svc->counters().auth.accepted == 4);
}

TEST_CASE("a request repeated whole is answered again but planned once") {
  auto svc = app_test::provisioned_service();
  ServiceTransport link(*svc);
  hil::LinkClient client(link, fast_pacing());
  client.set_key(app_test::test_key());
  REQUIRE(client.open_session(std::chrono::seconds(5)));
  // Lose the whole first Plan reply: the client's Query finds it; the firmware
  // must not plan the Scene a second time.
  bool dropped = false;
  link.set_filter([&](ServiceTransport::Direction d, const FrameView& f) {
    if (d == ServiceTransport::Direction::kToHost && f.header.type == MessageType::kPlanReply && !dropped) {
      dropped = f.header.segment_index + 1 == f.header.segment_count;
      return true;
    }
    return false;
  });
  const auto reply = client.request(MessageType::kPlanRequest, scene_body(0.0, true, 1), std::chrono::seconds(10));
  REQUIRE(reply);
  CHECK(reply->type == MessageType::kPlanReply);
  CHECK(client.counters().queries >= 1);
  CHECK(svc->counters().auth.accepted == 1);
}

// Issue 13, defect 1: the scene time is validated where it enters.
TEST_CASE("a Scene whose time is NaN, infinite, huge or negative is invalid_input, never planned") {
  auto svc = app_test::provisioned_service();
  ServiceTransport link(*svc);
  hil::LinkClient client(link, fast_pacing());
  client.set_key(app_test::test_key());
  const auto good = scene_body(0.0, true, 1, [](itp::scene::Scene& s) { s.dynamic_obstacles.clear(); });
  std::uint32_t cycle = 1;
  for (const double now : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(), 1e300, -1.0}) {
    const auto r = plan_over(client, with_now(good, now));
    CHECK_MESSAGE(r.plan->status == itp::PlanStatus::kInvalidInput, "now = ", now);
    CHECK(r.plan->invalid == itp::scene::ValidationReason::kSceneTimeOutOfRange);
    CHECK(r.plan->trajectory.empty());
    ++cycle;
  }
  // The planner never saw those: the next good cycle plans as a fresh one.
  const auto ok = plan_over(client, good);
  CHECK(ok.plan->status == itp::PlanStatus::kOk);
}

// Issue 13, defect 2 (firmware part): a reply never repeats unvalidated input.
TEST_CASE("an invalid_input reply carries no unvalidated number: origin 0, no trajectory") {
  auto svc = app_test::provisioned_service();
  ServiceTransport link(*svc);
  hil::LinkClient client(link, fast_pacing());
  client.set_key(app_test::test_key());
  const std::vector<std::function<void(itp::scene::Scene&)>> bad = {
      [](itp::scene::Scene& s) { s.reference_line[0].x = std::numeric_limits<double>::quiet_NaN(); },
      [](itp::scene::Scene& s) { s.ego.state.v = 1e9; },
      [](itp::scene::Scene& s) { s.ego.state.heading = 1e30; },
  };
  std::uint32_t cycle = 1;
  for (const auto& mutate : bad) {
    const auto r = plan_over(client, scene_body(0.0, true, cycle++, mutate));
    CHECK(r.plan->status == itp::PlanStatus::kInvalidInput);
    CHECK(r.header.origin_x == 0.0);
    CHECK(r.header.origin_y == 0.0);
    CHECK(r.plan->trajectory.empty());
  }
}

// Issue 13, defect 3: a scene with moving obstacles keeps planning after an hour.
TEST_CASE("scenes with moving obstacles plan at a scene time of an hour and of a day") {
  auto svc = app_test::provisioned_service();
  ServiceTransport link(*svc);
  hil::LinkClient client(link, fast_pacing());
  client.set_key(app_test::test_key());
  std::uint32_t cycle = 1;
  for (const double now : {3600.0, 4000.0, 86400.0}) {
    const auto r = plan_over(client, scene_body(now, true, cycle++));
    CHECK_MESSAGE(r.plan->status == itp::PlanStatus::kOk, "now = ", now, ": ",
                  itp::scene::to_string(r.plan->invalid));
  }
}

// Issue 13, defect 12: at 1 % byte faults no scene frame got through (no
// retransmission, and a 3 KB frame has a 5e-14 chance of arriving intact).
TEST_CASE("at 1 % byte faults both ways, Scenes and Plans get through by retransmission, none corrupted") {
  auto svc = app_test::provisioned_service();
  ServiceTransport service_link(*svc);
  hil::LinkFaults faults;
  faults.drop = faults.dup = faults.flip = faults.reorder = 0.0025;
  faults.seed = 12;
  hil::FaultyTransport link(service_link, faults);
  hil::LinkClient client(link, fast_pacing());
  client.set_key(app_test::test_key());
  int planned = 0;
  constexpr int kCycles = 40;
  for (std::uint32_t cycle = 1; cycle <= kCycles; ++cycle) {
    const auto body = scene_body(0.1 * cycle, cycle == 1, cycle);
    const auto reply = client.request(MessageType::kPlanRequest, body, std::chrono::seconds(2));
    if (!reply || reply->type != MessageType::kPlanReply) continue;
    auto plan = std::make_unique<itp::planner::Plan>();
    PlanHeader ph;
    REQUIRE(decode_plan(reply->payload, ph, *plan));
    CHECK(ph.scene_crc == crc32(body));  // the firmware planned exactly what was sent
    CHECK(ph.cycle == cycle);
    ++planned;
  }
  MESSAGE("1 % byte faults: ", planned, " of ", kCycles, " cycles planned; ", link.to_firmware().faults(),
          " faults to the firmware, ", link.to_host().faults(), " to the host; final segment size ",
          client.segment_size());
  CHECK(planned >= kCycles - 2);
  CHECK(link.to_firmware().faults() > 20);
  CHECK(link.to_host().faults() > 20);
}
