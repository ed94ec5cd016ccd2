#pragma once
// Reader of QPS, the free-MPS format of QP test sets (Maros & Meszaros 1999):
//   min 1/2 x'Qx + c'x + c0   s.t.  rows of A within RHS/RANGES,  BOUNDS on x
// with the sections NAME, ROWS (N, E, L, G), COLUMNS, RHS, RANGES, BOUNDS
// (UP, LO, FX, FR, MI, PL, BV), QUADOBJ / QSECTION (lower triangle, each
// off-diagonal entry once) or QMATRIX (both triangles), OBJSENSE and ENDATA.
// Names contain no blanks (free MPS); '*' in column 1 starts a comment line.
// The result is the dense qp-text/1 content (formats/qp_text.hpp) plus the
// objective constant c0 = -(RHS of the objective row).
//
// Conventions (those of the MPS/QPS readers of CPLEX and the test sets):
// default bounds 0 <= x < inf; an UP bound below 0 on a variable whose lower
// bound was not given makes the lower bound -inf; the first N row is the
// objective, further N rows are free and dropped; RANGES R on an E row
// gives [rhs, rhs + R] for R > 0 and [rhs + R, rhs] for R < 0, on L rows
// [rhs - |R|, rhs], on G rows [rhs, rhs + |R|]. OBJSENSE MAX negates c, Q and
// c0 (the QP is then the minimisation of the negated objective). Integer
// markers and semi-continuous bounds are refused with a message.
#include <iosfwd>
#include <string>

#include "formats/qp_text.hpp"

namespace hil::formats {

struct QpsProblem {
  std::string name;        // NAME section
  QpText qp;               // dense data, qp-text/1 convention
  double constant = 0.0;   // c0: objective = 1/2 x'Hx + g'x + constant
  bool maximise = false;   // OBJSENSE MAX (qp holds the negated objective)
};

// Parses QPS; memory follows the data read, sizes are bounded by the
// qp-text/1 reader's limits (kMaxTextVariables, ...). On failure returns
// false and says why, with the line number. No exception escapes.
bool read_qps(std::istream& in, QpsProblem& out, std::string& error);
bool read_qps_file(const std::string& path, QpsProblem& out, std::string& error);

// True if the file looks like QPS (its first section header is NAME, ROWS
// or a comment), not qp-text/1.
bool looks_like_qps(const std::string& path);

}  // namespace hil::formats
