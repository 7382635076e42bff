// The CHOLMOD state behind a linalg::SparseCholesky (private to engine/linalg: includes cholmod.h, which
// users of sparse_cholesky.hpp never see). sparse_cholesky.cpp analyses, factorizes and solves;
// sparse_cholesky_bounds.cpp bounds the residual of the computed factor and factorizes in double-double.
#pragma once

#include <cholmod.h>

#include <vector>

#include "linalg/sparse_cholesky.hpp"

namespace keel::linalg {

// L̂ as a packed lower-triangular matrix in compressed columns (the permuted order of the factorization), the
// rows of each column ascending.
struct LowerFactor {
  std::vector<int> p, i;
  std::vector<double> x;
};

// The rows of a lower-triangular pattern with sorted columns: for row j, the positions q (into i / x) of its
// entries L_jk, k ≤ j, and their columns; in column k every later position holds a row below j.
struct RowIndex {
  std::vector<int> p, q, col;
};

// L̂ of a CHOLMOD factor (supernodal or simplicial), packed with sorted columns.
LowerFactor lower_factor(cholmod_factor* factor, cholmod_common* c);

struct SparseCholesky::Impl {
  cholmod_common c;
  cholmod_sparse* A = nullptr;  // shares nothing: the pattern and values are copied in factorize()
  cholmod_factor* L = nullptr;
  LowerFactor lower;  // L̂ of the last factorization, made on first use
  bool lower_valid = false;
  // factorize_extended(): the symbolic pattern (made once), its row index and the double-double factor.
  std::vector<int> ext_p, ext_i;
  RowIndex ext_rows;
  std::vector<double> ext_x, ext_xl;
  bool extended_valid = false;
  const LowerFactor& lower_factor() {
    if (!lower_valid) {
      lower = keel::linalg::lower_factor(L, &c);
      lower_valid = true;
    }
    return lower;
  }
  Impl() {
    cholmod_start(&c);
    c.print = 0;  // failures come back through status checks
  }
  ~Impl() {
    if (L) cholmod_free_factor(&L, &c);
    if (A) cholmod_free_sparse(&A, &c);
    cholmod_finish(&c);
  }
};

}  // namespace keel::linalg
