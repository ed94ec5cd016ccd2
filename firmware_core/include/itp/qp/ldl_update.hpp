#pragma once
// LDL' factor of the working-set Gram matrix K = M_W M_W' (M = A L^-T, one row
// per active constraint), kept up to date as constraints enter and leave.
// L is unit lower triangular, stored packed by rows without its diagonal:
// L(i, j), j < i, lives at l[i (i - 1) / 2 + j]. w = number of rows.
//
// append (w -> w + 1), given k = K(w, 0..w-1) and kappa = K(w, w):
//   z = L^-1 k,  L(w, j) = z_j / d_j,  d_w = kappa - sum_j z_j L(w, j)   O(w^2)
// remove row/column r (w -> w - 1): rows above r are unchanged; rows below
// shift up, drop column r, and their trailing block takes the rank-one update
//   L22 D22 L22' + d_r c c',  c = L(r+1.., r)                           O(w^2)
// (Gill, Golub, Murray, Saunders 1974, method C1; as in DAQP).
namespace itp::qp::ldl {

constexpr int row_offset(int i) { return i * (i - 1) / 2; }

template <typename S>
S append(S* l, S* d, int w, const S* k, S kappa) {
  S* row = l + row_offset(w);
  S dw = kappa;
  for (int i = 0; i < w; ++i) {
    const S* li = l + row_offset(i);
    S z = k[i];
    for (int j = 0; j < i; ++j) z -= li[j] * row[j] * d[j];
    // row[j] currently holds L(w, j) = z_j / d_j for j < i, so
    // z_i = k_i - sum_j L(i, j) d_j L(w, j).
    row[i] = z / d[i];
    dw -= z * row[i];
  }
  d[w] = dw;
  return dw;
}

// c: scratch of length >= w.
template <typename S>
void remove(S* l, S* d, int w, int r, S* c) {
  // Save column r below the diagonal, then compact the rows below r.
  for (int i = r + 1; i < w; ++i) c[i - r - 1] = l[row_offset(i) + r];
  for (int i = r + 1; i < w; ++i) {
    const S* src = l + row_offset(i);
    S* dst = l + row_offset(i - 1);  // dst <= src: forward copy is safe
    for (int j = 0; j < r; ++j) dst[j] = src[j];
    for (int j = r + 1; j < i; ++j) dst[j - 1] = src[j];
  }
  S alpha = d[r];
  for (int i = r; i + 1 < w; ++i) d[i] = d[i + 1];
  // Rank-one update of the trailing block (new indices r..w-2) with alpha c c'.
  const int p = w - 1 - r;
  for (int j = 0; j < p; ++j) {
    const S cj = c[j];
    const S dj = d[r + j];
    const S dbar = dj + alpha * cj * cj;
    if (!(dbar > S(0))) {
      // Lost definiteness (only possible through rounding or a singular last
      // row); keep the value and let the caller's accuracy check refactorise.
      d[r + j] = dbar;
      alpha = S(0);
      continue;
    }
    const S beta = cj * alpha / dbar;
    alpha = dj * alpha / dbar;
    d[r + j] = dbar;
    for (int i = j + 1; i < p; ++i) {
      S& lij = l[row_offset(r + i) + r + j];
      c[i] -= cj * lij;
      lij += beta * c[i];
    }
  }
}

// Solves L D L' x = b in place.
template <typename S>
void solve(const S* l, const S* d, int w, S* b) {
  for (int i = 0; i < w; ++i) {
    const S* li = l + row_offset(i);
    S s = b[i];
    for (int j = 0; j < i; ++j) s -= li[j] * b[j];
    b[i] = s;
  }
  for (int i = 0; i < w; ++i) b[i] /= d[i];
  for (int i = w - 1; i >= 0; --i) {
    const S bi = b[i];
    const S* li = l + row_offset(i);
    for (int j = 0; j < i; ++j) b[j] -= li[j] * bi;
  }
}

// With a zero last pivot (row w-1 linearly dependent on the others), returns
// the null vector p of K with p[w-1] = 1: L' p = e_last, i.e.
//   L11' p1 = -L(w-1, 0..w-2)'.   Then M_W' p = 0.
template <typename S>
void null_vector(const S* l, int w, S* p) {
  const S* last = l + row_offset(w - 1);
  for (int j = 0; j < w - 1; ++j) p[j] = -last[j];
  p[w - 1] = S(1);
  for (int i = w - 2; i >= 0; --i) {
    const S pi = p[i];
    const S* li = l + row_offset(i);
    for (int j = 0; j < i; ++j) p[j] -= li[j] * pi;
  }
}

}  // namespace itp::qp::ldl
