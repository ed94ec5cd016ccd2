// A measurement image, not a firmware: the instruction cost of the link's
// cryptography (AES-128-CMAC and the secure channel) on the target. On
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
#include "itp/link/planner_messages.hpp"
#include "itp/link/secure_channel.hpp"
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
  report("sink", g_sink);
  port::log_line("done");
  for (;;) {  // parked: the runner stops QEMU after "done"
    port::idle();
  }
}
