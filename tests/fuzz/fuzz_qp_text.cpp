// libFuzzer target: the qp-text/1 reader (hil_sim/formats/qp_text.cpp) and
// the solver on what it reads. The reader must refuse bad files with an
// error, never abort or allocate what a header merely claims; an answer the
// solver calls optimal must be finite and feasible.
// It found issue 13's defects 4 and 5 within seconds; both are fixed.
#include <cmath>
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
  itp::qp::solve_cold(*problem, *workspace, itp::qp::QpSettings<double>{}, *result);
  if (result->status != itp::qp::QpStatus::kOptimal) return 0;
  for (int i = 0; i < problem->n; ++i) {
    const double x = result->x[i];
    trap_unless(std::isfinite(x));
    trap_unless(x >= problem->lb[i] - 1e-6 * (1 + std::fabs(problem->lb[i])) &&
                x <= problem->ub[i] + 1e-6 * (1 + std::fabs(problem->ub[i])));
  }
  for (int r = 0; r < problem->m; ++r) {
    double ax = 0;
    for (int k = 0; k < problem->a_nnz[r]; ++k) ax += problem->a_val[r][k] * result->x[problem->a_col[r][k]];
    trap_unless(ax >= problem->lba[r] - 1e-6 * (1 + std::fabs(problem->lba[r])) &&
                ax <= problem->uba[r] + 1e-6 * (1 + std::fabs(problem->uba[r])));
  }
  return 0;
}
