// planner_cli: run the planner on one scene/1 file.
//   planner_cli decide SCENE.json [--svg OUT.svg]   zones, kept decisions, costs, the chosen corridor
//   planner_cli plan SCENE.json [--svg OUT.svg] [--dump-qp DIR]   plan/1 JSON
//   (both with --config default|road: the planner configuration, sim/sim_config.hpp)
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <filesystem>
#include <iostream>
#include <memory>
#include <type_traits>

#include "apps/common_options.hpp"
#include "formats/plan_json.hpp"
#include "formats/qp_text.hpp"
#include "itp/decision/decision_tree.hpp"
#include "itp/planner/planner.hpp"
#include "sim/plan_plots.hpp"
#include "sim/scene_convert.hpp"
#include "sim/scene_files.hpp"
#include "sim/scene_generator.hpp"
#include "itp/link/planner_messages.hpp"
#include "sim/svg.hpp"

namespace {

using nlohmann::json;

struct Options {
  std::string scene_file;
  std::string svg;
  std::string dump_dir;
  double now = 0;
  std::string prediction = "truth";
  int indent = 2;
  std::string config = "default";  // default | road
};

std::uint64_t host_ticks() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count());
}

// Writes every QP the planner solves as qp-text/1, numbered in solve order.
struct QpDumper {
  std::string dir;
  int count = 0;
  std::string error;

  template <class D>
  void write(const char* kind, const itp::qp::QpProblem<D>& p) {
    const std::string path = fmt::format("{}/{:03d}_{}.qp", dir, count++, kind);
    std::string err;
    if (!hil::formats::write_qp_text_file(path, hil::formats::from_problem(p), err) && error.empty()) {
      error = err;
    }
  }
};

template <class Cfg>
json decision_json(const itp::planner::BasicPlanner<Cfg>& planner) {
  const auto& stage = planner.decision_stage();
  const auto& space = stage.space();
  json zones = json::array();
  for (std::size_t i = 0; i < space.zones.size(); ++i) {
    const auto& z = space.zones[i];
    zones.push_back({{"index", i}, {"slice", z.slice}, {"s", {space.slice_of(z).s_begin, space.slice_of(z).s_end}}, {"l", {z.l_min, z.l_max}},
                     {"area_cost", z.area_cost}, {"lane_cost", z.lane_cost}});
  }
  json kept = json::array();
  // The stage keeps each decision's score; its samples come from its coarse QP
  // solved again, cold (evaluate_again: the same optimum within the QP's tolerance).
  using Stage = std::remove_cvref_t<decltype(stage)>;
  auto arena = std::make_unique<typename Stage::QpArena>();  // its own: the planner's stays untouched
  auto evaluator = std::make_unique<typename Stage::CoarseEvaluator>(*arena);
  auto again = std::make_unique<typename Stage::CoarseResult>();
  for (std::size_t i = 0; i < stage.decisions().kept.size(); ++i) {
    const auto& d = stage.decisions().kept[i];
    const auto& c = stage.coarse(i);
    stage.evaluate_again(i, *evaluator, *again);
    const auto& samples_of = *again;
    json sides = json::array();
    for (const auto& b : planner.boxes()) {
      const auto side = itp::decision::side_of(space, d, b);
      sides.push_back({{"obstacle", b.obstacle_id},
                       {"side", side == itp::decision::Side::kLeft    ? "left"
                                : side == itp::decision::Side::kRight ? "right"
                                                                       : "not_reached"}});
    }
    json samples = json::array();
    for (int k = 0; itp::qp::is_usable(c.status) && k < samples_of.samples; ++k) {
      const auto u = static_cast<std::size_t>(k);
      samples.push_back({{"s", samples_of.s[u]}, {"l", samples_of.l[u]}, {"t", samples_of.t[u]},
                         {"l_lb", samples_of.l_lb[u]}, {"l_ub", samples_of.l_ub[u]}, {"t_lb", samples_of.t_lb[u]}});
    }
    kept.push_back({{"rank", i},
                    {"zones", std::vector<int>(d.zones.begin(), d.zones.end())},
                    {"sides", sides},
                    {"reaches_end", d.reaches_end},
                    {"reach", d.reach},
                    {"geometric_cost", d.geometric_cost},
                    {"area_cost", d.area_cost},
                    {"lane_cost", d.lane_cost},
                    {"link_cost", d.link_cost},
                    {"move_cost", d.move_cost},
                    {"coarse_qp", itp::qp::to_string(c.status)},
                    {"path_cost", c.path_cost},
                    {"dynamic_cost", c.dynamic_cost},
                    {"decision_cost", c.decision_cost},
                    {"kappa", {{"mean_abs", c.kappa_mean}, {"var", c.kappa_var}}},
                    {"a_lat", {{"mean_abs", c.a_lat_mean}, {"var", c.a_lat_var}}},
                    {"a_lon", {{"mean_abs", c.a_lon_mean}, {"var", c.a_lon_var}}},
                    {"samples", samples}});
  }
  json boxes = json::array();
  for (const auto& b : planner.boxes()) {
    boxes.push_back({{"obstacle", b.obstacle_id}, {"dynamic", b.dynamic}, {"s", {b.s_min, b.s_max}}, {"l", {b.l_min, b.l_max}}});
  }
  return {{"zones", zones},
          {"obstacles_sl", boxes},
          {"decisions", kept},
          {"tree", {{"nodes_expanded", stage.decisions().nodes_expanded},
                    {"complete_paths", stage.decisions().complete_paths},
                    {"truncated", stage.decisions().truncated}}},
          {"chosen", planner.chosen_decision()}};
}

template <class Cfg>
int run(const Options& opt, bool decide_only) {
  const auto loaded = hil::sim::load_scene(opt.scene_file);  // scene/1, or CommonRoad XML imported
  if (!loaded.world) {
    fmt::print(stderr, "planner_cli: {}\n", loaded.error);
    return 2;
  }
  const hil::sim::World& world = *loaded.world;
  auto scene = std::make_unique<itp::scene::BasicScene<Cfg>>();
  const auto mode = hil::apps::prediction_mode(opt.prediction);
  const auto conv = hil::sim::make_planner_scene(world, hil::sim::ego_at_start(world), opt.now, mode, *scene);
  if (!conv.ok) {
    fmt::print(stderr, "planner_cli: {}: {}\n", opt.scene_file, conv.error);
    return 2;
  }
  auto planner = std::make_unique<itp::planner::BasicPlanner<Cfg>>();
  auto plan = std::make_unique<itp::planner::BasicPlan<Cfg>>();
  planner->set_tick_source(itp::TickSource{&host_ticks, 1000000000u});
  QpDumper dumper{opt.dump_dir, 0, {}};
  typename itp::planner::BasicPlanner<Cfg>::QpObserver observer;
  if (!opt.dump_dir.empty()) {
    std::filesystem::create_directories(opt.dump_dir);
    observer.context = &dumper;
    observer.coarse = [](void* c, const auto& p) { static_cast<QpDumper*>(c)->write("coarse", p); };
    observer.path = [](void* c, const auto& p) { static_cast<QpDumper*>(c)->write("path", p); };
    observer.speed = [](void* c, const auto& p) { static_cast<QpDumper*>(c)->write("speed", p); };
    planner->set_qp_observer(&observer);
  }
  planner->plan(itp::planner::BasicPlanRequest<Cfg>{scene.get(), opt.now}, *plan);

  json out = decide_only ? decision_json(*planner) : hil::formats::plan_to_json(*plan);
  if (!decide_only) {
    // Extra (optional) keys: the ST graph and the speed QP's bounds of the last iteration.
    json st = json::array();
    for (const auto& d : planner->st_graph().decisions()) {
      st.push_back({{"obstacle", d.id}, {"decision", itp::speed::to_string(d.decision)}, {"k1", d.k1}, {"k2", d.k2}});
    }
    const auto& b = planner->speed_bounds();
    json bounds = json::array();
    for (int k = 0; k < Cfg::kStSamples; k += 5) {
      const auto u = static_cast<std::size_t>(k);
      bounds.push_back({{"t", 0.1 * k}, {"s_lo", b.s_lo[u]}, {"s_hi", std::isfinite(b.s_hi[u]) ? json(b.s_hi[u]) : json(nullptr)},
                        {"v_lo", b.v_lo[u]}, {"v_hi", b.v_hi[u]}, {"s_ref", b.s_ref[u]}});
    }
    out["st_graph"] = {{"decisions", st}, {"bounds", bounds}};
    json path = json::array();
    const auto& pr = planner->path_result();
    if (itp::qp::is_usable(pr.status)) {
      for (double s = planner->path_start(); s <= planner->path_start() + planner->path_length() + 1e-9; s += 5.0) {
        path.push_back({{"s", s}, {"l", pr.eval(s, 0)}, {"dl", pr.eval(s, 1)}, {"ddl", pr.eval(s, 2)}});
      }
    }
    out["path"] = path;
  }
  if (decide_only) {
    out["status"] = itp::to_string(plan->status);
  }
  std::cout << out.dump(opt.indent) << "\n";
  if (!opt.svg.empty()) {
    const std::string name = world.name.empty() ? opt.scene_file : world.name;
    std::vector<std::string> parts{hil::sim::plot_sl(*planner, *scene, fmt::format("{}: SL view, zones and chosen corridor", name))};
    if (!decide_only) {
      parts.push_back(hil::sim::plot_xy(*planner, *scene, *plan, opt.now, fmt::format("{}: XY view, status {}", name, itp::to_string(plan->status))));
      parts.push_back(hil::sim::plot_st(*planner, *plan, fmt::format("{}: ST view", name)));
    }
    if (!hil::sim::svg::write_text_file(opt.svg, hil::sim::stack_svgs(parts))) {
      fmt::print(stderr, "planner_cli: cannot write {}\n", opt.svg);
      return 2;
    }
  }
  if (!dumper.error.empty()) {
    fmt::print(stderr, "planner_cli: QP dump: {}\n", dumper.error);
    return 2;
  }
  if (!opt.dump_dir.empty()) {
    fmt::print(stderr, "planner_cli: wrote {} QPs to {}\n", dumper.count, opt.dump_dir);
  }
  return 0;
}

struct BatchOptions {
  int count = 100;
  std::uint64_t seed = 1;
  bool verbose = false;
  hil::apps::TargetOptions target;  // no --key: a fresh random key per run
  bool compare = false;
  double tolerance = 0.01;  // [m] largest position difference accepted by --compare
  int max_mismatches = 0;   // scenes allowed beyond the tolerance (statuses must always agree)
};

// The in-process plan of the scene exactly as a firmware receives it (float
// on the wire), to compare a target's answer with.
void plan_as_received(const itp::scene::Scene& scene, int stride, itp::planner::Planner& planner,
                      itp::planner::Plan& out) {
  static std::array<std::uint8_t, itp::link::kMaxSceneBytes<itp::DefaultConfig>> body{};
  static itp::scene::Scene wire;
  const std::size_t n = itp::link::encode_scene({1, 0.0, true}, scene, stride, body);
  itp::link::SceneHeader h;
  if (n == 0 || !itp::link::decode_scene(std::span<const std::uint8_t>(body.data(), n), h, wire)) {
    out = itp::planner::Plan{};
    return;
  }
  planner.reset();
  planner.plan(itp::planner::PlanRequest{&wire, 0.0}, out);
}

// Open-loop batch: plans the first cycle of generated scenes and tallies
// statuses, fallback reasons, iterations and time.
int run_batch(const BatchOptions& opt) {
  auto planner = std::make_unique<itp::planner::Planner>();
  auto reference = std::make_unique<itp::planner::Planner>();
  auto plan = std::make_unique<itp::planner::Plan>();
  auto expected = std::make_unique<itp::planner::Plan>();
  auto scene = std::make_unique<itp::scene::Scene>();
  planner->set_tick_source(itp::TickSource{&host_ticks, 1000000000u});
  std::unique_ptr<hil::sim::PlannerEndpoint> remote;
  if (opt.target.name != "inproc") {
    std::string error;
    remote = hil::apps::make_endpoint(opt.target, {}, error);
    if (!remote) {
      fmt::print(stderr, "planner_cli: {}\n", error);
      return 2;
    }
  }
  std::map<std::string, int> outcomes;
  std::vector<double> times;
  std::vector<double> instructions;
  double iterations = 0;
  double worst = 0;
  int mismatches = 0;
  int status_mismatches = 0;
  std::vector<double> diffs;
  for (int i = 0; i < opt.count; ++i) {
    const hil::sim::World w = hil::sim::generate_scene(opt.seed, i);
    const auto conv = hil::sim::make_planner_scene(w, hil::sim::ego_at_start(w), 0.0, hil::sim::Prediction::kGroundTruth, *scene);
    if (!conv.ok) {
      ++outcomes["convert_error"];
      continue;
    }
    if (remote) {
      remote->reset();
      const auto r = remote->plan(*scene, 0.0, *plan);
      if (!r.ok) {
        ++outcomes["link_error"];
        continue;
      }
      if (r.instructions >= 0) instructions.push_back(r.instructions);
      if (opt.compare) {
        plan_as_received(*scene, opt.target.name == "qemu" ? 5 : 1, *reference, *expected);
        double diff = expected->status == plan->status && expected->trajectory.size() == plan->trajectory.size() ? 0.0 : 1e9;
        for (std::size_t k = 0; diff < 1e9 && k < plan->trajectory.size(); ++k) {
          diff = std::max(diff, std::hypot(plan->trajectory[k].x - expected->trajectory[k].x,
                                           plan->trajectory[k].y - expected->trajectory[k].y));
        }
        worst = std::max(worst, diff);
        diffs.push_back(diff);
        status_mismatches += expected->status != plan->status ? 1 : 0;
        if (diff > opt.tolerance) {
          ++mismatches;
          fmt::print("{}: {} differs from inproc by {:.3g} m (status {} vs {})\n", w.name, opt.target.name, diff,
                     itp::to_string(plan->status), itp::to_string(expected->status));
        }
      }
    } else {
      planner->reset();
      planner->plan(itp::planner::PlanRequest{scene.get(), 0.0}, *plan);
    }
    std::string key = itp::to_string(plan->status);
    if (plan->status == itp::PlanStatus::kFallback) key += std::string(":") + itp::planner::to_string(plan->fallback);
    if (plan->status == itp::PlanStatus::kInvalidInput) key += std::string(":") + itp::scene::to_string(plan->invalid);
    ++outcomes[key];
    if (plan->timing.tick_hz > 0) {
      times.push_back(static_cast<double>(plan->timing.total) * 1e6 / static_cast<double>(plan->timing.tick_hz));
    }
    iterations += plan->iterations;
    if (opt.verbose && plan->status != itp::PlanStatus::kOk) {
      fmt::print("{:<12} {:<28} iterations {}  {}\n", w.name, key, plan->iterations, fmt::join(w.tags, ","));
    }
  }
  std::sort(times.begin(), times.end());
  for (const auto& [k, n] : outcomes) fmt::print("{:<36} {:4}\n", k, n);
  if (!times.empty() && opt.target.name != "qemu") {
    fmt::print("time per cycle [us]: median {:.0f}, max {:.0f}\n", times[times.size() / 2], times.back());
  }
  std::sort(instructions.begin(), instructions.end());
  if (!instructions.empty()) {
    fmt::print("instructions per cycle (Cortex-M7, QEMU icount): median {:.3g}, max {:.3g}\n",
               instructions[instructions.size() / 2], instructions.back());
  }
  fmt::print("iterations mean {:.2f} over {} plans\n", iterations / std::max<double>(1, static_cast<double>(opt.count)), opt.count);
  if (opt.compare) {
    std::sort(diffs.begin(), diffs.end());
    fmt::print("position difference {} vs inproc: median {:.3g} m, largest {:.3g} m; {} beyond {} m (allowed {}), "
               "{} status mismatches\n", opt.target.name, diffs.empty() ? 0.0 : diffs[diffs.size() / 2], worst, mismatches,
               opt.tolerance, opt.max_mismatches, status_mismatches);
    return mismatches <= opt.max_mismatches && status_mismatches == 0 && outcomes.count("link_error") == 0 ? 0 : 1;
  }
  return 0;
}

void add_common(CLI::App* cmd, Options& opt) {
  cmd->add_option("scene", opt.scene_file, "scene/1 JSON or CommonRoad XML file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--svg", opt.svg, "Write a picture of the cycle (SL; plan adds XY and ST views)");
  cmd->add_option("--now", opt.now, "Plan at this time of the scene [s] (obstacles move on)")->capture_default_str();
  hil::apps::add_prediction_option(*cmd, opt.prediction);
  cmd->add_option("--indent", opt.indent, "JSON indentation (-1: one line)")->capture_default_str();
  cmd->add_option("--config", opt.config, "Planner configuration: default (10 + 5 objects) or road (32 + 32)")
      ->check(CLI::IsMember({"default", "road"}))
      ->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"planner_cli: run the iterative triple-optimization planner on one scene/1 file"};
  app.require_subcommand(1);
  Options decide_opt;
  auto* decide = app.add_subcommand("decide", "Convex zones, the K best decisions with their costs, the chosen corridor (JSON)");
  add_common(decide, decide_opt);
  Options plan_opt;
  auto* plan = app.add_subcommand("plan", "The full planning cycle; prints plan/1 JSON");
  add_common(plan, plan_opt);
  plan->add_option("--dump-qp", plan_opt.dump_dir, "Write every QP of the cycle as qp-text/1 into this directory");
  BatchOptions batch_opt;
  auto* batch = app.add_subcommand("batch", "Plan the first cycle of generated scenes; tally statuses and time");
  hil::apps::add_generator_options(*batch, batch_opt.count, batch_opt.seed);
  batch->add_flag("--verbose", batch_opt.verbose, "List every scene that does not plan ok");
  hil::apps::add_target_option(*batch, batch_opt.target, {"inproc", "host", "qemu"});
  hil::apps::add_firmware_option(*batch, batch_opt.target);
  batch->add_flag("--compare", batch_opt.compare, "Compare every target plan with the in-process planner's");
  batch->add_option("--tolerance", batch_opt.tolerance, "Position tolerance of --compare [m]")->capture_default_str();
  batch->add_option("--max-mismatches", batch_opt.max_mismatches,
                    "Scenes allowed beyond the tolerance (a libm rounding can tip a discrete choice)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    if (*batch) return run_batch(batch_opt);
    const Options& opt = *decide ? decide_opt : plan_opt;
    const auto config = hil::sim::parse_sim_config(opt.config).value_or(hil::sim::SimConfig::kDefault);
    return hil::sim::with_config(config, [&]<class Cfg>(std::type_identity<Cfg>) { return run<Cfg>(opt, static_cast<bool>(*decide)); });
  } catch (const std::exception& e) {
    fmt::print(stderr, "planner_cli: {}\n", e.what());
    return 2;
  }
}
