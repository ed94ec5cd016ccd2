// hil_sim: the host simulator. `run` drives the planner in closed loop over
// generated or given scenes (inproc, or a firmware over the framed serial
// link); `ping` boots the firmware (host process or the Cortex-M7 ELF under
// QEMU), exchanges Ping/Pong, optionally injects garbage and corrupt frames
// first, and reports what the link counted; `qp-check` compares QP solutions
// on the host and the firmware; `gen` writes generated scenes; `import` turns
// a CommonRoad XML scenario into scene/1 (docs/commonroad.md).
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <cmath>
#include <random>
#include <thread>

#include "apps/common_options.hpp"
#include "apps/run_command.hpp"
#include "formats/qp_text.hpp"
#include "sim/report_compare.hpp"
#include "sim/scene_files.hpp"
#include "sim/scene_generator.hpp"
#include "sim/world.hpp"
#include "itp/link/messages.hpp"
#include "itp/link/qp_messages.hpp"
#include "itp/qp/qp.hpp"
#include "link/firmware_process.hpp"
#include "link/link_client.hpp"

namespace {

struct PingOptions {
  hil::apps::TargetOptions target{"qemu", "default", "", ""};
  std::string log;
  int count = 10;
  int timeout_ms = 5000;
  bool garbage = false;
  bool fill_pipe = false;
  std::uint32_t seed = 1;
};

// Shrinks the firmware's output pipe to one page and sends, back to back and
// without reading, just enough Pings that the last Pong overflows it: the
// firmware has then no input left and its transmitter is full. After a
// second the host reads, without a nudge: every Pong must arrive. A firmware
// that waits for transmit room only until the next received byte stalls
// here for good (issue 13, defect 10).
int run_burst(hil::ByteTransport& link, int count, int timeout_ms);

int run_fill_pipe(hil::ChildProcess& child, int timeout_ms) {
  const std::size_t capacity = child.set_output_pipe_size(4096);
  constexpr std::size_t kPongWire = 2 + 1 + itp::link::kHeaderBytes + itp::link::kPongBytes + itp::link::kCrcBytes;
  if (capacity == 0) {
    fmt::print("fill-pipe: cannot set the pipe size\n");
    return 1;
  }
  const int count = static_cast<int>(capacity / kPongWire) + 1;
  fmt::print("fill-pipe: pipe of {} bytes, {} Pongs of {} bytes\n", capacity, count, kPongWire);
  return run_burst(child, count, timeout_ms);
}

int run_burst(hil::ByteTransport& link, int count, int timeout_ms) {
  std::vector<std::uint8_t> out;
  std::array<std::uint8_t, itp::link::kMaxWireFrameBytes> frame{};
  for (int i = 0; i < count; ++i) {
    std::array<std::uint8_t, itp::link::kPingBytes> body{};
    itp::link::encode(itp::link::Ping{static_cast<std::uint32_t>(i)}, body);
    const std::size_t n = itp::link::encode_frame(itp::link::MessageType::kPing, static_cast<std::uint16_t>(i), body, frame);
    out.insert(out.end(), frame.begin(), frame.begin() + static_cast<long>(n));
  }
  if (!link.write_all(out)) {
    fmt::print("burst: the firmware is gone\n");
    return 1;
  }
  std::this_thread::sleep_for(std::chrono::seconds(1));
  itp::link::FrameDecoder dec;
  std::vector<bool> seen(static_cast<std::size_t>(count), false);
  int pongs = 0;
  std::array<std::uint8_t, 4096> rx{};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (pongs < count && std::chrono::steady_clock::now() < deadline) {
    const std::size_t n = link.read_some(rx, std::chrono::milliseconds(100));
    for (std::size_t i = 0; i < n; ++i) {
      itp::link::Pong pong;
      if (dec.push(rx[i]) == itp::link::DecodeResult::kFrame && dec.frame().header.type == itp::link::MessageType::kPong &&
          itp::link::decode(dec.frame().chunk, pong) && pong.nonce < seen.size() && !seen[pong.nonce]) {
        seen[pong.nonce] = true;
        ++pongs;
      }
    }
  }
  fmt::print("burst: {} pings sent back to back, {} pongs received without a nudge\n", count, pongs);
  return pongs == count ? 0 : 1;
}

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
  const hil::sim::SimConfig config = hil::apps::sim_config(opt.target);
  const std::string firmware = hil::apps::firmware_image(opt.target, hil::sim::default_firmware("host", config),
                                                         hil::sim::default_firmware("qemu", config));
  fmt::print("starting {} firmware: {}\n", opt.target.name, firmware);
  const hil::LinkKey key = hil::link_key_from(opt.target.key_file);
  hil::FirmwareProcess fw(opt.target.name, firmware, key, opt.log);
  if (opt.fill_pipe) {
    return run_fill_pipe(fw.process(), opt.timeout_ms);
  }
  hil::LinkClient client(fw.process());
  client.set_key(key);
  std::mt19937 rng(opt.seed);
  const auto timeout = std::chrono::milliseconds(opt.timeout_ms);

  int failures = 0;
  std::string build_id;
  std::uint64_t first_ticks = 0;
  std::uint64_t last_ticks = 0;
  std::uint64_t tick_hz = 0;
  bool counter_ok = true;
  itp::link::FirmwareCounters fw_counters;
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
  // The authenticated session: the key reached the firmware (key slot or file).
  const bool session = client.open_session(timeout);
  fmt::print("session           : {}\n", session ? "established (the firmware holds the link key)" : "FAILED");
  failures += session ? 0 : 1;
  const auto& cc = client.counters();
  const itp::link::LinkCounters& fl = fw_counters.link;
  fmt::print("firmware build id : {}\n", build_id.empty() ? "(none)" : build_id);
  fmt::print("round trips       : {} ok, {} failed, {} timeouts, {} queries\n", opt.count - failures, failures,
             cc.timeouts, cc.queries);
  fmt::print("firmware counted  : {} frames ok, {} dropped (cobs {}, length {}, crc {}, version {}, overflow {})\n",
             fl.frames_ok, fl.dropped(), fl.cobs_errors, fl.length_errors, fl.crc_errors, fl.version_errors,
             fl.overflows);
  fmt::print("firmware counter  : {} Hz, {} ticks between first and last pong\n", tick_hz,
             last_ticks - first_ticks);
  if (!counter_ok || tick_hz == 0) {
    fmt::print("error: the firmware's counter is not running or not monotonic\n");
    ++failures;
  }
  if (opt.garbage && opt.count > 2 && fl.dropped() == 0) {
    fmt::print("error: garbage was sent but the firmware counted no dropped frame\n");
    ++failures;
  }
  return failures == 0 ? 0 : 1;
}

struct QpCheckOptions {
  hil::apps::TargetOptions target{"qemu", "default", "", ""};
  std::vector<std::string> files;
  double tolerance = 1e-9;
  int timeout_ms = 20000;
};

// Solves each QP file on the host and on the firmware (cold start both) and
// compares: same status, and x equal to `tolerance` relative to max(1, |x|inf).
int run_qp_check(const QpCheckOptions& opt) {
  using D = itp::qp::PathQpDims<double, itp::DefaultConfig>;
  static itp::qp::QpProblem<D> problem;
  static itp::qp::QpWorkspace<D> workspace;
  static itp::qp::QpResult<D> host;
  static std::array<std::uint8_t, itp::link::kMaxQpRequestBytes<D>> body{};
  // The QP-check service lives in the test firmware image only.
  const std::string firmware = hil::apps::firmware_image(opt.target, ITP_DEFAULT_HOST_QP_CHECK_FIRMWARE,
                                                         ITP_DEFAULT_QEMU_QP_CHECK_FIRMWARE);
  const hil::LinkKey key = hil::link_key_from(opt.target.key_file);
  hil::FirmwareProcess fw(opt.target.name, firmware, key);
  hil::LinkClient client(fw.process());
  client.set_key(key);
  int failures = 0;
  double worst = 0;
  fmt::print("{:<28} {:>10} {:>10} {:>6} {:>12} {:>14}\n", "file", "host", "target", "iters", "rel. diff",
             opt.target.name == "qemu" ? "instructions" : "target ticks");
  for (const std::string& path : opt.files) {
    hil::formats::QpText text;
    std::string error;
    if (!hil::formats::read_qp_text_file(path, text, error) || !hil::formats::to_problem(text, problem, error)) {
      fmt::print("{}: {}\n", path, error);
      ++failures;
      continue;
    }
    itp::qp::solve_cold(problem, workspace, itp::qp::QpSettings<double>{}, host);
    const std::size_t n = itp::link::encode_qp_request(problem, body);
    const auto reply = n == 0 ? std::nullopt
                              : client.request(itp::link::MessageType::kQpSolveRequest,
                                               std::span<const std::uint8_t>(body.data(), n),
                                               std::chrono::milliseconds(opt.timeout_ms));
    itp::link::QpSolveReply<D> target;
    if (!reply || reply->type != itp::link::MessageType::kQpSolveReply || !itp::link::decode(reply->payload, target)) {
      fmt::print("{}: no valid reply from the firmware\n", path);
      client.resync();
      ++failures;
      continue;
    }
    double scale = 1;
    double diff = 0;
    for (int i = 0; i < problem.n; ++i) {
      scale = std::max(scale, std::fabs(host.x[i]));
    }
    for (int i = 0; i < problem.n; ++i) {
      diff = std::max(diff, std::fabs(host.x[i] - target.x[i]));
    }
    const bool usable = itp::qp::is_usable(host.status);
    const double rel = usable ? diff / scale : 0.0;
    const bool ok = host.status == target.status && rel <= opt.tolerance;
    worst = std::max(worst, rel);
    const double instr = opt.target.name == "qemu" ? static_cast<double>(target.ticks) * 40.0 : static_cast<double>(target.ticks);
    const auto slash = path.find_last_of('/');
    fmt::print("{:<28} {:>10} {:>10} {:>6} {:>12.3e} {:>14.0f}{}\n", path.substr(slash == std::string::npos ? 0 : slash + 1),
               itp::qp::to_string(host.status), itp::qp::to_string(target.status), target.iterations, rel, instr,
               ok ? "" : "  MISMATCH");
    failures += ok ? 0 : 1;
  }
  fmt::print("{} files, {} mismatches, largest relative difference {:.3e} (tolerance {:.1e})\n", opt.files.size(),
             failures, worst, opt.tolerance);
  return failures == 0 ? 0 : 1;
}

struct GenOptions {
  int count = 200;
  std::uint64_t seed = 1;
  std::string out = "scenes";
};

// Writes generated scenes as scene/1 files DIR/paper-NNNN.json.
int run_gen(const GenOptions& opt) {
  std::filesystem::create_directories(opt.out);
  for (int i = 0; i < opt.count; ++i) {
    const hil::sim::World w = hil::sim::generate_scene(opt.seed, i);
    const std::string path = fmt::format("{}/{}.json", opt.out, w.name);
    const std::string err = hil::sim::save_scene_file(w, path);
    if (!err.empty()) {
      fmt::print(stderr, "hil_sim gen: {}\n", err);
      return 2;
    }
  }
  fmt::print("wrote {} scenes (seed {}) to {}\n", opt.count, opt.seed, opt.out);
  return 0;
}

struct ImportOptions {
  std::string file;
  std::string out;  // "" = stdout
  hil::sim::CommonRoadOptions commonroad;
  bool quiet = false;
};

// CommonRoad XML -> scene/1 JSON (stdout, or --out FILE); notes and the
// summary go to stderr, so that stdout stays the scene alone.
int run_import(const ImportOptions& opt) {
  hil::sim::LoadedScene loaded = hil::sim::load_scene(opt.file, opt.commonroad);
  if (!loaded) {
    fmt::print(stderr, "hil_sim import: {}\n", loaded.error);
    return 2;
  }
  if (loaded.kind != hil::sim::SceneFileKind::kCommonRoadXml) {
    fmt::print(stderr, "hil_sim import: {}: not a CommonRoad XML file (a scene/1 file needs no import)\n", opt.file);
    return 2;
  }
  if (!opt.quiet) {
    for (const std::string& note : loaded.notes) fmt::print(stderr, "hil_sim import: {}\n", note);
  }
  const hil::sim::World& w = *loaded.world;
  if (opt.out.empty()) {
    fmt::print("{}\n", hil::sim::scene_to_text(w));
  } else {
    const std::string err = hil::sim::save_scene_file(w, opt.out);
    if (!err.empty()) {
      fmt::print(stderr, "hil_sim import: {}\n", err);
      return 2;
    }
  }
  fmt::print(stderr,
             "hil_sim import: {} -> {}: {} reference points, {} static + {} dynamic obstacles, speed limit {:.2f} m/s, "
             "duration {:.1f} s\n",
             opt.file, opt.out.empty() ? std::string("stdout") : opt.out, w.reference_line.size(),
             w.static_obstacles.size(), w.dynamic_obstacles.size(), w.road.speed_limit, w.duration.value_or(0.0));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hil_sim: host simulator for the itplan firmware over the framed serial link"};
  app.require_subcommand(1);

  PingOptions ping;
  auto* ping_cmd = app.add_subcommand("ping", "Boot a firmware and exchange Ping/Pong over the link");
  hil::apps::add_target_option(*ping_cmd, ping.target, {"host", "qemu"});
  hil::apps::add_config_option(*ping_cmd, ping.target);
  hil::apps::add_firmware_option(*ping_cmd, ping.target);
  ping_cmd->add_option("--log", ping.log, "File for the firmware's log lines");
  hil::apps::add_key_option(*ping_cmd, ping.target);
  ping_cmd->add_option("--count", ping.count, "Number of round trips")->check(CLI::PositiveNumber)->capture_default_str();
  ping_cmd->add_option("--timeout-ms", ping.timeout_ms, "Reply timeout per request")->capture_default_str();
  ping_cmd->add_flag("--garbage", ping.garbage, "Inject garbage, bit flips and truncated frames between pings");
  ping_cmd->add_flag("--fill-pipe", ping.fill_pipe,
                     "Instead: overflow a one-page output pipe with the last of a burst of Pongs, then read them "
                     "all without nudging (the transmitter must wake the firmware)");
  ping_cmd->add_option("--seed", ping.seed, "Seed for nonces and garbage")->capture_default_str();

  QpCheckOptions qp;
  auto* qp_cmd = app.add_subcommand("qp-check", "Solve qp-text/1 files on the host and on the firmware, and compare");
  qp_cmd->add_option("files", qp.files, "qp-text/1 files")->required()->check(CLI::ExistingFile);
  hil::apps::add_target_option(*qp_cmd, qp.target, {"host", "qemu"});
  hil::apps::add_firmware_option(*qp_cmd, qp.target, "this build's test image, which has the QP-check service");
  hil::apps::add_key_option(*qp_cmd, qp.target);
  qp_cmd->add_option("--tolerance", qp.tolerance, "Largest relative difference of x accepted")->capture_default_str();

  GenOptions gen;
  auto* gen_cmd = app.add_subcommand("gen", "Write generated scenes (the paper's envelope) as scene/1 JSON files");
  hil::apps::add_generator_options(*gen_cmd, gen.count, gen.seed);
  gen_cmd->add_option("--out", gen.out, "Output directory")->capture_default_str();

  ImportOptions imp;
  auto* import_cmd = app.add_subcommand(
      "import", "Convert a CommonRoad XML scenario (2020a) into a scene/1 JSON file (docs/commonroad.md)");
  import_cmd->add_option("file", imp.file, "CommonRoad XML file")->required()->check(CLI::ExistingFile);
  import_cmd->add_option("--out", imp.out, "Write scene/1 here (default: standard output)");
  import_cmd->add_flag("--quiet", imp.quiet, "Do not list the import's notes (choices, defaults, content left out)");
  hil::apps::add_commonroad_options(*import_cmd, imp.commonroad, true);

  hil::apps::RunCommand run;
  auto* run_cmd = app.add_subcommand("run", "Closed-loop simulation: drive the planner over scenes, report metrics");
  hil::apps::add_run_options(*run_cmd, run);

  std::string compare_a, compare_b, compare_json;
  auto* compare_cmd = app.add_subcommand(
      "compare", "Compare two report/1 files of the same scenes (e.g. qemu vs host): safety outcomes must match");
  compare_cmd->add_option("a", compare_a, "First report/1 file")->required()->check(CLI::ExistingFile);
  compare_cmd->add_option("b", compare_b, "Second report/1 file")->required()->check(CLI::ExistingFile);
  compare_cmd->add_option("--json", compare_json, "Also write the comparison as JSON here");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*ping_cmd) {
      return run_ping(ping);
    }
    if (*qp_cmd) {
      return run_qp_check(qp);
    }
    if (*gen_cmd) {
      return run_gen(gen);
    }
    if (*import_cmd) {
      return run_import(imp);
    }
    if (*run_cmd) {
      return hil::apps::run_command(run);
    }
    if (*compare_cmd) {
      return hil::sim::compare_command(compare_a, compare_b, compare_json);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "hil_sim: {}\n", e.what());
    return 2;
  }
  return 0;
}
