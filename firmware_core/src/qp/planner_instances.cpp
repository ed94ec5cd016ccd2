// Explicit instantiations of the solver for the planner's QP shapes, in
// double and in float, so that every firmware build (host and
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

// Both scalar types explicitly (not Scalar and float, which coincide in the
// float build and would instantiate twice), with the default configuration's
// shapes. Other configurations instantiate the solver implicitly in the
// stages that use it (two configurations may share a QP shape, which an
// explicit instantiation here would define twice).
ITP_QP_INSTANTIATE(PathQpDims<double>)
ITP_QP_INSTANTIATE(SpeedQpDims<double>)
ITP_QP_INSTANTIATE(CoarseQpDims<double>)
ITP_QP_INSTANTIATE(PathQpDims<float>)
ITP_QP_INSTANTIATE(SpeedQpDims<float>)
ITP_QP_INSTANTIATE(CoarseQpDims<float>)

#undef ITP_QP_INSTANTIATE

}  // namespace itp::qp
