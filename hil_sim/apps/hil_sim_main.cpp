// hil_sim: the host simulator. It talks to a firmware over the framed serial
// link. For now it has one job, `ping`: boot the firmware (host process or the
// Cortex-M7 ELF under QEMU), exchange Ping/Pong, optionally inject garbage and
// corrupt frames first, and report what the link counted.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <chrono>
#include <random>

#include "itp/link/messages.hpp"
#include "link/child_process.hpp"
#include "link/link_client.hpp"

namespace {

struct PingOptions {
  std::string target = "qemu";
  std::string firmware;
  std::string log;
  int count = 10;
  int timeout_ms = 5000;
  bool garbage = false;
  std::uint32_t seed = 1;
};

// Random bytes, a frame with one bit flipped and a truncated frame: the
// firmware must drop and count all of them, then still answer.
std::vector<std::uint8_t> make_garbage(std::mt19937& rng) {
  std::vector<std::uint8_t> junk(300);
  for (auto& b : junk) {
    b = static_cast<std::uint8_t>(rng());
  }
  junk.push_back(0u);
  std::array<std::uint8_t, 64> frame{};
  std::array<std::uint8_t, 4> body{1, 2, 3, 4};
  const std::size_t n = itp::link::encode_frame(itp::link::MessageType::kPing, 999, body, frame);
  std::vector<std::uint8_t> flipped(frame.begin(), frame.begin() + static_cast<long>(n));
  flipped[3] ^= 0x10u;
  if (flipped[3] == 0u) {
    flipped[3] = 0x55u;
  }
  junk.insert(junk.end(), flipped.begin(), flipped.end());
  junk.insert(junk.end(), frame.begin(), frame.begin() + static_cast<long>(n / 2));
  junk.push_back(0u);
  return junk;
}

int run_ping(const PingOptions& opt) {
  std::vector<std::string> cmd;
  if (opt.target == "qemu") {
    cmd = hil::qemu_command(opt.firmware.empty() ? ITP_DEFAULT_QEMU_FIRMWARE : opt.firmware, opt.log);
  } else {
    cmd = hil::host_firmware_command(opt.firmware.empty() ? ITP_DEFAULT_HOST_FIRMWARE : opt.firmware);
  }
  fmt::print("starting {} firmware: {}\n", opt.target, fmt::join(cmd, " "));
  hil::ChildProcess child(cmd, opt.target == "host" ? opt.log : "");
  hil::LinkClient client(child);
  std::mt19937 rng(opt.seed);
  const auto timeout = std::chrono::milliseconds(opt.timeout_ms);

  int failures = 0;
  std::string build_id;
  std::uint64_t first_ticks = 0;
  std::uint64_t last_ticks = 0;
  std::uint64_t tick_hz = 0;
  bool counter_ok = true;
  itp::link::LinkCounters fw_counters;
  for (int i = 0; i < opt.count; ++i) {
    if (opt.garbage && i % 2 == 1) {
      client.send_raw(make_garbage(rng));
    }
    itp::link::Ping ping{static_cast<std::uint32_t>(rng())};
    std::array<std::uint8_t, itp::link::kPingBytes> body{};
    itp::link::encode(ping, body);
    const auto t0 = std::chrono::steady_clock::now();
    const auto reply = client.request(itp::link::MessageType::kPing, body, timeout);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    itp::link::Pong pong;
    if (!reply || reply->type != itp::link::MessageType::kPong ||
        !itp::link::decode(reply->payload, pong) || pong.nonce != ping.nonce) {
      ++failures;
      fmt::print("ping {:3}: no valid pong\n", i);
      client.resync();
      continue;
    }
    build_id = pong.build_id.data();
    fw_counters = pong.counters;
    if (first_ticks == 0) {
      first_ticks = pong.ticks;
    } else if (pong.ticks <= last_ticks) {
      counter_ok = false;  // the port's counter must be monotonic and running
    }
    last_ticks = pong.ticks;
    tick_hz = pong.tick_hz;
    fmt::print("ping {:3}: pong in {:7.2f} ms, firmware counter {} ticks\n", i, ms, pong.ticks);
  }
  const auto& cc = client.counters();
  fmt::print("firmware build id : {}\n", build_id.empty() ? "(none)" : build_id);
  fmt::print("round trips       : {} ok, {} failed, {} timeouts\n", opt.count - failures, failures, cc.timeouts);
  fmt::print("firmware counted  : {} frames ok, {} dropped (cobs {}, length {}, crc {}, version {}, overflow {})\n",
             fw_counters.frames_ok, fw_counters.dropped(), fw_counters.cobs_errors,
             fw_counters.length_errors, fw_counters.crc_errors, fw_counters.version_errors,
             fw_counters.overflows);
  fmt::print("firmware counter  : {} Hz, {} ticks between first and last pong\n", tick_hz,
             last_ticks - first_ticks);
  if (!counter_ok || tick_hz == 0) {
    fmt::print("error: the firmware's counter is not running or not monotonic\n");
    ++failures;
  }
  if (opt.garbage && opt.count > 2 && fw_counters.dropped() == 0) {
    fmt::print("error: garbage was sent but the firmware counted no dropped frame\n");
    ++failures;
  }
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hil_sim: host simulator for the itplan firmware over the framed serial link"};
  app.require_subcommand(1);

  PingOptions ping;
  auto* ping_cmd = app.add_subcommand("ping", "Boot a firmware and exchange Ping/Pong over the link");
  ping_cmd->add_option("--target", ping.target, "Firmware to talk to")
      ->check(CLI::IsMember({"host", "qemu"}))
      ->capture_default_str();
  ping_cmd->add_option("--firmware", ping.firmware,
                       "Firmware executable (host) or ELF (qemu); defaults to this build's");
  ping_cmd->add_option("--log", ping.log, "File for the firmware's log lines");
  ping_cmd->add_option("--count", ping.count, "Number of round trips")->check(CLI::PositiveNumber)->capture_default_str();
  ping_cmd->add_option("--timeout-ms", ping.timeout_ms, "Reply timeout per request")->capture_default_str();
  ping_cmd->add_flag("--garbage", ping.garbage, "Inject garbage, bit flips and truncated frames between pings");
  ping_cmd->add_option("--seed", ping.seed, "Seed for nonces and garbage")->capture_default_str();

  CLI11_PARSE(app, argc, argv);
  try {
    if (*ping_cmd) {
      return run_ping(ping);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "hil_sim: {}\n", e.what());
    return 2;
  }
  return 0;
}
