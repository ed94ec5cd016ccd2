// Explicit instantiations of the solver for the planner's QP shapes, in the
// configured Scalar and in float, so that every firmware build (host and
// Cortex-M7) compiles the whole solver with the embedded rules.
#include "itp/qp/qp.hpp"

namespace itp::qp {

#define ITP_QP_INSTANTIATE(DIMS)                                                        \
  template QpStatus solve_cold<DIMS>(const QpProblem<DIMS>&, QpWorkspace<DIMS>&,       \
                                     const QpSettings<DIMS::Scalar>&, QpResult<DIMS>&); \
  template QpStatus solve_warm<DIMS>(const QpProblem<DIMS>&, QpWorkspace<DIMS>&,       \
                                     const QpSettings<DIMS::Scalar>&,                  \
                                     const WorkingSet<DIMS>&, QpResult<DIMS>&);        \
  template QpStatus solve_hot<DIMS>(const QpProblem<DIMS>&, QpWorkspace<DIMS>&,        \
                                    const QpSettings<DIMS::Scalar>&, QpResult<DIMS>&); \
  template KktResidual<DIMS::Scalar> kkt_residual<DIMS>(const QpProblem<DIMS>&,        \
                                                        const QpResult<DIMS>&);

ITP_QP_INSTANTIATE(PathQpDims<Scalar>)
ITP_QP_INSTANTIATE(SpeedQpDims<Scalar>)
ITP_QP_INSTANTIATE(CoarseQpDims<Scalar>)
ITP_QP_INSTANTIATE(PathQpDims<float>)

#undef ITP_QP_INSTANTIATE

}  // namespace itp::qp
