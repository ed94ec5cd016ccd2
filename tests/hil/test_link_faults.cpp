// A broken bus in the closed loop (issue 13, deliver 5): the fault injector
// itself, the host-port firmware at 1 % byte faults both ways (defect 12:
// before, no scene frame got through), and hil_sim run's exit status when
// the link fails (defect 8: it exited 0).
#include <doctest/doctest.h>

#include <cmath>
#include <deque>
#include <memory>
#include <vector>

#include "apps/run_command.hpp"
#include "link/fault_injection.hpp"
#include "sim/closed_loop.hpp"
#include "sim/link_endpoint.hpp"
#include "sim/scene_files.hpp"
#include "sim/scene_generator.hpp"

using namespace hil;

namespace {

// Bytes written come back on read: a loopback to look at the faults.
class Loopback final : public ByteTransport {
 public:
  bool write_all(std::span<const std::uint8_t> bytes) override {
    data.insert(data.end(), bytes.begin(), bytes.end());
    return true;
  }
  std::size_t read_some(std::span<std::uint8_t> buffer, std::chrono::milliseconds) override {
    const std::size_t n = std::min(buffer.size(), data.size());
    std::copy_n(data.begin(), n, buffer.begin());
    data.erase(data.begin(), data.begin() + static_cast<long>(n));
    return n;
  }
  std::deque<std::uint8_t> data;
};

}  // namespace

TEST_CASE("link faults: the spec parses, and bad specs are refused") {
  std::string error;
  const auto f = parse_link_faults("drop=0.01,dup=0.002,flip=0.003,reorder=0.004,seed=7", error);
  REQUIRE(f);
  CHECK(f->drop == 0.01);
  CHECK(f->dup == 0.002);
  CHECK(f->flip == 0.003);
  CHECK(f->reorder == 0.004);
  CHECK(f->seed == 7);
  const auto even = parse_link_faults("bytes=0.01", error);
  REQUIRE(even);
  CHECK(even->total() == doctest::Approx(0.01));
  for (const char* bad : {"drop", "drop=x", "drop=1.5", "nope=0.1", "drop=0.6,dup=0.6", "drop=0.1junk"}) {
    CHECK_FALSE_MESSAGE(parse_link_faults(bad, error), bad);
  }
}

TEST_CASE("link faults: each kind happens at its rate, the same seed gives the same faults") {
  LinkFaults f;
  f.drop = 0.004;
  f.dup = 0.003;
  f.flip = 0.002;
  f.reorder = 0.001;
  std::vector<std::uint8_t> input(1'000'000);
  for (std::size_t i = 0; i < input.size(); ++i) input[i] = static_cast<std::uint8_t>(i * 7 + 1);
  std::vector<std::uint8_t> first;
  for (int run = 0; run < 2; ++run) {
    Loopback loop;
    FaultyTransport t(loop, f);
    REQUIRE(t.write_all(input));
    const FaultCounters& c = t.to_firmware();
    CHECK(c.bytes == input.size());
    // Binomial: within 5 standard deviations of n p.
    const auto near = [&](std::uint64_t got, double p) {
      const double n = static_cast<double>(input.size());
      return std::fabs(static_cast<double>(got) - n * p) < 5.0 * std::sqrt(n * p);
    };
    CHECK(near(c.dropped, f.drop));
    CHECK(near(c.duplicated, f.dup));
    CHECK(near(c.flipped, f.flip));
    CHECK(near(c.reordered, f.reorder));
    // Every byte leaves once, duplicates twice, drops never (a byte held for
    // reordering at the very end is still held).
    const std::size_t expected = input.size() - c.dropped + c.duplicated;
    CHECK((loop.data.size() == expected || loop.data.size() + 1 == expected));
    const std::vector<std::uint8_t> out(loop.data.begin(), loop.data.end());
    if (run == 0) first = out;
    else CHECK(out == first);
  }
}

TEST_CASE("closed loop over the host firmware at 1 % byte faults both ways: plans get through, none is corrupt") {
  std::string error;
  sim::LinkOptions link;
  link.faults = *parse_link_faults("bytes=0.01,seed=3", error);
  link.deadline = std::chrono::milliseconds(1000);
  auto ep = sim::make_link_endpoint("host", "", &error, link);
  REQUIRE_MESSAGE(ep != nullptr, error);
  sim::RunOptions opt;
  opt.duration = 6.0;
  int cycles = 0, lost = 0, corrupt = 0;
  for (int i = 0; i < 3; ++i) {
    const sim::World w = sim::generate_scene(5, i);
    const sim::SceneRunResult r = sim::run_scene(w, *ep, opt);
    CHECK(r.error.empty());
    CHECK_FALSE(r.summary.collided());
    cycles += r.summary.cycles + r.summary.link_errors;
    lost += r.summary.link_errors;
    corrupt += r.summary.corrupt_scenes_accepted;
  }
  const nlohmann::json stats = ep->link_statistics();
  MESSAGE("1 % byte faults: ", lost, " of ", cycles, " cycles without a fresh plan; link ", stats.dump());
  CHECK(cycles == 180);
  CHECK(lost <= cycles / 20);  // at least 95 % of the cycles get their plan
  CHECK(corrupt == 0);
  CHECK(stats["faults_to_firmware"].get<int>() > 100);
  CHECK(stats["faults_to_host"].get<int>() > 100);
}

TEST_CASE("hil_sim run fails (exit 4) when the link fails, instead of reporting success") {
  // /bin/cat answers every frame with itself: never a plan.
  apps::RunCommand cmd;
  cmd.suite = "default";
  cmd.count = 1;
  cmd.target.name = "host";
  cmd.target.firmware = "/bin/cat";
  cmd.duration = 1.0;
  cmd.link_deadline_ms = 200;
  CHECK(apps::run_command(cmd) == 4);
  cmd.link_faults = "bytes=0.01";  // with injected faults too, a scene without any plan fails the run
  CHECK(apps::run_command(cmd) == 4);
}
