// The factor behind a MarginalCovariance (private to engine/cov): factor.cpp factorizes H with keel's one
// sparse Cholesky (linalg::SparseCholesky); extraction_forward.cpp and extraction_solve.cpp read the factor
// to extract blocks of Σ = H⁻¹ (extraction.hpp); marginal_covariance.cpp holds the public queries.
#pragma once

#include <Eigen/Core>
#include <fmt/format.h>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cov/marginal_covariance.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace keel::cov::detail {

using MapX = Eigen::Map<MatX, 0, Eigen::OuterStride<>>;
using CMapX = Eigen::Map<const MatX, 0, Eigen::OuterStride<>>;

}  // namespace keel::cov::detail

namespace keel::cov {

struct MarginalCovariance::Impl {
  int num_poses = 0;
  int num_landmarks = 0;
  int pose_dof = 3;
  int landmark_dof = 2;
  int size = 0;
  std::vector<int> offset;
  CovarianceOptions options;
  Extraction extraction = Extraction::solve;  // resolved (never automatic)
  FactorSummary summary;
  std::unique_ptr<linalg::SparseCholesky> factor;  // L Lᵀ = P H Pᵀ
  // Supernodal structure (Extraction::forward): the factor's arrays and the supernodal elimination tree.
  int nsuper = 0;
  const int* super = nullptr;  // columns super[s] … super[s+1]−1 of supernode s
  const int* pi = nullptr;     // row indices of s: ls[pi[s] … pi[s+1])
  const int* px = nullptr;     // values of s: lx[px[s] …], nsrow × nscol column-major
  const int* ls = nullptr;
  const double* lx = nullptr;
  std::vector<int> snode_of_col;  // permuted column → supernode
  std::vector<int> parent;        // supernode → parent supernode (−1 at a root); parent[s] > s
  std::vector<int> iperm;         // row of H → permuted column (L L ᵀ = P H Pᵀ)

  int num_variables() const { return num_poses + num_landmarks; }
  int dim(int v) const { return v < num_poses ? pose_dof : landmark_dof; }
  int off(int v) const { return offset[static_cast<std::size_t>(v)]; }
  int nscol(int s) const { return super[s + 1] - super[s]; }
  int nsrow(int s) const { return pi[s + 1] - pi[s]; }
  void check(int v) const {
    if (v < 0 || v >= num_variables())
      throw std::out_of_range(
          fmt::format("MarginalCovariance: variable {} is not in [0, {}) ({} poses, {} landmarks)", v,
                      num_variables(), num_poses, num_landmarks));
  }
  int variable_of_row(int r) const {  // error messages only
    int best = -1;
    for (int v = 0; v < num_variables(); ++v)
      if (off(v) >= 0 && off(v) <= r) best = v;
    return best;
  }
  std::string variable_name(int v) const {
    return v < num_poses ? fmt::format("pose {}", v) : fmt::format("landmark {}", v - num_poses);
  }
};

}  // namespace keel::cov
