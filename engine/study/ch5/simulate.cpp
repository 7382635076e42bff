#include "study/ch5/simulate.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "core/random.hpp"
#include "lie/euler.hpp"
#include "lie/fourth_order_joint.hpp"
#include "lie/gaussian.hpp"
#include "lie/metrics.hpp"
#include "lie/ssc.hpp"
#include "lie/uncertain.hpp"
#include "lie/unscented.hpp"

namespace keel::study::ch5 {

using namespace keel::lie;

namespace {

Vec6 normal6(core::Rng& rng) {
  Vec6 z;
  for (int i = 0; i < 6; ++i) z(i) = rng.normal();
  return z;
}

// Squared Mahalanobis distances use one Cholesky factor per prediction.
struct Whitener {
  Eigen::LLT<Mat6> llt;
  explicit Whitener(const Mat6& cov, const std::string& what) : llt(cov) {
    if (llt.info() != Eigen::Success)
      throw std::runtime_error(fmt::format("{}: predicted covariance is not positive definite", what));
  }
  double d2(const Vec6& v) const { return llt.matrixL().solve(v).squaredNorm(); }
};

Vec6 ssc_difference(const Vec6& x, const Vec6& mean) {
  Vec6 d = x - mean;
  for (int i = 3; i < 6; ++i) d(i) = wrap_angle(d(i));
  return d;
}

}  // namespace

Mat6 composition_step_covariance(double sigma_t, double sigma_r) {
  Vec6 d;
  d << 0.001 * sigma_t, 1e-5 * sigma_t, 1e-5, 1e-5, 1e-5, 0.003 * sigma_r;  // eq. 5.41
  return d.asDiagonal();
}

void CompositionSetup::validate() const {
  if (steps < 1)
    throw std::invalid_argument(fmt::format("CompositionSetup: steps must be >= 1, got {}", steps));
  if (!(sigma_t > 0) || !(sigma_r > 0))
    throw std::invalid_argument("CompositionSetup: sigma_t and sigma_r must be > 0");
  if (!(rho > -1.0 && rho < 1.0)) throw std::invalid_argument("CompositionSetup: rho must lie in (-1, 1)");
  if (trajectories < 2) throw std::invalid_argument("CompositionSetup: trajectories must be >= 2");
  if (levels.empty())
    throw std::invalid_argument("CompositionSetup: at least one probability level is needed");
  for (double p : levels)
    if (!(p > 0 && p < 1)) throw std::invalid_argument("CompositionSetup: levels must lie in (0, 1)");
}

CompositionOutcome simulate_composition(const CompositionSetup& s, const repro::RunContext& context,
                                        core::Progress* progress) {
  s.validate();
  const int n = s.steps;
  const Mat6 step_cov = composition_step_covariance(s.sigma_t, s.sigma_r);
  const SE3 step_mean(SO3::identity(), Vec3(1.0, 0.0, 0.0));  // eq. 5.42
  const MatX L = covariance_square_root(step_cov);
  const Mat6 L6 = L;
  const double innovation = std::sqrt(1.0 - s.rho * s.rho);

  // Joint covariance of ξ_1..ξ_N under the AR(1) model: Cov(ξ_j, ξ_k) = ρ^|j-k| Σ.
  JointPoses<SE3> joint;
  joint.means.assign(static_cast<std::size_t>(n), step_mean);
  joint.cov = MatX::Zero(6 * n, 6 * n);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k)
      joint.cov.block<6, 6>(6 * j, 6 * k) = std::pow(s.rho, std::abs(j - k)) * step_cov;

  CompositionOutcome out;
  const auto lie_joint = compose_chain(joint, true);
  const auto lie_ind = compose_chain(joint, false);
  std::vector<UncertainPose<SE3>> steps(static_cast<std::size_t>(n), UncertainPose<SE3>(step_mean, step_cov));
  const auto lie_4th = compose_chain_fourth_order(steps);
  out.lie_joint.mean = lie_joint.mean;
  out.lie_joint.cov = lie_joint.cov;
  out.lie_independent.mean = lie_ind.mean;
  out.lie_independent.cov = lie_ind.cov;
  out.lie_fourth_order.mean = lie_4th.mean;
  out.lie_fourth_order.cov = lie_4th.cov;
  out.has_joint_fourth_order = n <= s.joint_fourth_order_max_steps;
  if (out.has_joint_fourth_order) {
    const auto j4 = compose_chain_fourth_order_joint_exact(joint);
    out.lie_joint_fourth_order.mean = j4.mean;
    out.lie_joint_fourth_order.cov = j4.cov;
  }

  // SSC inputs: the Euler parameters x_k = ssc(exp(ξ_k) T̄) of each step by the unscented transform (§5.8.1 in
  // the other direction). All steps share one distribution, so one 6-D UT gives the mean x̂, the block P and
  // the cross-covariance C = E[ξ (x - x̂)ᵀ]; the blocks between steps follow by statistical linearization,
  // Cov(x_j, x_k) = G Cov(ξ_j, ξ_k) Gᵀ with G = Cᵀ Σ⁻¹ (exact for the diagonal blocks, which keep P).
  const UtResult ut = unscented_transform(VecX::Zero(6), MatX(step_cov), [&](const VecX& xi) -> VecX {
    return ssc_from_se3(SE3::exp(Vec6(xi)) * step_mean);
  });
  const Mat6 G = Mat6(ut.cross_cov).transpose() * step_cov.inverse();
  VecX x_all(6 * n);
  MatX x_cov(6 * n, 6 * n);
  for (int j = 0; j < n; ++j) {
    x_all.segment<6>(6 * j) = ut.mean;
    for (int k = 0; k < n; ++k) {
      x_cov.block<6, 6>(6 * j, 6 * k) =
          j == k ? Mat6(ut.cov) : Mat6(std::pow(s.rho, std::abs(j - k)) * G * step_cov * G.transpose());
    }
  }
  const auto ssc_pred = ssc::head_to_tail_chain_3d(x_all, x_cov);
  out.ssc.mean = se3_from_ssc(ssc_pred.mean);
  out.ssc.cov = ssc_pred.cov;
  MatX x_cov_blocks = MatX::Zero(6 * n, 6 * n);
  for (int j = 0; j < n; ++j) x_cov_blocks.block<6, 6>(6 * j, 6 * j) = x_cov.block<6, 6>(6 * j, 6 * j);
  const auto ssc_ind = ssc::head_to_tail_chain_3d(x_all, x_cov_blocks);
  out.ssc_independent.mean = se3_from_ssc(ssc_ind.mean);
  out.ssc_independent.cov = ssc_ind.cov;

  // Monte Carlo: trajectory i draws from its own stream, so the result does not depend on the thread count.
  const std::size_t m = s.trajectories;
  std::vector<SE3> ends(m);
  context.trials(  // one trial per trajectory; its record is the end pose
      m,
      [&](std::size_t i) {
        core::Rng rng = context.streams().stream(i);
        Vec6 xi = L6 * normal6(rng);
        SE3 T = SE3::exp(xi) * step_mean;
        for (int k = 1; k < n; ++k) {
          xi = s.rho * xi + innovation * (L6 * normal6(rng));
          T = T * (SE3::exp(xi) * step_mean);
        }
        ends[i] = T;
      },
      progress, ends);

  const Whitener w_joint(lie_joint.cov, "lie_joint"), w_ind(lie_ind.cov, "lie_independent"),
      w_4th(lie_4th.cov, "lie_fourth_order"), w_ssc(ssc_pred.cov, "ssc"),
      w_ssc_ind(ssc_ind.cov, "ssc_independent"),
      w_j4(out.has_joint_fourth_order ? out.lie_joint_fourth_order.cov : Mat6(Mat6::Identity()),
           "lie_joint_fourth_order");
  const SE3 inv_joint = lie_joint.mean.inverse(), inv_ind = lie_ind.mean.inverse(),
            inv_4th = lie_4th.mean.inverse();
  std::vector<std::array<double, 6>> d2(m);
  const SE3 inv_j4 = out.lie_joint_fourth_order.mean.inverse();
  core::parallel_for(
      m,
      [&](std::size_t i) {
        d2[i][0] = w_ssc.d2(ssc_difference(ssc_from_se3(ends[i]), ssc_pred.mean));
        d2[i][1] = w_ind.d2((ends[i] * inv_ind).log());
        d2[i][2] = w_joint.d2((ends[i] * inv_joint).log());
        d2[i][3] = w_4th.d2((ends[i] * inv_4th).log());
        d2[i][4] = w_ssc_ind.d2(ssc_difference(ssc_from_se3(ends[i]), ssc_ind.mean));
        d2[i][5] = out.has_joint_fourth_order ? w_j4.d2((ends[i] * inv_j4).log()) : 0.0;
      },
      context.threads());
  CompositionPrediction* preds[6] = {&out.ssc,
                                     &out.lie_independent,
                                     &out.lie_joint,
                                     &out.lie_fourth_order,
                                     &out.ssc_independent,
                                     &out.lie_joint_fourth_order};
  for (double p : s.levels) {
    const double r2 = chi2_quantile(p, 6.0);
    for (int k = 0; k < (out.has_joint_fourth_order ? 6 : 5); ++k) {
      std::size_t inside = 0;
      for (const auto& d : d2) inside += d[k] <= r2 ? 1 : 0;
      preds[k]->inside.push_back(static_cast<double>(inside) / static_cast<double>(m));
    }
  }
  if (s.keep_samples) out.samples = std::move(ends);
  return out;
}

SscConversion convert_ssc_prediction(const CompositionOutcome& o, const std::vector<double>& levels) {
  if (o.samples.empty())
    throw std::invalid_argument("convert_ssc_prediction: the study kept no samples (set keep_samples)");
  SscConversion c;
  const auto converted = joint_poses_from_ssc<SE3>(VecX(ssc_from_se3(o.ssc.mean)), MatX(o.ssc.cov));
  c.unscented.mean = converted.means.at(0);
  c.unscented.cov = Mat6(converted.cov);
  const double m = static_cast<double>(o.samples.size());
  auto spread = [&](const SE3& mean) {
    const SE3 inv = mean.inverse();
    Mat6 S = Mat6::Zero();
    for (const auto& T : o.samples) {
      const Vec6 xi = (T * inv).log();
      S += xi * xi.transpose();
    }
    return Mat6(S / m);
  };
  c.cov_samples = spread(c.unscented.mean);
  auto volume_ratio = [](const Mat6& a, const Mat6& b) {
    return std::sqrt(a.determinant() / b.determinant());
  };
  c.volume_vs_samples = volume_ratio(c.unscented.cov, c.cov_samples);
  c.volume_vs_joint = volume_ratio(c.unscented.cov, o.lie_joint.cov);
  c.joint_volume_vs_samples = volume_ratio(o.lie_joint.cov, spread(o.lie_joint.mean));
  const Whitener w(c.unscented.cov, "ssc_unscented");
  const SE3 inv = c.unscented.mean.inverse();
  for (double p : levels) {
    const double r2 = chi2_quantile(p, 6.0);
    std::size_t inside = 0;
    for (const auto& T : o.samples) inside += w.d2((T * inv).log()) <= r2 ? 1 : 0;
    c.unscented.inside.push_back(static_cast<double>(inside) / m);
  }
  return c;
}

void RelativePoseSetup::validate() const {
  if (samples < 2) throw std::invalid_argument("RelativePoseSetup: samples must be >= 2");
  MatX joint(12, 12);
  joint << cov_g1, cov_g1_g2, cov_g1_g2.transpose(), cov_g2;
  validate_covariance(joint, "RelativePoseSetup joint covariance");
}

RelativePoseSetup relative_pose_setup(double yaw, const std::vector<double>& t_g1,
                                      const std::vector<double>& t_g2,
                                      const std::vector<double>& marginal_diag,
                                      const std::vector<double>& cross_diag, double alpha) {
  auto vec = [](const std::vector<double>& v, std::size_t n, const char* what) {
    if (v.size() != n) {
      throw std::invalid_argument(
          fmt::format("relative_pose_setup: {} needs {} numbers, got {}", what, n, v.size()));
    }
    return Eigen::Map<const VecX>(v.data(), static_cast<Eigen::Index>(n)).eval();
  };
  if (!(alpha > 0)) throw std::invalid_argument("relative_pose_setup: alpha must be > 0");
  RelativePoseSetup s;
  const SO3 R = SO3::exp(Vec3(0.0, 0.0, yaw));
  s.T_g1 = SE3(R, vec(t_g1, 3, "t_g1"));
  s.T_g2 = SE3(R, vec(t_g2, 3, "t_g2"));
  s.cov_g1 = alpha * Mat6(vec(marginal_diag, 6, "marginal_diag").asDiagonal());  // eq. 5.54
  s.cov_g2 = s.cov_g1;
  s.cov_g1_g2 = alpha * Mat6(vec(cross_diag, 6, "cross_diag").asDiagonal());  // eq. 5.55
  s.validate();
  return s;
}

RelativePoseOutcome simulate_relative_pose(const RelativePoseSetup& s, const repro::RunContext& context,
                                           core::Progress* progress) {
  s.validate();
  RelativePoseOutcome out;
  const UncertainPose<SE3> g1(s.T_g1, s.cov_g1), g2(s.T_g2, s.cov_g2);
  const auto joint = relative(g1, g2, s.cov_g1_g2);  // eq. 5.51, all terms
  const auto ind = relative(g1, g2);                 // eq. 5.51, first two terms
  out.mean = joint.mean;                             // eq. 5.48
  out.cov_joint = joint.cov;
  out.cov_independent = ind.cov;

  MatX jc(12, 12);
  jc << s.cov_g1, s.cov_g1_g2, s.cov_g1_g2.transpose(), s.cov_g2;
  const Eigen::Matrix<double, 12, 12> L = covariance_square_root(jc);
  const SE3 mean_inv = out.mean.inverse();
  std::vector<Vec6> xs(s.samples);
  std::vector<SE3> poses(s.keep_samples ? s.samples : 0);
  // One trial per sample; its record is ξ_i, and the relative pose when the samples are kept.
  const auto save = [&](repro::Writer& w, std::size_t i) {
    repro::save(w, xs[i]);
    if (s.keep_samples) repro::save(w, poses[i]);
  };
  const auto load = [&](repro::Reader& r, std::size_t i) {
    repro::load(r, xs[i]);
    if (s.keep_samples) repro::load(r, poses[i]);
  };
  context.trials(
      s.samples,
      [&](std::size_t i) {
        core::Rng rng = context.streams().stream(i);
        Eigen::Matrix<double, 12, 1> z;
        for (int k = 0; k < 12; ++k) z(k) = rng.normal();
        const Eigen::Matrix<double, 12, 1> xi = L * z;
        const SE3 T1 = SE3::exp(xi.head<6>()) * s.T_g1;
        const SE3 T2 = SE3::exp(xi.tail<6>()) * s.T_g2;
        const SE3 Tm = T1.inverse() * T2;  // eq. 5.58
        xs[i] = (Tm * mean_inv).log();     // eq. 5.59
        if (s.keep_samples) poses[i] = Tm;
      },
      save, load, progress);
  Mat6 acc = Mat6::Zero();  // eq. 5.57, summed in trial order
  for (const auto& x : xs) acc += x * x.transpose();
  out.cov_mc = acc / static_cast<double>(s.samples);
  out.error_joint = covariance_error(out.cov_joint, out.cov_mc);
  out.error_independent = covariance_error(out.cov_independent, out.cov_mc);
  if (s.keep_samples) out.samples = std::move(poses);
  return out;
}

void planar_lie_region(const SE3& mean, const Mat6& cov, double p, int count, std::vector<double>& x,
                       std::vector<double>& y) {
  if (count < 1) throw std::invalid_argument("planar_lie_region: count must be >= 1");
  Mat3 c;
  const int idx[3] = {0, 1, 5};  // ρx, ρy, φz
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) c(a, b) = cov(idx[a], idx[b]);
  const Mat3 L = Mat3(covariance_square_root(c));
  const double r = std::sqrt(chi2_quantile(p, 3.0));
  x.clear();
  y.clear();
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double zc = 1.0 - 2.0 * (i + 0.5) / count;  // Fibonacci sphere
    const double rad = std::sqrt(1.0 - zc * zc);
    const Vec3 u(rad * std::cos(golden * i), rad * std::sin(golden * i), zc);
    const Vec3 v = r * (L * u);
    Vec6 xi = Vec6::Zero();
    xi(0) = v(0);
    xi(1) = v(1);
    xi(5) = v(2);
    const SE3 T = SE3::exp(xi) * mean;
    x.push_back(T.translation()(0));
    y.push_back(T.translation()(1));
  }
}

void planar_lie_region(const CompositionPrediction& pr, double p, int count, std::vector<double>& x,
                       std::vector<double>& y) {
  planar_lie_region(pr.mean, pr.cov, p, count, x, y);
}

void planar_ssc_ellipse(const CompositionPrediction& ssc, double p, int count, std::vector<double>& x,
                        std::vector<double>& y) {
  if (count < 3) throw std::invalid_argument("planar_ssc_ellipse: count must be >= 3");
  const Mat2 c = ssc.cov.block<2, 2>(0, 0);
  const Mat2 L = Mat2(covariance_square_root(c));
  const double r = std::sqrt(chi2_quantile(p, 3.0));
  x.clear();
  y.clear();
  for (int i = 0; i <= count; ++i) {
    const double t = 2.0 * M_PI * i / count;
    const Vec2 v = r * (L * Vec2(std::cos(t), std::sin(t)));
    x.push_back(ssc.mean.translation()(0) + v(0));
    y.push_back(ssc.mean.translation()(1) + v(1));
  }
}

void planar_positions(const std::vector<SE3>& poses, std::vector<double>& x, std::vector<double>& y) {
  x.clear();
  y.clear();
  x.reserve(poses.size());
  y.reserve(poses.size());
  for (const auto& T : poses) {
    x.push_back(T.translation()(0));
    y.push_back(T.translation()(1));
  }
}

}  // namespace keel::study::ch5
