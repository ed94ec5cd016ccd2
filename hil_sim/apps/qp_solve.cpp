// qp_solve: solve QP files (qp-text/1 or QPS) with the firmware's dual
// active-set QP solver and report status, objective, iterations, KKT residual,
// the infeasibility certificate and timing (docs/qp.md, "qp_solve").
//
//   qp_solve [--repeat N] [--warm | --hot] [--json] [--check] [settings...] FILE...
//
// Compile-time variants of the one solver, tried in this order, each file
// going to the first that fits: the planner's own coarse, speed and path
// shapes (so that a dumped planner QP is solved by exactly the instance the
// planner runs, with its loop lengths and memory footprint), the banded host
// shape (n <= 160, m <= 800, <= 32 nonzeros per row, H half-bandwidth <= 16)
// and the general shape (dense H, any row, n <= 160, m <= 1200). Like the
// planner's StageQp, cold solves of chain-form files go to the chain solver
// first (docs/qp.md, "Chain solver").
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "formats/qp_text.hpp"
#include "formats/qps.hpp"
#include "itp/qp/qp.hpp"

namespace {

using CoarseQp = itp::qp::CoarseQpDims<double, itp::DefaultConfig>;
using SpeedQp = itp::qp::SpeedQpDims<double, itp::DefaultConfig>;
using PathQp = itp::qp::PathQpDims<double, itp::DefaultConfig>;
using BandedQp = itp::qp::QpDims<double, 160, 800, 32, 16>;
using GeneralQp = itp::qp::GeneralQpDims<double>;
constexpr const char* kVariantNames[] = {"coarse", "speed", "path", "banded", "general"};

// One file as read: the dense data, its constant and where it came from.
struct Input {
  std::string path;
  std::string name;              // file name without directory and extension
  std::string qps_name;          // QPS NAME section
  std::string format;            // "qp-text/1" or "qps"
  hil::formats::QpText qp;
  double constant = 0.0;         // QPS objective constant c0
  std::optional<double> obj_ref; // objective of the problem including c0
};

// Half-bandwidth of H and the largest row nonzero count.
void shape(const hil::formats::QpText& qp, int& bandwidth, int& row_nnz) {
  const auto n = static_cast<std::size_t>(qp.n);
  bandwidth = 0;
  row_nnz = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (qp.H[i * n + j] != 0.0) bandwidth = std::max(bandwidth, static_cast<int>(i - j));
    }
  }
  for (std::size_t r = 0; r < static_cast<std::size_t>(qp.m); ++r) {
    int k = 0;
    for (std::size_t j = 0; j < n; ++j) k += qp.A[r * n + j] != 0.0 ? 1 : 0;
    row_nnz = std::max(row_nnz, k);
  }
}

template <class D>
bool fits(const hil::formats::QpText& qp, int bandwidth, int row_nnz) {
  return qp.n <= D::kMaxVariables && qp.m <= D::kMaxRows && bandwidth <= D::kBandwidth &&
         row_nnz <= D::kMaxRowNonzeros;
}

struct Options {
  int repeat = 1;
  bool warm = false, hot = false, json = false, check = false;
  bool general_only = false;  // --no-chain: skip the chain solver (A/B runs)
  double tolerance = 1e-6;
  itp::qp::QpSettings<double> settings;
  std::string references;
  std::string write_dir;
  int require_solved = -1;
};

// State of one variant across the files of a sequence (warm/hot modes).
template <class D>
struct Solver {
  itp::qp::QpProblem<D> problem;
  itp::qp::QpWorkspace<D> ws;
  itp::qp::QpResult<D> result;
  itp::qp::WorkingSet<D> previous;
  bool have_previous = false;  // a working set of the previous file (same n, m)
  const hil::formats::QpText* previous_qp = nullptr;
};

struct Outcome {
  itp::qp::QpStatus status = itp::qp::QpStatus::kInvalidInput;
  std::string start = "cold";
  double time_us = 0.0;
};

bool same_matrices(const hil::formats::QpText* a, const hil::formats::QpText& b) {
  return a != nullptr && a->n == b.n && a->m == b.m && a->H == b.H && a->A == b.A;
}

// Solves `in` once with solver state `s` (cold, or warm/hot from the previous file).
template <class D>
Outcome solve_once(Solver<D>& s, const Input& in, const Options& opt) {
  Outcome out;
  std::string error;
  if (!hil::formats::to_problem(in.qp, s.problem, error)) {
    out.status = itp::qp::QpStatus::kInvalidInput;
    return out;
  }
  const bool same_shape = s.previous_qp != nullptr && s.previous_qp->n == in.qp.n && s.previous_qp->m == in.qp.m;
  const bool same = same_matrices(s.previous_qp, in.qp);
  const bool hot = opt.hot && same && s.ws.factored;
  // The chain solver's hot start: the same H and A as its last settled solve.
  const bool chain_hot = opt.hot && same && !opt.general_only && s.ws.chain_stride > 0 && s.have_previous;
  const bool warm = (opt.warm || opt.hot) && !hot && same_shape && s.have_previous;
  const auto t0 = std::chrono::steady_clock::now();
  if (hot) {
    out.status = itp::qp::solve_hot(s.problem, s.ws, opt.settings, s.result);
  } else if (opt.general_only) {
    out.status = warm ? itp::qp::solve_warm(s.problem, s.ws, opt.settings, s.previous, s.result)
                      : itp::qp::solve_cold(s.problem, s.ws, opt.settings, s.result);
  } else {
    // As the planner's StageQp: a chain-form file goes to the chain solver
    // first, cold or from the previous file's working set.
    out.status =
        itp::qp::solve_structured(s.problem, s.ws, opt.settings, warm ? &s.previous : nullptr, s.result, chain_hot);
  }
  const auto t1 = std::chrono::steady_clock::now();
  out.time_us = std::chrono::duration<double, std::micro>(t1 - t0).count();
  out.start = hot || (chain_hot && out.status == itp::qp::QpStatus::kOptimal && s.ws.chain_stride > 0)
                  ? "hot"
                  : (warm ? "warm" : "cold");
  s.previous = s.result.working_set;
  s.have_previous = itp::qp::is_usable(out.status);
  s.previous_qp = &in.qp;
  return out;
}

// FNV-1a over the bit patterns of everything a solve returns (status, counters,
// objective, x, multipliers or ray, working set): two builds of the solver give
// bit-identical results on a file exactly when their digests agree.
template <class D>
std::string result_digest(const itp::qp::QpResult<D>& r, int n, int m) {
  std::uint64_t h = 1469598103934665603ULL;
  auto mix = [&h](const void* data, std::size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
      h ^= b[i];
      h *= 1099511628211ULL;
    }
  };
  const int head[] = {static_cast<int>(r.status), r.iterations, r.refactorisations, r.proximal_steps};
  mix(head, sizeof head);
  mix(&r.objective, sizeof r.objective);
  mix(&r.certificate_residual, sizeof r.certificate_residual);
  mix(&r.certificate_gap, sizeof r.certificate_gap);
  mix(r.x, sizeof(r.x[0]) * static_cast<std::size_t>(n));
  mix(r.y_bounds, sizeof(r.y_bounds[0]) * static_cast<std::size_t>(n));
  mix(r.y_rows, sizeof(r.y_rows[0]) * static_cast<std::size_t>(m));
  for (int i = 0; i < r.working_set.size; ++i) {
    const auto& e = r.working_set.entries[i];
    const int v[] = {e.index, e.is_bound, e.side};
    mix(v, sizeof v);
  }
  return fmt::format("{:016x}", h);
}

// Everything reported about one file, from its last solve.
template <class D>
nlohmann::json report(const Solver<D>& s, const Input& in, const Outcome& last, std::vector<double>& times,
                      const char* variant, const Options& opt, bool& ok) {
  using itp::qp::QpStatus;
  nlohmann::json rec;
  rec["file"] = in.path;
  rec["name"] = in.name;
  rec["format"] = in.format;
  rec["variant"] = variant;
  rec["start"] = last.start;
  rec["n"] = in.qp.n;
  rec["m"] = in.qp.m;
  rec["status"] = itp::qp::to_string(last.status);
  rec["iterations"] = s.result.iterations;
  rec["proximal_steps"] = s.result.proximal_steps;
  rec["digest"] = result_digest(s.result, in.qp.n, in.qp.m);
  rec["refactorisations"] = s.result.refactorisations;
  std::sort(times.begin(), times.end());
  rec["median_us"] = times[times.size() / 2];
  rec["min_us"] = times.front();
  rec["max_us"] = times.back();
  ok = last.status == QpStatus::kOptimal;
  if (last.status == QpStatus::kOptimal) {
    const auto kkt = itp::qp::kkt_residual(s.problem, s.result);
    double data_scale = 1.0;
    for (double v : in.qp.g) data_scale = std::max(data_scale, std::abs(v));
    const double objective = s.result.objective + in.constant;
    rec["objective"] = objective;
    rec["kkt_residual"] = kkt.max();
    rec["kkt_relative"] = kkt.max() / data_scale;
    ok = ok && kkt.max() <= opt.tolerance * data_scale;
    if (in.qp.x_ref) {
      double dev = 0.0, ref_scale = 1.0;
      for (int j = 0; j < in.qp.n; ++j) {
        const double r = (*in.qp.x_ref)[static_cast<std::size_t>(j)];
        dev = std::max(dev, std::abs(s.result.x[j] - r));
        ref_scale = std::max(ref_scale, std::abs(r));
      }
      rec["x_ref_deviation"] = dev;
      ok = ok && dev <= opt.tolerance * ref_scale;
    }
    if (in.obj_ref) {
      const double rel = std::abs(objective - *in.obj_ref) / std::max(1.0, std::abs(*in.obj_ref));
      rec["obj_ref"] = *in.obj_ref;
      rec["rel_obj_err"] = rel;
      ok = ok && rel <= opt.tolerance;
    }
  }
  if (last.status == QpStatus::kInfeasible) {
    // The dual ray, checked again here from the file's data (certificates.hpp).
    const auto check =
        itp::qp::check_dual_ray(s.problem, s.result.y_bounds, s.result.y_rows, opt.settings.certificate_radius);
    nlohmann::json cert;
    cert["residual"] = check.residual;
    cert["gap"] = check.gap;
    cert["holds"] = check.holds;
    cert["y_rows"] = std::vector<double>(s.result.y_rows, s.result.y_rows + in.qp.m);
    cert["y_bounds"] = std::vector<double>(s.result.y_bounds, s.result.y_bounds + in.qp.n);
    rec["certificate"] = cert;
  }
  return rec;
}

// Published objective values, one "NAME value" per line ('#' comments).
std::map<std::string, double> read_references(const std::string& path, std::string& error) {
  std::map<std::string, double> refs;
  std::ifstream in(path);
  if (!in) {
    error = "cannot open " + path;
    return refs;
  }
  std::string line;
  while (std::getline(in, line)) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ss(line);
    std::string name;
    double v = 0.0;
    if (ss >> name >> v) refs[name] = v;
  }
  return refs;
}

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  std::string b = path.substr(slash == std::string::npos ? 0 : slash + 1);
  const auto dot = b.find_last_of('.');
  return dot == std::string::npos ? b : b.substr(0, dot);
}

bool read_input(const std::string& path, const std::map<std::string, double>& refs, Input& in, std::string& error) {
  in.path = path;
  in.name = base_name(path);
  if (hil::formats::looks_like_qps(path)) {
    hil::formats::QpsProblem qps;
    if (!hil::formats::read_qps_file(path, qps, error)) return false;
    in.format = "qps";
    in.qps_name = qps.name;
    in.qp = std::move(qps.qp);
    in.constant = qps.constant;
  } else {
    if (!hil::formats::read_qp_text_file(path, in.qp, error)) return false;
    in.format = "qp-text/1";
    if (in.qp.obj_ref) in.obj_ref = *in.qp.obj_ref;
  }
  // By file name first (CVXQP1_S.QPS says NAME CVXQP1), then by QPS NAME.
  auto it = refs.find(in.name);
  if (it == refs.end() && !in.qps_name.empty()) it = refs.find(in.qps_name);
  if (it != refs.end()) in.obj_ref = it->second;
  return true;
}

// qp-text/1 copy of an input (QPS -> qp-text for other solvers); obj_ref
// then excludes the constant, as qp-text/1 has none.
bool write_copy(const Input& in, const std::string& dir, std::string& error) {
  hil::formats::QpText copy = in.qp;
  if (in.obj_ref) copy.obj_ref = *in.obj_ref - in.constant;
  return hil::formats::write_qp_text_file(dir + "/" + in.name + ".qp", copy, error);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Solve QPs (min 1/2 x'Hx + g'x s.t. lbA <= Ax <= ubA, lb <= x <= ub) from qp-text/1 or QPS\n"
      "(free MPS with QUADOBJ/QSECTION, RANGES, BOUNDS) files with the firmware's dual active-set\n"
      "solver (docs/qp.md). Per file: status, objective (QPS: with its constant), iterations,\n"
      "max KKT residual, median time over --repeat runs, the deviation from x_ref / obj_ref or\n"
      "--references, and for 'infeasible' the dual ray and its check. Variants, the first that\n"
      "fits: the planner's coarse (40 x 20), speed (45 x 210) and path (63 x 400) shapes, banded\n"
      "(n <= 160, m <= 800, <= 32 nonzeros per row, H half-bandwidth <= 16), general (n <= 160,\n"
      "m <= 1200, any structure). Chain-form files (the coarse shape: interleaved chains with\n"
      "difference rows, docs/qp.md \"Chain solver\") go to the chain solver first, as in the planner:\n"
      "cold, --warm from the previous working set, --hot also skipping the checks of H and A."};
  std::vector<std::string> files;
  Options opt;
  auto& st = opt.settings;
  app.add_option("files", files, "QP files (qp-text/1 or QPS), solved in the order given")->required();
  app.add_option("--repeat", opt.repeat,
                 "cold: solve each file N times; --warm/--hot: N passes over the sequence, each from a "
                 "fresh solver; report the median time")
      ->check(CLI::Range(1, 100000));
  auto* warm = app.add_flag("--warm", opt.warm,
                            "the files are one sequence: start each from the previous file's final "
                            "working set (files of the same n and m), refactorising H and A");
  app.add_flag("--hot", opt.hot,
               "as --warm, but where H and A equal the previous file's, reuse its factorisations "
               "(solve_hot); other files are solved warm")
      ->excludes(warm);
  app.add_flag("--json", opt.json, "print one JSON document instead of text");
  app.add_flag("--no-chain", opt.general_only,
               "solve chain-form files (the coarse shape) with the general active-set solver only, "
               "not the chain solver first");
  app.add_flag("--check", opt.check,
               "exit 1 unless every file is optimal with KKT residual and reference deviations <= "
               "--tolerance (relative to 1 + |data|)");
  app.add_option("--tolerance", opt.tolerance, "tolerance for --check and rel_obj_err (default 1e-6)");
  app.add_option("--references", opt.references,
                 "file of published optimal objectives, one 'NAME value' per line (file name without "
                 "extension, else QPS NAME)");
  app.add_option("--require-solved", opt.require_solved,
                 "exit 1 unless at least K files are solved to --tolerance, no 'optimal' misses its "
                 "reference and no file with a reference is called infeasible");
  app.add_option("--write-qp-text", opt.write_dir,
                 "also write each input as qp-text/1 into this directory (obj_ref from --references, "
                 "without the QPS constant)");
  // Every setting of itp::qp::QpSettings (workspace.hpp documents them).
  app.add_option("--primal-tolerance", st.primal_tolerance, "max violation of a unit-norm row counted as satisfied")
      ->capture_default_str();
  app.add_option("--dual-tolerance", st.dual_tolerance, "multipliers above -this count as non-negative")
      ->capture_default_str();
  app.add_option("--singular-tolerance", st.singular_tolerance,
                 "pivot below this * |m|^2 marks a linearly dependent constraint")
      ->capture_default_str();
  app.add_option("--refactor-tolerance", st.refactor_tolerance,
                 "active-set residual above which the factor is recomputed")
      ->capture_default_str();
  app.add_option("--proximal-weight", st.proximal_weight,
                 "eps of the proximal term for a singular H (0: automatic)")
      ->capture_default_str();
  app.add_option("--stationarity-tolerance", st.stationarity_tolerance,
                 "proximal iterations stop when eps |x_k+1 - x_k| <= this (1 + |g| + |Hx|)")
      ->capture_default_str();
  app.add_option("--certificate-radius", st.certificate_radius,
                 "'infeasible' needs a ray proving no feasible x within this times the data's scale")
      ->capture_default_str();
  app.add_option("--max-iterations", st.max_iterations, "iteration cap (0: the variant's 3(N+M))")
      ->capture_default_str();
  app.add_option("--max-proximal-steps", st.max_proximal_steps, "proximal iteration cap (0: the variant's)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  std::string error;
  std::map<std::string, double> refs;
  if (!opt.references.empty()) {
    refs = read_references(opt.references, error);
    if (!error.empty()) {
      fmt::print(stderr, "qp_solve: {}\n", error);
      return 2;
    }
  }
  // Read everything first (parsing is never timed).
  std::vector<Input> inputs;
  nlohmann::json out = nlohmann::json::array();
  bool all_ok = true;
  for (const auto& path : files) {
    Input in;
    error.clear();
    if (!read_input(path, refs, in, error)) {
      all_ok = false;
      nlohmann::json rec{{"file", path}, {"status", "read_error"}, {"error", error}};
      if (!opt.json) fmt::print("{}: error: {}\n", path, error);
      out.push_back(rec);
      continue;
    }
    if (!opt.write_dir.empty() && !write_copy(in, opt.write_dir, error)) {
      fmt::print(stderr, "qp_solve: {}\n", error);
      return 2;
    }
    inputs.push_back(std::move(in));
  }

  // Variant per file; one solver state per variant, fresh for each pass.
  std::vector<int> variant(inputs.size(), -1);
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    int bw = 0, nnz = 0;
    shape(inputs[k].qp, bw, nnz);
    const auto& q = inputs[k].qp;
    variant[k] = fits<CoarseQp>(q, bw, nnz)   ? 0
                 : fits<SpeedQp>(q, bw, nnz)  ? 1
                 : fits<PathQp>(q, bw, nnz)   ? 2
                 : fits<BandedQp>(q, bw, nnz) ? 3
                 : fits<GeneralQp>(q, bw, nnz) ? 4
                                               : -1;
  }
  const bool sequence = opt.warm || opt.hot;
  const int passes = sequence ? opt.repeat : 1;
  const int per_file = sequence ? 1 : opt.repeat;
  std::vector<std::vector<double>> times(inputs.size());
  std::vector<nlohmann::json> records(inputs.size());
  std::vector<bool> ok(inputs.size(), false);
  for (int pass = 0; pass < passes; ++pass) {
    auto coarse = std::make_unique<Solver<CoarseQp>>();
    auto speed = std::make_unique<Solver<SpeedQp>>();
    auto path = std::make_unique<Solver<PathQp>>();
    auto banded = std::make_unique<Solver<BandedQp>>();
    auto general = std::make_unique<Solver<GeneralQp>>();
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      if (variant[k] < 0) continue;
      const bool final_pass = pass + 1 == passes;
      bool good = false;
      // Solves file k per_file times with solver s; on the final pass reports it.
      auto run = [&](auto& s) {
        Outcome last;
        for (int r = 0; r < per_file; ++r) {
          last = solve_once(s, inputs[k], opt);
          times[k].push_back(last.time_us);
        }
        if (final_pass) {
          records[k] = report(s, inputs[k], last, times[k], kVariantNames[variant[k]], opt, good);
          ok[k] = good;
        }
      };
      switch (variant[k]) {
        case 0: run(*coarse); break;
        case 1: run(*speed); break;
        case 2: run(*path); break;
        case 3: run(*banded); break;
        default: run(*general); break;
      }
    }
  }
  int solved = 0, wrong_optimal = 0, wrong_infeasible = 0;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const Input& in = inputs[k];
    if (variant[k] < 0) {
      all_ok = false;
      nlohmann::json rec{{"file", in.path}, {"status", "beyond_capacity"},
                         {"error", fmt::format("n {} m {} fits neither variant", in.qp.n, in.qp.m)}};
      if (!opt.json) fmt::print("{}: error: {}\n", in.path, rec["error"].get<std::string>());
      out.push_back(rec);
      continue;
    }
    out.push_back(records[k]);
    all_ok = all_ok && ok[k];
    const std::string status = records[k]["status"];
    solved += ok[k] ? 1 : 0;
    if (status == "optimal" && in.obj_ref && !ok[k]) ++wrong_optimal;
    if (status == "infeasible" && in.obj_ref) ++wrong_infeasible;
  }
  if (opt.json) {
    fmt::print("{}\n", nlohmann::json{{"format", "qp-solve/1"},
                                      {"results", out},
                                      {"summary",
                                       {{"files", files.size()},
                                        {"solved", solved},
                                        {"wrong_optimal", wrong_optimal},
                                        {"wrong_infeasible", wrong_infeasible}}}}
                           .dump(2));
  } else {
    for (const auto& rec : out) {
      if (!rec.contains("variant")) continue;
      std::string line = fmt::format("{}: status {} ({} {}) n {} m {} iterations {}", rec["file"].get<std::string>(),
                                     rec["status"].get<std::string>(), rec["variant"].get<std::string>(),
                                     rec["start"].get<std::string>(), rec["n"].get<int>(), rec["m"].get<int>(),
                                     rec["iterations"].get<int>());
      if (rec["proximal_steps"].get<int>() > 0) line += fmt::format(" proximal {}", rec["proximal_steps"].get<int>());
      if (rec.contains("objective")) {
        line += fmt::format(" objective {:.12g} kkt {:.3g}", rec["objective"].get<double>(),
                            rec["kkt_residual"].get<double>());
      }
      if (rec.contains("rel_obj_err")) line += fmt::format(" rel_obj_err {:.3g}", rec["rel_obj_err"].get<double>());
      if (rec.contains("x_ref_deviation")) {
        line += fmt::format(" x_ref_dev {:.3g}", rec["x_ref_deviation"].get<double>());
      }
      if (rec.contains("certificate")) {
        line += fmt::format(" certificate residual {:.3g} gap {:.3g} holds {}",
                            rec["certificate"]["residual"].get<double>(), rec["certificate"]["gap"].get<double>(),
                            rec["certificate"]["holds"].get<bool>());
      }
      line += fmt::format(" median {:.2f} us (min {:.2f}, max {:.2f}, {} runs)", rec["median_us"].get<double>(),
                          rec["min_us"].get<double>(), rec["max_us"].get<double>(), opt.repeat);
      fmt::print("{}\n", line);
    }
    fmt::print("# summary files {} solved {} wrong_optimal {} wrong_infeasible {}\n", files.size(), solved,
               wrong_optimal, wrong_infeasible);
  }
  if (opt.require_solved >= 0) {
    return (solved >= opt.require_solved && wrong_optimal == 0 && wrong_infeasible == 0) ? 0 : 1;
  }
  return (opt.check && !all_ok) ? 1 : 0;
}
