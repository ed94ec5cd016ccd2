#pragma once
// A hook through which host tools see every QP the planner solves (planner_cli
// --dump-qp writes them as qp-text/1). Plain function pointers, null by
// default: the firmware never sets it and pays one null check per solve.
#include "itp/config.hpp"
#include "itp/qp/dimensions.hpp"
#include "itp/qp/problem.hpp"

namespace itp::qp {

template <class Cfg>
struct BasicPlannerQpObserver {
  void* context = nullptr;
  void (*coarse)(void* context, const QpProblem<CoarseQpDims<Scalar, Cfg>>& problem) = nullptr;
  void (*path)(void* context, const QpProblem<PathQpDims<Scalar, Cfg>>& problem) = nullptr;
  void (*speed)(void* context, const QpProblem<SpeedQpDims<Scalar, Cfg>>& problem) = nullptr;
};

using PlannerQpObserver = BasicPlannerQpObserver<DefaultConfig>;

}  // namespace itp::qp
