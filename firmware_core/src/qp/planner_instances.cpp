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
// One alias per shape: a macro argument cannot hold the template's comma.
using PathDouble = PathQpDims<double, DefaultConfig>;
using SpeedDouble = SpeedQpDims<double, DefaultConfig>;
using CoarseDouble = CoarseQpDims<double, DefaultConfig>;
using PathFloat = PathQpDims<float, DefaultConfig>;
using SpeedFloat = SpeedQpDims<float, DefaultConfig>;
using CoarseFloat = CoarseQpDims<float, DefaultConfig>;
ITP_QP_INSTANTIATE(PathDouble)
ITP_QP_INSTANTIATE(SpeedDouble)
ITP_QP_INSTANTIATE(CoarseDouble)
ITP_QP_INSTANTIATE(PathFloat)
ITP_QP_INSTANTIATE(SpeedFloat)
ITP_QP_INSTANTIATE(CoarseFloat)

#undef ITP_QP_INSTANTIATE

}  // namespace itp::qp
