#include "study/ch5/pair_simulation.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "core/random.hpp"
#include "lie/euler.hpp"
#include "lie/gaussian.hpp"
#include "lie/metrics.hpp"
#include "lie/ssc.hpp"
#include "lie/uncertain.hpp"

namespace keel::study::ch5 {

using namespace keel::lie;

void PairStudySetup::validate() const {
  if (samples < 2) throw std::invalid_argument("PairStudySetup: samples must be >= 2");
}

namespace {

double corr(const Mat6& S, int a, int b) {
  const double d = std::sqrt(S(a, a) * S(b, b));
  return d > 0 ? S(a, b) / d : 0.0;
}

// The study of one pair at each sample size of `sizes` (ascending, ≥ 2): M samples drawn from `rng` in turn,
// and after the M-th the record at M = sizes[s]. The first M draws are those of a run at M alone, and the
// accumulators at the M-th sample are that run's, so record s is bit for bit the record of a run with
// samples = sizes[s] on the same stream.
std::vector<PairRecord> study_one(const SE2& Ti, const SE2& Tj, const Mat6& S,
                                  const std::vector<std::size_t>& sizes, core::Rng& rng) {
  PairRecord rec;
  rec.corr_x = corr(S, 0, 3);
  rec.corr_y = corr(S, 1, 4);
  rec.corr_theta = corr(S, 2, 5);

  const Mat3 Sii = S.block<3, 3>(0, 0), Sjj = S.block<3, 3>(3, 3), Sij = S.block<3, 3>(0, 3);
  const UncertainPose<SE2> gi(Ti, Sii), gj(Tj, Sjj);
  const auto joint = relative(gi, gj, Sij);  // eq. 5.51, all four terms
  const auto ind = relative(gi, gj);         // eq. 5.51, first two terms
  const SE2 mean = joint.mean;               // eq. 5.48
  const SE2 mean_inv = mean.inverse();

  // SSC tail-to-tail on the (x, y, θ) parameters with the first-order coordinate covariance.
  Mat6 Jx = Mat6::Zero();
  Jx.block<3, 3>(0, 0) = ssc_jacobian_of_left_perturbation(Ti);
  Jx.block<3, 3>(3, 3) = ssc_jacobian_of_left_perturbation(Tj);
  const Mat6 Sx = Jx * S * Jx.transpose();
  const auto ssc_pred = ssc::tail_to_tail(ssc_from_se2(Ti), ssc_from_se2(Tj), Sx);

  // Monte Carlo: ξ ~ N(0, S) (eqs. 5.57–5.59); the SSC reference is the sample covariance of the same
  // samples' parameters (about their sample mean, angle differences wrapped around the predicted mean).
  const Mat6 L = Mat6(covariance_square_root(S));
  Mat3 lie_acc = Mat3::Zero(), ssc_acc = Mat3::Zero(), raw_acc = Mat3::Zero();
  Vec3 ssc_sum = Vec3::Zero(), raw_sum = Vec3::Zero();
  std::vector<PairRecord> out;
  out.reserve(sizes.size());
  for (std::size_t m = 0; out.size() < sizes.size(); ++m) {
    Vec6 z;
    for (int k = 0; k < 6; ++k) z(k) = rng.normal();
    const Vec6 xi = L * z;
    const SE2 Ti_m = SE2::exp(xi.head<3>()) * Ti;
    const SE2 Tj_m = SE2::exp(xi.tail<3>()) * Tj;
    const SE2 Tm = Ti_m.inverse() * Tj_m;  // eq. 5.58
    const Vec3 e = (Tm * mean_inv).log();  // eq. 5.59
    lie_acc += e * e.transpose();
    const Vec3 raw = ssc_from_se2(Tm);
    raw_sum += raw;
    raw_acc += raw * raw.transpose();
    Vec3 x = raw - ssc_pred.mean;
    x(2) = wrap_angle(x(2));
    ssc_sum += x;
    ssc_acc += x * x.transpose();
    if (m + 1 != sizes[out.size()]) continue;
    const double M = static_cast<double>(m + 1);
    const Mat3 lie_mc = lie_acc / M;  // eq. 5.57
    const Vec3 ssc_mean = ssc_sum / M;
    const Mat3 ssc_mc = (ssc_acc - M * ssc_mean * ssc_mean.transpose()) / (M - 1.0);
    rec.error_joint = covariance_error(joint.cov, lie_mc);
    rec.error_independent = covariance_error(ind.cov, lie_mc);
    rec.normalized_error_lie = normalized_covariance_error(joint.cov, lie_mc);
    rec.normalized_error_ssc = normalized_covariance_error(ssc_pred.cov, ssc_mc);
    const Vec3 raw_mean = raw_sum / M;
    const Mat3 raw_mc = (raw_acc - M * raw_mean * raw_mean.transpose()) / (M - 1.0);
    rec.normalized_error_ssc_raw_angles = normalized_covariance_error(ssc_pred.cov, raw_mc);
    const double tr = joint.cov.trace();
    rec.normalized_mc_floor = std::sqrt((tr * tr + (joint.cov * joint.cov).trace()) / M) / joint.cov.norm();
    out.push_back(rec);
  }
  return out;
}

}  // namespace

std::vector<std::vector<PairRecord>> simulate_pairs_2d_sizes(const std::vector<SE2>& poses,
                                                             const std::vector<std::pair<int, int>>& pairs,
                                                             const std::vector<Mat6>& joint_covs,
                                                             const std::vector<std::size_t>& sizes,
                                                             const repro::RunContext& context,
                                                             core::Progress* progress) {
  if (sizes.empty()) throw std::invalid_argument("simulate_pairs_2d: no sample size given");
  for (std::size_t s = 0; s < sizes.size(); ++s) {
    if (sizes[s] < 2 || (s > 0 && sizes[s] <= sizes[s - 1]))
      throw std::invalid_argument(
          fmt::format("simulate_pairs_2d: sample sizes must be >= 2 and ascending (got {} after {})",
                      sizes[s], s > 0 ? fmt::format("{}", sizes[s - 1]) : std::string("nothing")));
  }
  if (pairs.size() != joint_covs.size()) {
    throw std::invalid_argument(
        fmt::format("simulate_pairs_2d: {} pairs but {} covariances", pairs.size(), joint_covs.size()));
  }
  const int n = static_cast<int>(poses.size());
  for (const auto& [i, j] : pairs) {
    if (i < 0 || j < 0 || i >= n || j >= n) {
      throw std::invalid_argument(
          fmt::format("simulate_pairs_2d: pair ({}, {}) refers to a pose outside [0, {})", i, j, n));
    }
  }
  std::vector<std::vector<PairRecord>> per_pair(pairs.size());  // per_pair[k][s]: pair k at sizes[s]
  context.trials(  // one trial per pair; its record is its PairRecord at every size
      pairs.size(),
      [&](std::size_t k) {
        core::Rng rng = context.streams().stream(k);
        const auto [i, j] = pairs[k];
        try {
          per_pair[k] = study_one(poses[static_cast<std::size_t>(i)], poses[static_cast<std::size_t>(j)],
                                  joint_covs[k], sizes, rng);
        } catch (const std::exception& e) {
          throw std::runtime_error(fmt::format("pair ({}, {}): {}", i, j, e.what()));
        }
        for (auto& r : per_pair[k]) r.i = i, r.j = j;
      },
      progress, per_pair);
  std::vector<std::vector<PairRecord>> out(sizes.size(), std::vector<PairRecord>(pairs.size()));
  for (std::size_t k = 0; k < pairs.size(); ++k)
    for (std::size_t s = 0; s < sizes.size(); ++s) out[s][k] = per_pair[k][s];
  return out;
}

std::vector<PairRecord> simulate_pairs_2d(const std::vector<SE2>& poses,
                                          const std::vector<std::pair<int, int>>& pairs,
                                          const std::vector<Mat6>& joint_covs, const PairStudySetup& setup,
                                          const repro::RunContext& context, core::Progress* progress) {
  setup.validate();
  return std::move(
      simulate_pairs_2d_sizes(poses, pairs, joint_covs, {setup.samples}, context, progress).front());
}

PairStatistics pair_statistics(const std::vector<PairRecord>& records, double PairRecord::* field,
                               int offset) {
  PairStatistics st;
  double sum = 0, sum2 = 0;
  for (const auto& r : records) {
    if (offset >= 0 && r.j - r.i != offset) continue;
    const double v = r.*field;
    sum += v;
    sum2 += v * v;
    ++st.count;
  }
  if (st.count == 0) return st;
  st.mean = sum / static_cast<double>(st.count);
  st.std = std::sqrt(std::max(0.0, sum2 / static_cast<double>(st.count) - st.mean * st.mean));
  return st;
}

}  // namespace keel::study::ch5
