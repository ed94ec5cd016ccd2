#pragma once
// Umbrella header of the sparse dual active-set QP solver (docs/qp.md).
#include "itp/qp/certificates.hpp"
#include "itp/qp/chain_qp.hpp"
#include "itp/qp/dimensions.hpp"
#include "itp/qp/kkt.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/solver.hpp"
#include "itp/qp/status.hpp"
#include "itp/qp/workspace.hpp"
