#pragma once
// A hook through which host tools see every QP the planner solves (planner_cli
// --dump-qp writes them as qp-text/1). Plain function pointers, null by
// default: the firmware never sets it and pays one null check per solve.
#include "itp/config.hpp"
#include "itp/qp/dimensions.hpp"
#include "itp/qp/problem.hpp"

namespace itp::qp {

struct PlannerQpObserver {
  void* context = nullptr;
  void (*coarse)(void* context, const QpProblem<CoarseQpDims<Scalar>>& problem) = nullptr;
  void (*path)(void* context, const QpProblem<PathQpDims<Scalar>>& problem) = nullptr;
  void (*speed)(void* context, const QpProblem<SpeedQpDims<Scalar>>& problem) = nullptr;
};

}  // namespace itp::qp
