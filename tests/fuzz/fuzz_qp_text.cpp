// libFuzzer target: the qp-text/1 reader (hil_sim/formats/qp_text.cpp) and
// the solver on what it reads. The reader must refuse bad files with an
// error, never abort or allocate what a header merely claims; an answer the
// solver calls optimal must be finite and meet the solver's documented
// feasibility contract (docs/qp.md, "Feasibility contract"), evaluated here
// independently in long double: every bound's and row's violation at most
// (primal_tolerance + refactor_tolerance) max(1, sum_k |a_k x_k|, |b|).
// It found issue 13's defects 4 and 5 within seconds, and a row of norm 1e9
// violated by 0.3 at x = 0 (docs/fuzzing.md); all three are fixed.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>

#include "formats/qp_text.hpp"
#include "itp/qp/qp.hpp"

namespace {
void trap_unless(bool ok) {
  if (!ok) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using D = itp::qp::PathQpDims<double, itp::DefaultConfig>;
  static auto problem = std::make_unique<itp::qp::QpProblem<D>>();
  static auto workspace = std::make_unique<itp::qp::QpWorkspace<D>>();
  static auto result = std::make_unique<itp::qp::QpResult<D>>();
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  hil::formats::QpText text;
  std::string error;
  if (!hil::formats::read_qp_text(in, text, error) || !hil::formats::to_problem(text, *problem, error)) {
    return 0;
  }
  const itp::qp::QpSettings<double> settings{};
  itp::qp::solve_cold(*problem, *workspace, settings, *result);
  if (result->status != itp::qp::QpStatus::kOptimal) return 0;
  using LD = long double;
  const LD tol = static_cast<LD>(settings.primal_tolerance) + static_cast<LD>(settings.refactor_tolerance);
  const LD eps = static_cast<LD>(std::numeric_limits<double>::epsilon());
  // v <= tol max(1, mag, |b|), with room for the rounding of the solver's own
  // double evaluation of a'x (4 (nnz + 2) eps mag; far below tol mag).
  auto within = [&](LD ax, LD mag, LD lo, LD hi, int nnz) {
    const LD v = ax > hi ? ax - hi : (ax < lo ? lo - ax : 0.0L);
    const LD b = ax > hi ? std::fabs(hi) : (ax < lo ? std::fabs(lo) : 0.0L);
    const LD scale = std::max<LD>(std::max<LD>(1.0L, mag), b);
    return v <= tol * scale * (1.0L + 1e-6L) + 4.0L * static_cast<LD>(nnz + 2) * eps * mag;
  };
  for (int i = 0; i < problem->n; ++i) {
    const double x = result->x[i];
    trap_unless(std::isfinite(x));
    const LD xl = static_cast<LD>(x);
    trap_unless(within(xl, std::fabs(xl), static_cast<LD>(problem->lb[i]), static_cast<LD>(problem->ub[i]), 1));
  }
  for (int r = 0; r < problem->m; ++r) {
    LD ax = 0, mag = 0;
    for (int k = 0; k < problem->a_nnz[r]; ++k) {
      const LD t = static_cast<LD>(problem->a_val[r][k]) * static_cast<LD>(result->x[problem->a_col[r][k]]);
      ax += t;
      mag += std::fabs(t);
    }
    trap_unless(within(ax, mag, static_cast<LD>(problem->lba[r]), static_cast<LD>(problem->uba[r]), problem->a_nnz[r]));
  }
  return 0;
}
