// A measurement image, not a firmware: the instruction cost of the link's
// cryptography (AES-128-CMAC and the secure channel) on the target, and the
// link's whole share of a planning cycle at the largest Scene and Plan (the
// part of a firmware cycle outside the planner: tools/wcet_table.py adds it
// to the planner's derived bound). On
// mps2-an500 under `qemu-system-arm -icount shift=0` one tick of the 25 MHz
// counter is 40 guest instructions (docs/port.md), so each figure below is
// ticks x 40 over many repetitions (+-40 instructions / repetitions).
// Results go to the log line (UART1), ending with "done"; see
// docs/protocol.md, "Why AES-128-CMAC", for the command and the figures.
#include <array>
#include <cstddef>
#include <cstdint>
#include <new>

#include "firmware_config.hpp"
#include "itp/crypto/aes_cmac.hpp"
#include "itp/link/crc32.hpp"
#include "itp/link/frame_decoder.hpp"
#include "itp/link/planner_messages.hpp"
#include "itp/link/secure_channel.hpp"
#include "itp/link/segments.hpp"
#include "itp/planner/plan.hpp"
#include "itp/scene/scene.hpp"
#include "itp/scene/validation.hpp"
#include "port/firmware_run.hpp"
#include "port/port.hpp"

namespace {

namespace crypto = itp::crypto;
namespace link = itp::link;

constexpr std::uint64_t kInstructionsPerTick = 40;  // 1 GHz virtual instruction rate / 25 MHz timer
// A Scene as the closed loop sends it (about 1.6 KB, thinned), the largest Plan.
constexpr std::size_t kSceneBody = 1600;
constexpr std::size_t kPlanBody = itp::link::kMaxPlanBytes<port_image::FirmwareConfig>;
constexpr std::size_t kLargestSceneBody = itp::link::kMaxSceneBytes<port_image::FirmwareConfig>;
constexpr std::size_t kBufferBytes = kLargestSceneBody + link::kSecuredOverhead;

std::array<std::uint8_t, kBufferBytes> g_message{};
std::array<std::uint8_t, kBufferBytes> g_sealed{};
// Both ends, placed in static storage at start (no static destructors on target).
alignas(link::SecureChannel) std::byte g_host_storage[sizeof(link::SecureChannel)];
alignas(link::SecureChannel) std::byte g_fw_storage[sizeof(link::SecureChannel)];
link::SecureChannel* g_host_ptr = nullptr;
link::SecureChannel* g_fw_ptr = nullptr;
volatile std::uint8_t g_sink = 0;

// "name value" on the log line, without printf (no heap, no locale).
void report(const char* name, std::uint64_t value) {
  std::array<char, 96> line{};
  std::size_t n = 0;
  for (; name[n] != '\0' && n < 70; ++n) {  // names are short literals
    line[n] = name[n];
  }
  line[n++] = ' ';
  std::array<char, 20> digits{};
  std::size_t d = 0;
  do {  // at most 20 digits for a u64
    digits[d++] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0 && d < digits.size());
  while (d > 0) {  // d <= 20
    line[n++] = digits[--d];
  }
  line[n] = '\0';
  port::log_line(line.data());
}

std::uint64_t instructions(std::uint64_t ticks, std::uint64_t reps) { return ticks * kInstructionsPerTick / reps; }

void bench_cmac(const crypto::CmacKey& key, const char* name, std::size_t bytes, std::uint64_t reps) {
  const std::uint64_t t0 = port::counter_ticks();
  for (std::uint64_t r = 0; r < reps; ++r) {  // reps <= 1000
    const crypto::CmacTag tag = crypto::aes_cmac(key, std::span<const std::uint8_t>(g_message.data(), bytes));
    g_sink = static_cast<std::uint8_t>(g_sink ^ tag[0]);
  }
  report(name, instructions(port::counter_ticks() - t0, reps));
}

bool handshake(std::uint16_t seq) {
  link::SecureChannel& g_host = *g_host_ptr;
  link::SecureChannel& g_fw = *g_fw_ptr;
  std::array<std::uint8_t, link::kNonceBytes> nh{};
  nh[0] = static_cast<std::uint8_t>(seq);
  std::array<std::uint8_t, link::kHandshakeBytes> open{};
  std::array<std::uint8_t, link::kHandshakeBytes> challenge{};
  std::array<std::uint8_t, link::kHandshakeBytes> confirm{};
  const std::size_t n = g_host.start_handshake(nh, open);
  const std::uint64_t t0 = port::counter_ticks();
  const bool ok = g_fw.challenge(seq, std::span<const std::uint8_t>(open.data(), n), challenge) == link::AuthStatus::kOk;
  const std::uint64_t t1 = port::counter_ticks();
  const bool answered = ok && g_host.answer_challenge(seq, challenge, static_cast<std::uint16_t>(seq + 1), confirm) ==
                                  link::AuthStatus::kOk;
  const std::uint64_t t2 = port::counter_ticks();
  const bool confirmed = answered && g_fw.confirm(static_cast<std::uint16_t>(seq + 1), confirm) == link::AuthStatus::kOk;
  const std::uint64_t t3 = port::counter_ticks();
  std::array<std::uint8_t, link::kSecuredOverhead> accept{};
  const std::size_t m = g_fw.seal(link::MessageType::kSessionAccept, static_cast<std::uint16_t>(seq + 1), accept, 0);
  std::span<const std::uint8_t> body;
  const bool in_session = confirmed && m == accept.size() &&
                          g_host.open(link::MessageType::kSessionAccept, static_cast<std::uint16_t>(seq + 1), accept,
                                      body) == link::AuthStatus::kOk;
  report("firmware_challenge_instructions", (t1 - t0) * kInstructionsPerTick);
  report("host_answer_challenge_instructions", (t2 - t1) * kInstructionsPerTick);
  report("firmware_confirm_instructions", (t3 - t2) * kInstructionsPerTick);
  return in_session;
}

// The firmware's share of a cycle: open the host's sealed Scene, seal its Plan.
void bench_cycle(const char* open_name, std::size_t scene_body, const char* seal_name, std::size_t plan_body,
                 std::uint16_t reps) {
  std::uint64_t open_ticks = 0;
  std::uint64_t seal_ticks = 0;
  std::uint64_t accepted = 0;
  link::SecureChannel& g_host = *g_host_ptr;
  link::SecureChannel& g_fw = *g_fw_ptr;
  for (std::uint16_t r = 0; r < reps; ++r) {  // reps <= 100
    const std::size_t len = g_host.seal(link::MessageType::kPlanRequest, r, g_sealed, scene_body);
    std::span<const std::uint8_t> body;
    const std::uint64_t t0 = port::counter_ticks();
    const link::AuthStatus st =
        g_fw.open(link::MessageType::kPlanRequest, r, std::span<const std::uint8_t>(g_sealed.data(), len), body);
    const std::uint64_t t1 = port::counter_ticks();
    const std::size_t sent = g_fw.seal(link::MessageType::kPlanReply, r, g_message, plan_body);
    const std::uint64_t t2 = port::counter_ticks();
    accepted += (st == link::AuthStatus::kOk && sent == plan_body + link::kSecuredOverhead) ? 1u : 0u;
    open_ticks += t1 - t0;
    seal_ticks += t2 - t1;
  }
  report(open_name, instructions(open_ticks, reps));
  report(seal_name, instructions(seal_ticks, reps));
  report("cycles_authenticated", accepted);
}

// ---- The link's share of a cycle at the largest messages -------------------
// Everything the service does for one Scene besides planning it
// (app/firmware_service.hpp, on_byte .. next_frame): reassemble the request
// from its frames, open it (MAC, freshness), decode it, its CRC echo and its
// validation, then encode the Plan, seal it and cut it into frames. Each at
// the configuration's largest Scene (every vector full) and largest Plan
// (full trajectory, a decision per obstacle), in 255 segments each way: the
// most frames a message may take (per-frame costs at their worst; the
// closed loop sends far fewer). Costs other than the MAC depend on the
// element counts, not on the values.
using Cfg = port_image::FirmwareConfig;
using Scene = itp::scene::BasicScene<Cfg>;
using Plan = itp::planner::BasicPlan<Cfg>;
constexpr std::size_t kWireBytes = kBufferBytes + link::kMaxSegments * (link::kMaxWireFrameBytes - link::kMaxSegmentBytes);
std::array<std::uint8_t, kWireBytes> g_wire{};
std::array<std::uint8_t, link::kMaxWireFrameBytes> g_frame{};
Scene g_scene_in{};
Scene g_scene_out{};
Plan g_plan{};
link::FrameDecoder g_decoder{};
link::Inbox<kBufferBytes> g_inbox{};
link::Outbox<kBufferBytes> g_outbox{};

// A scene with every vector at capacity that passes validation.
void fill_largest_scene(Scene& sc) {
  sc.reset();
  for (int i = 0; i < Cfg::kMaxReferencePoints; ++i) {  // capacity
    static_cast<void>(sc.reference_line.push_back({static_cast<itp::Scalar>(i), itp::Scalar(0)}));
  }
  for (int i = 0; i < Cfg::kMaxBoundaryPoints; ++i) {  // capacity
    const auto s = static_cast<itp::Scalar>(i);
    static_cast<void>(sc.road.left.table.push_back({s, itp::Scalar(3) + itp::Scalar(0.001) * s}));
    static_cast<void>(sc.road.right.table.push_back({s, itp::Scalar(-3) - itp::Scalar(0.001) * s}));
  }
  sc.ego.state.x = itp::Scalar(1);
  sc.ego.state.v = itp::Scalar(10);
  for (int i = 0; i < Cfg::kMaxStaticObstacles; ++i) {  // capacity
    itp::scene::StaticObstacle o;
    o.id = 1 + i;
    o.x = itp::Scalar(20 + 5 * i);
    o.y = itp::Scalar(2.5);
    o.length = o.width = itp::Scalar(1);
    static_cast<void>(sc.static_obstacles.push_back(o));
  }
  for (int j = 0; j < Cfg::kMaxDynamicObstacles; ++j) {  // capacity
    itp::scene::BasicDynamicObstacle<Cfg> o;
    o.id = 1000 + j;
    o.length = itp::Scalar(4.5);
    o.width = itp::Scalar(1.8);
    for (int k = 0; k < Cfg::kMaxPredictionSamples; ++k) {  // capacity
      const auto t = itp::Scalar(0.1) * static_cast<itp::Scalar>(k);
      static_cast<void>(o.trajectory.push_back({t, itp::Scalar(30) + itp::Scalar(10) * t, itp::Scalar(-1.5),
                                                itp::Scalar(0), itp::Scalar(10)}));
    }
    static_cast<void>(sc.dynamic_obstacles.push_back(o));
  }
}

void fill_largest_plan(Plan& plan) {
  plan.status = itp::PlanStatus::kOk;
  plan.trajectory.clear();
  plan.decisions.clear();
  for (int i = 0; i < Cfg::kTrajectorySamples; ++i) {  // capacity
    const auto t = itp::Scalar(0.1) * static_cast<itp::Scalar>(i);
    static_cast<void>(plan.trajectory.push_back({t, itp::Scalar(10) * t, itp::Scalar(0.1), itp::Scalar(0.01),
                                                 itp::Scalar(0.001), itp::Scalar(10), itp::Scalar(0),
                                                 itp::Scalar(10) * t, itp::Scalar(0.1)}));
  }
  for (int i = 0; i < Cfg::kMaxObstacles; ++i) {  // capacity
    itp::planner::ObstacleDecision d;
    d.obstacle = 1 + i;
    d.lateral = itp::planner::LateralSide::kLeft;
    static_cast<void>(plan.decisions.push_back(d));
  }
}

// Frames of the message in `g_outbox` (staged) into g_wire; their total size.
std::size_t frames_to_wire() {
  std::size_t n = 0;
  for (std::size_t k = 0; k < link::kMaxSegments; ++k) {  // <= 255 frames
    const std::size_t f = g_outbox.next_frame(g_frame);
    if (f == 0 || n + f > g_wire.size()) {
      break;
    }
    for (std::size_t i = 0; i < f; ++i) {  // <= kMaxWireFrameBytes
      g_wire[n + i] = g_frame[i];
    }
    n += f;
  }
  return n;
}

// Segment size that cuts `length` bytes into the most segments a message may have.
std::size_t most_segments(std::size_t length) { return (length + link::kMaxSegments - 1) / link::kMaxSegments; }

void bench_link_share(std::uint16_t reps) {
  link::SecureChannel& g_host = *g_host_ptr;
  link::SecureChannel& g_fw = *g_fw_ptr;
  fill_largest_scene(g_scene_out);
  fill_largest_plan(g_plan);
  link::SceneHeader sh;
  sh.now = 1.0;
  const std::size_t scene_body = link::encode_scene(
      sh, g_scene_out, 1, std::span<std::uint8_t>(g_message.data() + link::kFreshnessBytes, kLargestSceneBody));
  std::uint64_t receive = 0, open = 0, decode = 0, encode = 0, seal = 0, send = 0;
  std::uint64_t ok = 0, frames_in = 0, frames_out = 0, plan_body = 0;
  for (std::uint16_t r = 0; r < reps; ++r) {  // reps <= 100
    const auto seq = static_cast<std::uint16_t>(1000 + r);
    // The host's side, untimed: seal the Scene and cut it into frames.
    for (std::size_t i = 0; i < scene_body; ++i) {  // <= kLargestSceneBody
      g_outbox.buffer()[link::kFreshnessBytes + i] = g_message[link::kFreshnessBytes + i];
    }
    const std::size_t sealed = g_host.seal(link::MessageType::kPlanRequest, seq, g_outbox.buffer(), scene_body);
    static_cast<void>(g_outbox.stage(link::MessageType::kPlanRequest, seq, sealed, most_segments(sealed), 0, false));
    const std::size_t wire = frames_to_wire();
    // The firmware's side, timed stage by stage.
    const std::uint64_t t0 = port::counter_ticks();
    bool complete = false;
    for (std::size_t i = 0; i < wire; ++i) {  // <= kWireBytes
      if (g_decoder.push(g_wire[i]) == link::DecodeResult::kFrame) {
        ++frames_in;
        complete = g_inbox.add(g_decoder.frame()) == link::InboxResult::kComplete;
      }
    }
    const std::uint64_t t1 = port::counter_ticks();
    std::span<const std::uint8_t> body;
    const bool opened = complete && g_fw.open(link::MessageType::kPlanRequest, seq, g_inbox.message(), body) ==
                                        link::AuthStatus::kOk;
    const std::uint64_t t2 = port::counter_ticks();
    link::SceneHeader header;
    const bool decoded = opened && link::decode_scene(body, header, g_scene_in);
    link::PlanHeader ph;
    ph.cycle = header.cycle;
    ph.scene_crc = link::crc32(body);
    const bool valid = decoded && itp::scene::validate(g_scene_in, static_cast<itp::Scalar>(header.now)).ok();
    const std::uint64_t t3 = port::counter_ticks();
    const std::size_t n =
        link::encode_plan(ph, g_plan, g_outbox.buffer().subspan(link::kFreshnessBytes, kLargestSceneBody));
    const std::uint64_t t4 = port::counter_ticks();
    const std::size_t m = g_fw.seal(link::MessageType::kPlanReply, seq, g_outbox.buffer(), n);
    const std::uint64_t t5 = port::counter_ticks();
    static_cast<void>(g_outbox.stage(link::MessageType::kPlanReply, seq, m, most_segments(m), 0, false));
    for (std::size_t k = 0; k < link::kMaxSegments; ++k) {  // <= 255 frames
      const std::size_t f = g_outbox.next_frame(g_frame);
      if (f == 0) {
        break;
      }
      ++frames_out;
      g_sink = static_cast<std::uint8_t>(g_sink ^ g_frame[f - 1]);
    }
    const std::uint64_t t6 = port::counter_ticks();
    ok += (valid && n > 0 && m == n + link::kSecuredOverhead) ? 1u : 0u;
    plan_body = n;
    receive += t1 - t0;
    open += t2 - t1;
    decode += t3 - t2;
    encode += t4 - t3;
    seal += t5 - t4;
    send += t6 - t5;
  }
  report("link_scene_body_bytes", scene_body);
  report("link_plan_body_bytes", plan_body);
  report("link_frames_in_per_cycle", frames_in / reps);
  report("link_frames_out_per_cycle", frames_out / reps);
  report("link_cycles", reps);
  report("link_cycles_valid", ok);
  report("link_receive_instructions", instructions(receive, reps));
  report("link_open_instructions", instructions(open, reps));
  report("link_decode_validate_instructions", instructions(decode, reps));
  report("link_encode_plan_instructions", instructions(encode, reps));
  report("link_seal_instructions", instructions(seal, reps));
  report("link_send_instructions", instructions(send, reps));
  report("link_share_instructions", instructions(receive + open + decode + encode + seal + send, reps));
}

}  // namespace

void firmware_run() {
  port::init();
  for (std::size_t i = 0; i < g_message.size(); ++i) {  // fixed size
    g_message[i] = static_cast<std::uint8_t>(i * 7 + 1);
    g_sealed[i] = g_message[i];
  }
  // RFC 4493's key; the figures do not depend on key or data (constant time).
  constexpr std::array<std::uint8_t, 16> kKey = {0x2b, 0x7e, 0x15, 0x16, 0x28, 0xae, 0xd2, 0xa6,
                                                 0xab, 0xf7, 0x15, 0x88, 0x09, 0xcf, 0x4f, 0x3c};
  crypto::CmacKey key;
  const std::uint64_t k0 = port::counter_ticks();
  for (int r = 0; r < 100; ++r) {  // 100 key set-ups
    key.set(kKey);
  }
  report("cmac_key_setup_instructions", instructions(port::counter_ticks() - k0, 100));
  bench_cmac(key, "cmac_0_bytes_instructions", 0, 1000);
  bench_cmac(key, "cmac_16_bytes_instructions", 16, 1000);
  bench_cmac(key, "cmac_64_bytes_instructions", 64, 500);
  bench_cmac(key, "cmac_1024_bytes_instructions", 1024, 100);
  bench_cmac(key, "cmac_4096_bytes_instructions", 4096, 50);
  report("secure_channel_bytes", sizeof(link::SecureChannel));
  report("cmac_key_bytes", sizeof(crypto::CmacKey));

  g_host_ptr = ::new (g_host_storage) link::SecureChannel(link::Role::kHost);  // placement: no heap
  g_fw_ptr = ::new (g_fw_storage) link::SecureChannel(link::Role::kFirmware);
  g_host_ptr->set_key(kKey);
  g_fw_ptr->set_key(kKey);
  std::array<std::uint8_t, link::kEntropyBytes> entropy{};
  entropy[0] = 1;
  g_fw_ptr->set_entropy(entropy);
  report("session_established", handshake(1) ? 1u : 0u);
  report("scene_body_bytes", kSceneBody);
  report("plan_body_bytes", kPlanBody);
  bench_cycle("open_scene_instructions", kSceneBody, "seal_plan_instructions", kPlanBody, 100);
  report("largest_scene_body_bytes", kLargestSceneBody);
  bench_cycle("open_largest_scene_instructions", kLargestSceneBody, "seal_plan_again_instructions", kPlanBody, 20);
  bench_link_share(10);
  report("sink", g_sink);
  port::log_line("done");
  for (;;) {  // parked: the runner stops QEMU after "done"
    port::idle();
  }
}
