// qp_solve: solve qp-text/1 files with the firmware's dual active-set QP
// solver and report status, objective, iterations, KKT residual and timing.
//
//   qp_solve [--repeat N] [--warm] [--json] [--check] FILE...
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "formats/qp_text.hpp"
#include "itp/qp/qp.hpp"

namespace {

// Host capacities: generous enough for every planner QP and its variants.
using HostQp = itp::qp::QpDims<double, 160, 800, 32, 16>;

struct Solver {
  itp::qp::QpProblem<HostQp> problem;
  itp::qp::QpWorkspace<HostQp> ws;
  itp::qp::QpResult<HostQp> result;
  itp::qp::WorkingSet<HostQp> previous;
  bool have_previous = false;
  int previous_n = -1, previous_m = -1;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Solve qp-text/1 QPs (min 1/2 x'Hx + g'x s.t. lbA <= Ax <= ubA, lb <= x <= ub) with the\n"
      "firmware's sparse dual active-set solver (docs/qp.md). Per file: status, objective,\n"
      "iterations, max KKT residual, median solve time over --repeat runs and, when the file\n"
      "has x_ref / obj_ref, the deviation from them. Capacities: n <= 160, m <= 800, <= 32\n"
      "nonzeros per row of A, H half-bandwidth <= 16."};
  std::vector<std::string> files;
  int repeat = 1;
  bool warm = false, json = false, check = false;
  double tolerance = 1e-6;
  app.add_option("files", files, "qp-text/1 files, solved in the order given")->required();
  app.add_option("--repeat", repeat, "solve each file N times; report the median time")
      ->check(CLI::Range(1, 100000));
  app.add_flag("--warm", warm,
               "warm-start each file from the previous file's final working set "
               "(files of the same n and m)");
  app.add_flag("--json", json, "print one JSON document instead of text");
  app.add_flag("--check", check,
               "exit 1 unless every file is optimal with KKT residual and reference "
               "deviations <= --tolerance (relative to 1 + |data|)");
  app.add_option("--tolerance", tolerance, "tolerance for --check (default 1e-6)");
  CLI11_PARSE(app, argc, argv);

  auto s = std::make_unique<Solver>();
  const itp::qp::QpSettings<double> settings;
  nlohmann::json out = nlohmann::json::array();
  bool all_ok = true;
  for (const auto& path : files) {
    hil::formats::QpText qp;
    std::string error;
    nlohmann::json rec;
    rec["file"] = path;
    if (!hil::formats::read_qp_text_file(path, qp, error) ||
        !hil::formats::to_problem(qp, s->problem, error)) {
      all_ok = false;
      rec["status"] = "read_error";
      rec["error"] = error;
      if (!json) fmt::print("{}: error: {}\n", path, error);
      out.push_back(rec);
      s->have_previous = false;
      continue;
    }
    const bool use_warm = warm && s->have_previous && s->previous_n == qp.n && s->previous_m == qp.m;
    std::vector<double> times_us;
    itp::qp::QpStatus status = itp::qp::QpStatus::kInvalidInput;
    for (int k = 0; k < repeat; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      status = use_warm ? itp::qp::solve_warm(s->problem, s->ws, settings, s->previous, s->result)
                        : itp::qp::solve_cold(s->problem, s->ws, settings, s->result);
      const auto t1 = std::chrono::steady_clock::now();
      times_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
    std::sort(times_us.begin(), times_us.end());
    const double median = times_us[times_us.size() / 2];
    const auto kkt = itp::qp::kkt_residual(s->problem, s->result);
    double data_scale = 1.0;
    for (double v : qp.g) data_scale = std::max(data_scale, std::abs(v));
    rec["status"] = itp::qp::to_string(status);
    rec["warm"] = use_warm;
    rec["n"] = qp.n;
    rec["m"] = qp.m;
    rec["iterations"] = s->result.iterations;
    rec["median_us"] = median;
    rec["min_us"] = times_us.front();
    rec["max_us"] = times_us.back();
    bool ok = status == itp::qp::QpStatus::kOptimal;
    if (ok) {
      rec["objective"] = s->result.objective;
      rec["kkt_residual"] = kkt.max();
      ok = ok && kkt.max() <= tolerance * data_scale;
      if (qp.x_ref) {
        double dev = 0.0, ref_scale = 1.0;
        for (int j = 0; j < qp.n; ++j) {
          dev = std::max(dev, std::abs(s->result.x[j] - (*qp.x_ref)[static_cast<std::size_t>(j)]));
          ref_scale = std::max(ref_scale, std::abs((*qp.x_ref)[static_cast<std::size_t>(j)]));
        }
        rec["x_ref_deviation"] = dev;
        ok = ok && dev <= tolerance * ref_scale;
      }
      if (qp.obj_ref) {
        const double dev = std::abs(s->result.objective - *qp.obj_ref);
        rec["obj_ref_deviation"] = dev;
        ok = ok && dev <= tolerance * (1.0 + std::abs(*qp.obj_ref));
      }
      s->previous = s->result.working_set;
      s->have_previous = true;
      s->previous_n = qp.n;
      s->previous_m = qp.m;
    } else {
      s->have_previous = false;
    }
    all_ok = all_ok && ok;
    if (!json) {
      fmt::print("{}: status {}{} n {} m {} iterations {} ", path, itp::qp::to_string(status),
                 use_warm ? " (warm)" : "", qp.n, qp.m, s->result.iterations);
      if (status == itp::qp::QpStatus::kOptimal) {
        fmt::print("objective {:.12g} kkt {:.3g} ", s->result.objective, kkt.max());
        if (rec.contains("x_ref_deviation")) {
          fmt::print("x_ref_dev {:.3g} ", rec["x_ref_deviation"].get<double>());
        }
        if (rec.contains("obj_ref_deviation")) {
          fmt::print("obj_ref_dev {:.3g} ", rec["obj_ref_deviation"].get<double>());
        }
      }
      fmt::print("median {:.2f} us (min {:.2f}, max {:.2f}, {} runs)\n", median, times_us.front(),
                 times_us.back(), repeat);
    }
    out.push_back(rec);
  }
  if (json) fmt::print("{}\n", nlohmann::json{{"format", "qp-solve/1"}, {"results", out}}.dump(2));
  return (check && !all_ok) ? 1 : 0;
}
