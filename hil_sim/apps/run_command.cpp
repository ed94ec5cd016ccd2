#include "apps/run_command.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <type_traits>

#include <fmt/core.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "link/fault_injection.hpp"
#include "sim/closed_loop.hpp"
#include "sim/cycle_trace.hpp"
#include "sim/metrics.hpp"
#include "sim/scene_files.hpp"
#include "sim/scene_generator.hpp"
#include "sim/scene_plots.hpp"
#include "sim/summary_table.hpp"
#include "sim/svg.hpp"

namespace hil::apps {

using nlohmann::json;
using sim::LoadedScene;
using sim::Prediction;
using sim::RunOptions;
using sim::SceneRunResult;
using sim::SceneSummary;
using sim::SuiteAggregator;
using sim::World;
namespace svg = sim::svg;

void add_run_options(CLI::App& cmd, RunCommand& run) {
  auto* scene_opt =
      cmd.add_option("--scene", run.scene_files, "scene/1 JSON or CommonRoad XML file(s) to run (instead of a suite)")
          ->check(CLI::ExistingFile);
  cmd.add_option("--suite", run.suite,
                 "Generated suite: default, or stress (every scene with 10 static + 5 dynamic obstacles)")
      ->check(CLI::IsMember({"default", "stress"}))
      ->excludes(scene_opt)
      ->capture_default_str();
  add_generator_options(cmd, run.count, run.seed);
  add_target_option(cmd, run.target, {"inproc", "host", "qemu"});
  add_config_option(cmd, run.target);
  add_firmware_option(cmd, run.target);
  add_prediction_option(cmd, run.prediction);
  cmd.add_option("--report", run.report, "Write report/1 JSON here");
  cmd.add_option("--plots", run.plots, "Write one SVG per scene and index.html into this directory");
  cmd.add_option("--trace", run.trace, "Write one JSON object per cycle (status, reason, ego pose, speed) to this file");
  cmd.add_option("--diagnostics", run.diagnostics,
                 "host/qemu: after the run, ask the firmware for its Diagnostics (stack peak) and write them as JSON here");
  cmd.add_option("--duration", run.duration, "Run length per scene [s] (default: the scene's, else 12)")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--link-faults", run.link_faults,
                 "host/qemu: byte faults on the link, both directions: drop=P,dup=P,flip=P,reorder=P[,seed=N] "
                 "(or bytes=P, split evenly)");
  cmd.add_option("--link-deadline-ms", run.link_deadline_ms,
                 "host/qemu: time a cycle's reply may take, retransmissions included (default 1000 host, 20000 qemu)")
      ->check(CLI::PositiveNumber);
  add_key_option(cmd, run.target);
  add_commonroad_options(cmd, run.commonroad, false);
  cmd.add_flag("--fail-on-unsafe", run.fail_on_unsafe,
               "Exit 5 when any scene has a collision or a road departure (for CI; they are results otherwise)");
}

namespace {

class Progress {
 public:
  explicit Progress(int total) : total_(total), tty_(isatty(fileno(stderr)) != 0) {}
  void update(int done, const std::string& name, int collisions, int fallbacks) {
    if (tty_) {
      constexpr int kWidth = 30;
      const int filled = total_ > 0 ? done * kWidth / total_ : kWidth;
      fmt::print(stderr, "\r[{:#<{}}{:.<{}}] {}/{} {} collisions {} fallbacks {}\x1b[K", "", filled, "", kWidth - filled,
                 done, total_, name, collisions, fallbacks);
      if (done == total_) fmt::print(stderr, "\n");
      std::fflush(stderr);
    } else {
      const int decile = total_ > 0 ? done * 10 / total_ : 10;
      if (decile > last_decile_) {
        last_decile_ = decile;
        fmt::print(stderr, "{:3}% {}/{} {} collisions {} fallbacks {}\n", decile * 10, done, total_, name, collisions,
                   fallbacks);
      }
    }
  }

 private:
  int total_;
  bool tty_;
  int last_decile_ = 0;
};

// Everything after loading the worlds, with the planner of configuration Cfg.
template <class Cfg>
int run_worlds(const RunCommand& cmd, const std::vector<World>& worlds);

}  // namespace

int run_command(const RunCommand& cmd) {
  // Scenes.
  std::vector<World> worlds;
  if (!cmd.scene_files.empty()) {
    for (const auto& path : cmd.scene_files) {
      LoadedScene loaded = sim::load_scene(path, cmd.commonroad);
      if (!loaded) {
        fmt::print(stderr, "hil_sim run: {}\n", loaded.error);
        return 2;
      }
      for (const std::string& note : loaded.notes) fmt::print(stderr, "hil_sim run: {}: {}\n", path, note);
      worlds.push_back(std::move(*loaded.world));
    }
  } else if (cmd.suite == "default") {
    worlds = sim::default_suite(cmd.count, cmd.seed);
  } else if (cmd.suite == "stress") {
    // The envelope's corner: 10 static + 5 dynamic obstacles in every scene
    // (a slot whose candidates keep breaking the generator's rules stays empty).
    sim::GeneratorConfig config;
    config.min_static = config.max_static = 10;
    config.min_dynamic = config.max_dynamic = 5;
    worlds = sim::default_suite(cmd.count, cmd.seed, config);
  } else {
    fmt::print(stderr, "hil_sim run: unknown suite '{}' (known: default, stress)\n", cmd.suite);
    return 2;
  }
  return sim::with_config(sim_config(cmd.target),
                          [&]<class Cfg>(std::type_identity<Cfg>) { return run_worlds<Cfg>(cmd, worlds); });
}

namespace {

template <class Cfg>
int run_worlds(const RunCommand& cmd, const std::vector<World>& worlds) {
  // Endpoint.
  std::string why;
  sim::LinkOptions link;
  link.deadline = std::chrono::milliseconds(cmd.link_deadline_ms);
  if (!cmd.link_faults.empty()) {
    const auto faults = parse_link_faults(cmd.link_faults, why);
    if (!faults) {
      fmt::print(stderr, "hil_sim run: --link-faults: {}\n", why);
      return 2;
    }
    link.faults = *faults;
  }
  if (cmd.target.name == "inproc" && link.faults.any()) {
    fmt::print(stderr, "hil_sim run: --link-faults needs a link (--target host or qemu)\n");
    return 2;
  }
  const std::unique_ptr<sim::BasicPlannerEndpoint<Cfg>> endpoint = make_endpoint<Cfg>(cmd.target, link, why);
  if (!endpoint) {
    fmt::print(stderr, "hil_sim run: cannot use target '{}'{}\n", cmd.target.name, why.empty() ? "" : ": " + why);
    return 2;
  }

  RunOptions opt;
  opt.prediction = prediction_mode(cmd.prediction);
  opt.duration = cmd.duration;
  opt.keep_snapshot = !cmd.plots.empty();
  if (!cmd.plots.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(cmd.plots, ec);
    if (ec) {
      fmt::print(stderr, "hil_sim run: cannot create '{}': {}\n", cmd.plots, ec.message());
      return 2;
    }
  }

  fmt::print("hil_sim run: {} scenes, target {}, config {}, prediction {}{}\n", worlds.size(), endpoint->name(),
             sim::to_string(sim::sim_config_of<Cfg>()),
             opt.prediction == Prediction::kGroundTruth ? "ground truth"
             : opt.prediction == Prediction::kLane      ? "along lanes (constant velocity off the lane map)"
                                                         : "constant velocity",
             link.faults.any() ? ", link faults " + to_string(link.faults) : std::string());
  std::fflush(stdout);
  std::ofstream trace;
  if (!cmd.trace.empty()) {
    trace.open(cmd.trace);
    if (!trace) {
      fmt::print(stderr, "hil_sim run: cannot write '{}'\n", cmd.trace);
      return 2;
    }
  }
  SuiteAggregator suite;
  std::vector<svg::IndexRow> rows;
  Progress progress(static_cast<int>(worlds.size()));
  int collisions = 0, fallbacks = 0;
  for (std::size_t i = 0; i < worlds.size(); ++i) {
    const World& w = worlds[i];
    SceneRunResult r = sim::run_scene(w, *endpoint, opt);
    const SceneSummary& s = r.summary;
    collisions += s.collided() ? 1 : 0;
    fallbacks += s.fallbacks;
    if (!r.error.empty()) fmt::print(stderr, "\nhil_sim run: {}: {}\n", w.name, r.error);
    if (trace.is_open()) sim::write_cycle_trace(trace, w.name, r);
    if (!cmd.plots.empty()) {
      const std::string file = w.name + ".svg";
      if (!svg::write_text_file((std::filesystem::path(cmd.plots) / file).string(), sim::scene_run_svg(w, r))) {
        fmt::print(stderr, "hil_sim run: cannot write {}/{}\n", cmd.plots, file);
        return 2;
      }
      rows.push_back(sim::scene_index_row(w, s, file));
    }
    suite.add(s);
    progress.update(static_cast<int>(i + 1), w.name, collisions, fallbacks);
  }

  json rep = suite.report(endpoint->name());
  rep["config"] = sim::to_string(sim::sim_config_of<Cfg>());
  const json link_stats = endpoint->link_statistics();
  if (!link_stats.is_null()) rep["link"] = link_stats;
  fmt::print("{}", sim::summary_table(rep));
  if (!cmd.diagnostics.empty()) {
    // Asked after the last cycle: the peak covers the whole run (docs/memory.md).
    const auto diag = endpoint->diagnostics();
    if (!diag) {
      fmt::print(stderr, "hil_sim run: target '{}' gave no Diagnostics reply\n", endpoint->name());
      return 2;
    }
    const json d = {{"target", endpoint->name()},
                    {"scenes", worlds.size()},
                    {"stack_bytes", diag->stack_bytes},
                    {"stack_peak_bytes", diag->stack_peak_bytes}};
    std::ofstream out(cmd.diagnostics);
    out << d.dump(1) << "\n";
    if (!out) {
      fmt::print(stderr, "hil_sim run: cannot write '{}'\n", cmd.diagnostics);
      return 2;
    }
    fmt::print("firmware stack: peak {} of {} bytes (painted; 0: not measured), diagnostics: {}\n",
               diag->stack_peak_bytes, diag->stack_bytes, cmd.diagnostics);
  }
  if (!cmd.report.empty()) {
    const std::string err = sim::write_report(rep, cmd.report);
    if (!err.empty()) {
      fmt::print(stderr, "hil_sim run: {}\n", err);
      return 2;
    }
    fmt::print("report: {}\n", cmd.report);
  }
  if (!cmd.plots.empty()) {
    std::vector<std::string> lines;
    std::istringstream table(sim::summary_table(rep));
    for (std::string line; std::getline(table, line);) {
      if (!line.empty() && line.front() != '-') lines.push_back(line);
    }
    const std::string index = (std::filesystem::path(cmd.plots) / "index.html").string();
    if (!svg::write_text_file(index, svg::index_html(fmt::format("hil_sim run — {} scenes, target {}",
                                                                 worlds.size(), endpoint->name()),
                                                     lines, rows))) {
      fmt::print(stderr, "hil_sim run: cannot write {}\n", index);
      return 2;
    }
    fmt::print("plots: {}\n", index);
  }
  if (rep.value("crashes", 0) > 0) return 3;
  // A link that failed is a failed run, not a result (issue 13, defect 8: a
  // run where every cycle was a link error exited 0).
  const int link_errors = rep.value("link_errors", 0);
  const int no_plan = rep.value("scenes_without_any_plan", 0);
  if ((link_errors > 0 && !link.faults.any()) || no_plan > 0) {
    fmt::print(stderr, "hil_sim run: the link failed: {} cycles without a plan, {} scenes without any{}\n", link_errors,
               no_plan, link.faults.any() ? "" : " (no faults were injected)");
    return 4;
  }
  const int unsafe = rep.value("collisions", 0) + rep.value("road_departures", 0);
  if (cmd.fail_on_unsafe && unsafe > 0) {
    fmt::print(stderr, "hil_sim run: {} scene(s) with a collision and {} with a road departure\n",
               rep.value("collisions", 0), rep.value("road_departures", 0));
    return 5;
  }
  return 0;
}

}  // namespace
}  // namespace hil::apps
