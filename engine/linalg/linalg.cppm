// keel.linalg — the curated facade of engine/linalg: keel's one sparse symmetric positive-definite
// factorization (CHOLMOD, inside the .cpp files only) with its fill-reducing orderings, multi-threaded solves
// and the rigorous bounds on its residual that the certificates rest on (Higham Thm 10.3, and the residual
// measured in doubled precision). Facade rules (docs/DESIGN.md): includes in the global module fragment
// (public headers only), using- declarations in the export block, no import of another facade.
module;
#include "linalg/sparse_cholesky.hpp"
export module keel.linalg;

export namespace keel::linalg {
using keel::linalg::CholeskyOptions;
using keel::linalg::FactorKind;
using keel::linalg::Ordering;
using keel::linalg::ordering_from_string;
using keel::linalg::SolveWorkspace;
using keel::linalg::SparseCholesky;
using keel::linalg::Supernodes;
using keel::linalg::to_string;
}  // namespace keel::linalg
