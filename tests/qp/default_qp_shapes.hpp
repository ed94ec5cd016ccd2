#pragma once
// The planner's QP shapes in the default configuration, for the tests and
// benchmarks that exercise them (the shapes themselves name no default).
#include "itp/config.hpp"
#include "itp/qp/dimensions.hpp"

template <typename S>
using PathQp = itp::qp::PathQpDims<S, itp::DefaultConfig>;
template <typename S>
using SpeedQp = itp::qp::SpeedQpDims<S, itp::DefaultConfig>;
template <typename S>
using CoarseQp = itp::qp::CoarseQpDims<S, itp::DefaultConfig>;
