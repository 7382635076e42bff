// keel::lie — the unscented transform (thesis §5.8.1) and the conversion of an SSC
// (Euler-angle) Gaussian into jointly distributed Lie-algebra poses (eqs. 5.60-5.62).
#pragma once

#include <concepts>
#include <functional>

#include "types.hpp"
#include "uncertain.hpp"

namespace keel::lie {

/// Scaled unscented-transform parameters.  With n the input dimension and
/// lambda = alpha^2 (n + kappa) - n, the 2n + 1 sigma points are
///   X_0 = mu,  X_{i} = mu + sqrt(n + lambda) L_i,  X_{n+i} = mu - sqrt(n + lambda) L_i  (L L^T = Sigma)
/// with weights
///   Wm_0 = lambda / (n + lambda),  Wc_0 = Wm_0 + (1 - alpha^2 + beta),  W_i = 1 / (2 (n + lambda)).
/// For alpha = 1, beta = 0 this is exactly the Julier & Uhlmann (1997) set, eq. (12):
/// W_0 = kappa / (n + kappa), W_i = 1 / (2 (n + kappa)), spread sqrt(n + kappa).
/// Default: alpha = 1, beta = 0, kappa = 0 (J&U 1997 with kappa = 0): all weights are
/// non-negative (W_0 = 0), so the output covariance is always positive semi-definite even
/// for the high-dimensional joint vectors of eq. 5.62.  J&U's heuristic n + kappa = 3
/// (julier_uhlmann_heuristic) matches Gaussian fourth moments per axis but makes W_0
/// negative when n > 3.
struct UtParams {
  double alpha = 1.0;
  double beta = 0.0;
  double kappa = 0.0;

  /// J&U (1997) heuristic kappa = 3 - n.
  static UtParams julier_uhlmann_heuristic(int n) { return UtParams{1.0, 0.0, 3.0 - static_cast<double>(n)}; }
};

struct SigmaPoints {
  MatX points;  ///< n x (2n + 1), column 0 is the mean
  VecX wm;      ///< mean weights
  VecX wc;      ///< covariance weights
};

struct UtResult {
  VecX mean;       ///< sum_k Wm_k f(X_k)
  MatX cov;        ///< sum_k Wc_k (f(X_k) - mean)(f(X_k) - mean)^T
  MatX cross_cov;  ///< sum_k Wc_k (X_k - mu)(f(X_k) - mean)^T
};

/// Throws std::invalid_argument on a non-symmetric / non-PSD covariance, a size mismatch, or
/// n + lambda <= 0.
[[nodiscard]] SigmaPoints sigma_points(const VecX& mean, const MatX& cov, const UtParams& params = {});

[[nodiscard]] UtResult unscented_transform(const VecX& mean, const MatX& cov,
                                           const std::function<VecX(const VecX&)>& f,
                                           const UtParams& params = {});

/// eqs. 5.60-5.62: given stacked SSC vectors x_hat = [x_1; ...; x_n] (6n for SE3 with
/// se3_from_ssc, 3n for SE2 with se2_from_ssc) and their joint covariance Sigma_hat, returns
/// T_i = f(x_hat_i) (eq. 5.61) and Sigma_{1:n} = sum_k W_k l(X_k) l(X_k)^T (eq. 5.62) with
/// l_i(x) = log(f(x_i) f(x_hat_i)^-1) (eq. 5.60).  As in eq. 5.62 the covariance is taken
/// about zero (the perturbation of the mean pose), not about the sigma-point mean of l.
/// Explicitly instantiated for G = SE3 (default) and G = SE2.
template <class G = SE3>
  requires std::same_as<G, SE3> || std::same_as<G, SE2>
JointPoses<G> joint_poses_from_ssc(const VecX& x_hat, const MatX& Sigma_hat, const UtParams& params = {});

}  // namespace keel::lie
