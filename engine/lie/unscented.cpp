#include "unscented.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "euler.hpp"
#include "gaussian.hpp"

namespace keel::lie {

SigmaPoints sigma_points(const VecX& mean, const MatX& cov, const UtParams& params) {
  const Eigen::Index n = mean.size();
  if (n == 0) throw std::invalid_argument("sigma_points: empty mean");
  if (cov.rows() != n || cov.cols() != n) {
    throw std::invalid_argument(fmt::format("sigma_points: covariance is {}x{} but the mean has {} entries",
                                            cov.rows(), cov.cols(), n));
  }
  const double nd = static_cast<double>(n);
  const double lambda = params.alpha * params.alpha * (nd + params.kappa) - nd;
  const double spread2 = nd + lambda;
  if (!(spread2 > 0.0)) throw std::invalid_argument("sigma_points: n + lambda must be positive");
  const MatX L = covariance_square_root(cov) * std::sqrt(spread2);  // validates cov
  SigmaPoints sp;
  sp.points.resize(n, 2 * n + 1);
  sp.points.col(0) = mean;
  for (Eigen::Index i = 0; i < n; ++i) {
    sp.points.col(1 + i) = mean + L.col(i);
    sp.points.col(1 + n + i) = mean - L.col(i);
  }
  sp.wm = VecX::Constant(2 * n + 1, 1.0 / (2.0 * spread2));
  sp.wc = sp.wm;
  sp.wm(0) = lambda / spread2;
  sp.wc(0) = lambda / spread2 + (1.0 - params.alpha * params.alpha + params.beta);
  return sp;
}

UtResult unscented_transform(const VecX& mean, const MatX& cov, const std::function<VecX(const VecX&)>& f,
                             const UtParams& params) {
  const SigmaPoints sp = sigma_points(mean, cov, params);
  const Eigen::Index K = sp.points.cols();
  std::vector<VecX> ys;
  ys.reserve(static_cast<std::size_t>(K));
  for (Eigen::Index k = 0; k < K; ++k) {
    ys.push_back(f(sp.points.col(k)));
    if (ys.back().size() != ys.front().size())
      throw std::invalid_argument("unscented_transform: f returned outputs of different sizes");
  }
  const Eigen::Index m = ys.front().size();
  UtResult r;
  r.mean = VecX::Zero(m);
  for (Eigen::Index k = 0; k < K; ++k) r.mean += sp.wm(k) * ys[static_cast<std::size_t>(k)];
  r.cov = MatX::Zero(m, m);
  r.cross_cov = MatX::Zero(mean.size(), m);
  for (Eigen::Index k = 0; k < K; ++k) {
    const VecX dy = ys[static_cast<std::size_t>(k)] - r.mean;
    r.cov.noalias() += sp.wc(k) * dy * dy.transpose();
    r.cross_cov.noalias() += sp.wc(k) * (sp.points.col(k) - mean) * dy.transpose();
  }
  r.cov = (0.5 * (r.cov + r.cov.transpose())).eval();
  return r;
}

namespace {

template <class G>
G group_from_ssc(const typename G::Tangent& x) {
  if constexpr (std::is_same_v<G, SE3>) {
    return se3_from_ssc(x);
  } else {
    return se2_from_ssc(x);
  }
}

}  // namespace

template <class G>
  requires std::same_as<G, SE3> || std::same_as<G, SE2>
JointPoses<G> joint_poses_from_ssc(const VecX& x_hat, const MatX& Sigma_hat, const UtParams& params) {
  constexpr int D = G::DoF;
  if (x_hat.size() == 0 || x_hat.size() % D != 0) {
    throw std::invalid_argument(fmt::format(
        "joint_poses_from_ssc: x_hat has length {}, expected a positive multiple of {}", x_hat.size(), D));
  }
  const Eigen::Index n = x_hat.size() / D;
  JointPoses<G> out;
  std::vector<G> mean_inv;
  for (Eigen::Index i = 0; i < n; ++i) {
    out.means.push_back(group_from_ssc<G>(x_hat.segment<D>(D * i)));  // eq. 5.61
    mean_inv.push_back(out.means.back().inverse());
  }
  // eq. 5.60, vectorised over all poses.
  auto ell = [&](const VecX& x) {
    VecX v(x.size());
    for (Eigen::Index i = 0; i < n; ++i)
      v.segment<D>(D * i) =
          (group_from_ssc<G>(x.segment<D>(D * i)) * mean_inv[static_cast<std::size_t>(i)]).log();
    return v;
  };
  const SigmaPoints sp = sigma_points(x_hat, Sigma_hat, params);
  out.cov = MatX::Zero(x_hat.size(), x_hat.size());
  for (Eigen::Index k = 0; k < sp.points.cols(); ++k) {
    const VecX l = ell(sp.points.col(k));
    out.cov.noalias() += sp.wc(k) * l * l.transpose();  // eq. 5.62
  }
  out.cov = (0.5 * (out.cov + out.cov.transpose())).eval();
  return out;
}

template JointPoses<SE3> joint_poses_from_ssc<SE3>(const VecX&, const MatX&, const UtParams&);
template JointPoses<SE2> joint_poses_from_ssc<SE2>(const VecX&, const MatX&, const UtParams&);

}  // namespace keel::lie
