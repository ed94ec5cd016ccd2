#pragma once
// Settings, working set, result and the one solver workspace. All sizes come
// from the QpDims capacities; the caller owns these objects (static storage).
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "itp/qp/dimensions.hpp"
#include "itp/qp/status.hpp"

namespace itp::qp {

// Tolerances default per scalar type (docs/qp.md, "Tolerances"). Every field
// is a documented option of `qp_solve` (--primal-tolerance, ...).
template <typename S>
struct QpSettings {
  static constexpr bool kDouble = std::is_same_v<S, double>;
  // Max violation of a constraint, measured on the row scaled to unit 2-norm,
  // that still counts as satisfied (also the final feasibility check of x).
  // An optimal x also meets, in the problem's own units, violation <=
  // (primal_tolerance + refactor_tolerance) max(1, sum_k |a_k x_k|, |b|)
  // (docs/qp.md, "Feasibility contract").
  S primal_tolerance = kDouble ? S(1e-9) : S(2e-4);
  // Multipliers above -dual_tolerance count as non-negative (then clamped to 0).
  S dual_tolerance = kDouble ? S(1e-12) : S(1e-6);
  // A new working-set pivot below singular_tolerance * |m_j|^2 marks the
  // constraint as linearly dependent on the working set.
  S singular_tolerance = kDouble ? S(1e-11) : S(1e-5);
  // Residual |m_i'u - d_i| / (1 + |d_i|) on active rows above which the
  // working-set factor is recomputed from scratch (bounded per solve).
  S refactor_tolerance = kDouble ? S(1e-8) : S(1e-3);
  // Weight eps of the proximal term eps/2 |x - x_k|^2 used when H is singular
  // (positive semidefinite); 0: automatic (hessian_factor.hpp). Never used for
  // a positive definite H. The result is the optimum of the original QP.
  S proximal_weight = S(0);
  // Proximal iterations stop at a fixed point: eps |x_k+1 - x_k|_inf (the
  // stationarity residual of the original QP) <= this * (1 + |g|_inf + |Hx|_inf).
  S stationarity_tolerance = kDouble ? S(1e-10) : S(1e-5);
  // A dual ray y is reported as kInfeasible only if it proves that no x with
  // |x_j| <= certificate_radius * (1 + scale of the data) (boxed variables:
  // their box) is feasible (certificates.hpp); otherwise kNumericalTrouble.
  S certificate_radius = kDouble ? S(1e5) : S(1e2);
  // Run-time iteration cap, clamped to D::kMaxIterations (<= 0: use that).
  int max_iterations = 0;
  // Run-time cap of proximal iterations, clamped to D::kMaxProximalSteps.
  int max_proximal_steps = 0;
};

// One working-set entry: a simple bound on x[index] or row `index` of A,
// active at its lower (-1) or upper (+1) side. For an equality the side is the
// one that was violated when it entered; either side is accepted on input.
struct ActiveConstraint {
  std::int16_t index = 0;
  std::int8_t is_bound = 0;  // 1: bound on x[index], 0: row index of A
  std::int8_t side = 0;      // -1 lower, +1 upper
};

template <class D>
struct WorkingSet {
  int size = 0;
  ActiveConstraint entries[static_cast<std::size_t>(D::kMaxActive)];  // [N + 1]
  void clear() { size = 0; }
  bool push(int index, bool is_bound, int side) {
    if (size >= D::kMaxActive) return false;
    entries[size].index = static_cast<std::int16_t>(index);
    entries[size].is_bound = static_cast<std::int8_t>(is_bound ? 1 : 0);
    entries[size].side = static_cast<std::int8_t>(side < 0 ? -1 : 1);
    ++size;
    return true;
  }
};

// Solution. Multiplier sign convention (stationarity Hx + g + A'y_rows + y_bounds = 0):
// y > 0 means the UPPER side is active, y < 0 the LOWER side, 0 inactive.
template <class D>
struct QpResult {
  using S = typename D::Scalar;
  QpStatus status = QpStatus::kInvalidInput;
  int iterations = 0;             // working-set changes (adds + removes)
  int refactorisations = 0;       // from-scratch recomputations of the factor
  int proximal_steps = 0;         // outer proximal iterations (0: H positive definite)
  S objective = S(0);             // 1/2 x'Hx + g'x at x
  // kInfeasible: the dual ray's check (certificates.hpp): |A'y_rows + y_bounds|_inf
  // and the gap -(support of y) after normalising max |y_c| |a_c| to 1.
  S certificate_residual = S(0);
  S certificate_gap = S(0);
  S x[static_cast<std::size_t>(D::kMaxVariables)];          // primal solution          [N]
  // Multipliers; for kInfeasible the dual ray instead (same sign convention).
  S y_bounds[static_cast<std::size_t>(D::kMaxVariables)];   // bound multipliers        [N]
  S y_rows[static_cast<std::size_t>(D::kMaxRows > 0 ? D::kMaxRows : 1)];  // row multipliers [M]
  WorkingSet<D> working_set;      // final active set (warm start input) [N+1]
  bool usable() const { return is_usable(status); }
};

// Everything the solver needs between and during solves; reused by hotstart.
// Sizes with N = kMaxVariables, M = kMaxRows, Bw = kBandwidth:
template <class D>
struct QpWorkspace {
  using S = typename D::Scalar;
  static constexpr int kN = D::kMaxVariables;
  static constexpr int kM = D::kMaxRows;
  static constexpr int kA = D::kMaxActive;   // N + 1
  static constexpr int kC = D::kMaxConstraints;  // N + M
  static constexpr std::size_t kNz = static_cast<std::size_t>(kN);
  static constexpr std::size_t kAz = static_cast<std::size_t>(kA);
  static constexpr std::size_t kCz = static_cast<std::size_t>(kC);
  static constexpr std::size_t kBandz = static_cast<std::size_t>(D::kBandwidth + 1);
  static constexpr std::size_t kLdlz = kAz * (kAz - 1) / 2;
  static constexpr std::size_t kMz = static_cast<std::size_t>(kM > 0 ? kM : 1);
  // Variables are grouped in blocks of kScanBlock (>= 8, a power of two, so
  // that there are at most 254 blocks) for the row-skipping bound of the
  // violation scan (solver.hpp, most_violated); kScanBlocks blocks.
  static constexpr int kMaxShiftSteps = 8;  // N < 32767 needs at most 7
  static constexpr int scan_block_shift() {
    int shift = 3;
    for (int k = 0; k < kMaxShiftSteps && (kN >> shift) >= 254; ++k) ++shift;
    return shift;
  }
  static constexpr int kScanBlockShift = scan_block_shift();
  static constexpr int kScanBlock = 1 << kScanBlockShift;
  static constexpr int kScanBlocks = (kN + kScanBlock - 1) / kScanBlock;
  static constexpr std::size_t kScanBlocksz = static_cast<std::size_t>(kScanBlocks);
  static_assert(kScanBlocks < 255, "block indices are stored as uint8");
  using BlockIndex = std::uint8_t;

  S chol[kNz][kBandz];             // banded Cholesky factor L of H      [N x (Bw+1)]
  S x_unc[kNz];                    // unconstrained optimum -H^-1 g       [N]
  S x[kNz];                        // current primal iterate              [N]
  S u[kNz];                        // transformed iterate u = L'(x - x_unc) [N]
  S row_scale[kCz];                // 1 / |a_c| for violation ranking     [N + M]
  // Rows of M = A L^-T for the working set, one slot per active entry
  // (dense from m_start[slot]; the entries before it are zero and never
  // read, so they are not stored). A chain solve borrows rows 0-2 for its
  // chains' g, lb and ub and clears `factored` (chain_qp.hpp). [(N+1) x N]
  S m_rows[kAz][kNz];
  std::int16_t m_start[kAz];       // first nonzero column of each slot   [N+1]
  // With even_band: 0 / 1 if the slot's row has nonzeros only at even / odd
  // columns (then so has L^-1 a, exactly), else -1; always -1 otherwise. [N+1]
  std::int8_t m_parity[kAz];
  std::int16_t slot_of[kAz];       // working-set position -> slot        [N+1]
  std::int16_t free_slots[kAz];    // stack of unused slots               [N+1]
  int free_count = 0;             // entries in free_slots
  S ldl_l[kLdlz];                   // packed unit-lower L of M_W M_W'     [(N+1)N/2]
  S ldl_d[kAz];                    // D of M_W M_W'                       [N+1]
  S lambda[kAz];                   // dual iterate (u-space, >= 0 for ineq) [N+1]
  // y = L_K^-1 (-d_W), the forward half of lambda* = -K^-1 d_W (K = L_K D L_K'),
  // valid for positions < fwd_valid: an add extends it by one entry, a
  // removal at r invalidates r.., new bounds or a refactorisation all. [N+1]
  S fwd_d[kAz];
  S d_w[kAz];                      // signed transformed bounds of W      [N+1]
  S scratch[kAz];                  // K row / null vector / update vector [N+1]
  S scratch2[kAz];                  // H x for the objective               [N+1]
  std::int16_t w_index[kAz];       // active constraint ids (0..N-1 bounds, N.. rows) [N+1]
  std::int8_t w_side[kAz];         // active side per position, -1/+1     [N+1]
  std::int8_t active_side[kCz];    // side per constraint id, 0 inactive  [N + M]
  // Violation-scan bookkeeping (reset at every solve). path_len[b] = sum over
  // the primal steps of this solve of |dx restricted to block b|_2 (rounded
  // up); path_prefix[b] = sum of path_len[0..b-1]. row_cert[r] = certified
  // scaled slack of row r at its last exact evaluation plus the path length
  // of its blocks at that time: while row_cert[r] - (current path length of
  // its blocks) > 2 primal_tolerance the row cannot be violated and is not
  // evaluated.                                               [M], [B], [B+1]
  S row_cert[kMz];
  // Blocks touched by row r: first_block[r] .. end_block[r]-1 (set with
  // row_scale, i.e. whenever A may have changed).                 [M], [M]
  BlockIndex row_first_block[kMz];
  BlockIndex row_end_block[kMz];
  S path_len[kScanBlocksz];
  S path_prefix[kScanBlocksz + 1];
  // Weight eps of the proximal term (0: H positive definite, no proximal
  // iterations); chol then factors H + eps I.
  S proximal_weight = S(0);
  int w_size = 0;                 // |W|
  int set_aside = 0;              // constraints set aside in this solve (active_set.hpp)
  int fwd_valid = 0;              // leading entries of fwd_d that are current
  bool last_singular = false;             // last W row is linearly dependent
  bool factored = false;          // chol/m_rows valid for hotstart
  // H (hence L) has only zeros at odd band offsets: the triangular solves
  // of the iterations skip them (banded_cholesky.hpp, Stride = 2); set with chol.
  bool even_band = false;
  int factored_n = 0;                 // n the factors were built for (or the chain solver settled)
  int factored_m = 0;                 // m the factors were built for (or the chain solver settled)
  // The chain solver settled the last problem, in chains of this stride K
  // (chain_qp.hpp; 0: it did not): a restart on the same H and A may skip
  // their checks. Cleared by every factorisation of the general solver.
  int chain_stride = 0;
};

}  // namespace itp::qp
