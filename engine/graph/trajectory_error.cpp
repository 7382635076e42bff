#include "graph/trajectory_error.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <stdexcept>

#include "graph/residuals.hpp"

namespace keel::graph {

namespace {

template <class Pose>
void check_sizes(const std::vector<Pose>& reference, const std::vector<Pose>& estimate, const char* what) {
  if (reference.size() != estimate.size())
    throw std::invalid_argument(
        fmt::format("{}: {} reference poses but {} estimated", what, reference.size(), estimate.size()));
  if (reference.empty()) throw std::invalid_argument(fmt::format("{}: no pose", what));
}

template <class Pose>
double ate(const std::vector<Pose>& reference, const std::vector<Pose>& estimate) {
  check_sizes(reference, estimate, "absolute_trajectory_error");
  using Point = typename Pose::Point;
  constexpr int kDim = Point::RowsAtCompileTime;
  using Mat = Eigen::Matrix<double, kDim, kDim>;
  const double n = static_cast<double>(reference.size());
  Point mr = Point::Zero(), me = Point::Zero();
  for (std::size_t k = 0; k < reference.size(); ++k) {
    mr += reference[k].translation();
    me += estimate[k].translation();
  }
  mr /= n;
  me /= n;
  // Cross-covariance Σ (p_k − p̄)(p̂_k − p̂̄)ᵀ = U S Vᵀ; R = U diag(1, …, det(U Vᵀ)) Vᵀ maximizes tr(Rᵀ Σ).
  Mat C = Mat::Zero();
  for (std::size_t k = 0; k < reference.size(); ++k)
    C += (reference[k].translation() - mr) * (estimate[k].translation() - me).transpose();
  const Eigen::JacobiSVD<Mat> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat D = Mat::Identity();
  D(kDim - 1, kDim - 1) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Mat R = svd.matrixU() * D * svd.matrixV().transpose();
  const Point t = mr - R * me;
  double sum = 0.0;
  for (std::size_t k = 0; k < reference.size(); ++k)
    sum += (reference[k].translation() - (R * estimate[k].translation() + t)).squaredNorm();
  return std::sqrt(sum / n);
}

template <class Pose>
double rpe(const std::vector<Pose>& reference, const std::vector<Pose>& estimate,
           const std::vector<std::pair<int, int>>& pairs) {
  check_sizes(reference, estimate, "relative_pose_error");
  if (pairs.empty()) throw std::invalid_argument("relative_pose_error: no pair of poses");
  const int n = static_cast<int>(reference.size());
  double sum = 0.0;
  for (const auto& [i, j] : pairs) {
    if (i < 0 || i >= n || j < 0 || j >= n)
      throw std::invalid_argument(
          fmt::format("relative_pose_error: pair ({}, {}) names a pose out of 0 … {}", i, j, n - 1));
    const auto si = static_cast<std::size_t>(i), sj = static_cast<std::size_t>(j);
    // ρ(z⁻¹ T̂_i⁻¹ T̂_j) with z = T_i⁻¹ T_j: the edge residual (residuals.hpp), its translation first.
    const auto r = edge_residual(Pose(reference[si].inverse() * reference[sj]), estimate[si], estimate[sj]);
    sum += r.template head<Pose::Point::RowsAtCompileTime>().squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(pairs.size()));
}

}  // namespace

double absolute_trajectory_error(const std::vector<SE2>& reference, const std::vector<SE2>& estimate) {
  return ate(reference, estimate);
}
double absolute_trajectory_error(const std::vector<SE3>& reference, const std::vector<SE3>& estimate) {
  return ate(reference, estimate);
}
double relative_pose_error(const std::vector<SE2>& reference, const std::vector<SE2>& estimate,
                           const std::vector<std::pair<int, int>>& pairs) {
  return rpe(reference, estimate, pairs);
}
double relative_pose_error(const std::vector<SE3>& reference, const std::vector<SE3>& estimate,
                           const std::vector<std::pair<int, int>>& pairs) {
  return rpe(reference, estimate, pairs);
}

}  // namespace keel::graph
