// The public queries of a MarginalCovariance (marginal_covariance.hpp): options, joint marginals and the pair
// queries; the factorization is factor.cpp, the extraction methods extraction.hpp.
#include "cov/marginal_covariance.hpp"

#include <fmt/format.h>
#include <stdexcept>
#include <string>

#include "core/names.hpp"
#include "cov/extraction.hpp"

namespace keel::cov {

// ---------------------------------------------------------------------------------------------------------------------
// Options
// ---------------------------------------------------------------------------------------------------------------------

namespace {

constexpr core::NameTable<Extraction, 3> kExtraction{
    "cov::Extraction",
    {{{Extraction::automatic, "auto"}, {Extraction::forward, "forward"}, {Extraction::solve, "solve"}}}};

}  // namespace

std::string_view to_string(Extraction e) { return kExtraction.name(e); }

Extraction extraction_from_string(std::string_view s) { return kExtraction.parse(s); }

void CovarianceOptions::validate() const {
  if (block_columns < 1)
    throw std::invalid_argument(
        fmt::format("CovarianceOptions: block_columns must be >= 1 (got {})", block_columns));
  if (extraction == Extraction::forward && !supernodal)
    throw std::invalid_argument(
        "CovarianceOptions: extraction 'forward' needs a supernodal factorization "
        "(supernodal = true)");
}

std::vector<MatX> MarginalCovariance::joint_many(const std::vector<std::vector<int>>& queries,
                                                 unsigned threads) const {
  const Impl& I = *impl_;
  for (const auto& q : queries)
    for (int v : q) I.check(v);
  return I.extraction == Extraction::forward ? detail::joint_many_forward(I, queries, threads)
                                             : detail::joint_many_solve(I, queries, threads);
}

MatX MarginalCovariance::joint(const std::vector<int>& vars) const { return joint_many({vars}, 1).front(); }

MatX MarginalCovariance::marginal(int var) const { return joint({var}); }

namespace {

// The pair queries of an SE(2) (D = 3) or SE(3) (D = 6) graph: every id a pose, the poses of that dimension.
template <int D>
void check_pairs(const MarginalCovariance::Impl& I, const std::vector<std::pair<int, int>>& pairs,
                 const char* what) {
  if (I.pose_dof != D)
    throw std::invalid_argument(
        fmt::format("{}: the poses are not SE({}) (pose DoF {})", what, D == 3 ? 2 : 3, I.pose_dof));
  for (const auto& [i, j] : pairs)
    for (int v : {i, j})
      if (v < 0 || v >= I.num_poses)
        throw std::invalid_argument(
            fmt::format("{}: {} is not a pose id (0 … {})", what, v, I.num_poses - 1));
}

}  // namespace

std::vector<Mat6> pair_marginals_2d(const MarginalCovariance& cov,
                                    const std::vector<std::pair<int, int>>& pairs, unsigned threads) {
  const auto& I = *cov.impl_;
  check_pairs<3>(I, pairs, "pair_marginals_2d");
  return I.extraction == Extraction::forward ? detail::pairs_forward<3>(I, pairs, threads)
                                             : detail::pairs_solve<3>(I, pairs, threads);
}

std::vector<Mat12> pair_marginals_3d(const MarginalCovariance& cov,
                                     const std::vector<std::pair<int, int>>& pairs, unsigned threads) {
  const auto& I = *cov.impl_;
  check_pairs<6>(I, pairs, "pair_marginals_3d");
  return I.extraction == Extraction::forward ? detail::pairs_forward<6>(I, pairs, threads)
                                             : detail::pairs_solve<6>(I, pairs, threads);
}

std::vector<MatX> pair_marginals(const MarginalCovariance& cov, const std::vector<std::pair<int, int>>& pairs,
                                 unsigned threads) {
  std::vector<MatX> out;
  out.reserve(pairs.size());
  if (cov.impl_->pose_dof == 6) {
    for (auto& m : pair_marginals_3d(cov, pairs, threads)) out.emplace_back(m);
  } else {
    for (auto& m : pair_marginals_2d(cov, pairs, threads)) out.emplace_back(m);
  }
  return out;
}

std::vector<MatX> linear_map_covariances(const MarginalCovariance& cov, const std::vector<LinearMap>& maps,
                                         const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                                         unsigned threads) {
  const auto& I = *cov.impl_;
  for (std::size_t u = 0; u < maps.size(); ++u) {
    const LinearMap& m = maps[u];
    if (m.vars.empty() || m.vars.size() != m.coefficients.size())
      throw std::invalid_argument(
          fmt::format("linear_map_covariances: map {} has {} variables and {} coefficient blocks (at least "
                      "one, one each)",
                      u, m.vars.size(), m.coefficients.size()));
    const auto rows = m.coefficients.front().rows();
    for (std::size_t t = 0; t < m.vars.size(); ++t) {
      I.check(m.vars[t]);
      const MatX& C = m.coefficients[t];
      if (rows < 1 || C.rows() != rows || C.cols() != I.dim(m.vars[t]))
        throw std::invalid_argument(
            fmt::format("linear_map_covariances: map {}, term {} ({}): coefficients {}×{}, expected {}×{}", u,
                        t, I.variable_name(m.vars[t]), C.rows(), C.cols(), std::max<Eigen::Index>(rows, 1),
                        I.dim(m.vars[t])));
    }
  }
  for (const auto& [u, v] : pairs)
    if (u >= maps.size() || v >= maps.size())
      throw std::out_of_range(fmt::format("linear_map_covariances: pair ({}, {}) names a map outside 0 … {}",
                                          u, v, static_cast<std::ptrdiff_t>(maps.size()) - 1));
  return I.extraction == Extraction::forward ? detail::maps_forward(I, maps, pairs, threads)
                                             : detail::maps_solve(I, maps, pairs, threads);
}

}  // namespace keel::cov
