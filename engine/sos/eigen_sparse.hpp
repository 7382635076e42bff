// Eigen's sparse modules for keel.sos, included in one place. Eigen 3.4's SparseCore/TriangularSolver.h sets
// a variable it never reads; the strict preset includes Eigen with -I (not -isystem, DESIGN rule 6) and
// -Werror, so that one warning is silenced around the include here and nowhere else.
#pragma once

#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wunused-but-set-variable"
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#pragma clang diagnostic pop
