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

}  // namespace keel::cov
