#include "convex/sdp.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/names.hpp"

namespace keel::convex {

namespace {
constexpr core::NameTable<SdpSolver, 2> kSolverNames{
    "convex::SdpSolver", {{{SdpSolver::dsdp, "dsdp"}, {SdpSolver::sdpa, "sdpa"}}}};

void check_entries(const std::vector<int>& sizes, const std::vector<SdpEntry>& entries,
                   const std::string& what) {
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const SdpEntry& e = entries[k];
    if (e.block < 0 || e.block >= static_cast<int>(sizes.size()))
      throw std::invalid_argument(fmt::format("convex::Sdp: {} entry {} names block {} (blocks: {})", what, k,
                                              e.block, sizes.size()));
    const int n = sizes[static_cast<std::size_t>(e.block)];
    if (e.col < 0 || e.row < e.col || e.row >= n)
      throw std::invalid_argument(fmt::format(
          "convex::Sdp: {} entry {} at ({}, {}) is not in the lower triangle of block {} (size {})", what, k,
          e.row, e.col, e.block, n));
    if (!std::isfinite(e.value))
      throw std::invalid_argument(
          fmt::format("convex::Sdp: {} entry {} is not finite ({})", what, k, e.value));
  }
}

void check_lp_entries(int size, const std::vector<LpEntry>& entries, const std::string& what) {
  for (std::size_t k = 0; k < entries.size(); ++k) {
    if (entries[k].row < 0 || entries[k].row >= size)
      throw std::invalid_argument(fmt::format(
          "convex::Sdp: {} entry {} names row {} of an orthant of size {}", what, k, entries[k].row, size));
    if (!std::isfinite(entries[k].value))
      throw std::invalid_argument(
          fmt::format("convex::Sdp: {} entry {} is not finite ({})", what, k, entries[k].value));
  }
}

double inner_lp(const Eigen::VectorXd& x, const std::vector<LpEntry>& entries) {
  double v = 0.0;
  for (const LpEntry& e : entries) v += e.value * x(e.row);
  return v;
}

double inner(const std::vector<Eigen::MatrixXd>& x, const std::vector<SdpEntry>& entries) {
  double v = 0.0;
  for (const SdpEntry& e : entries) {
    const double xe = x[static_cast<std::size_t>(e.block)](e.row, e.col);
    v += (e.row == e.col ? 1.0 : 2.0) * e.value * xe;
  }
  return v;
}

double min_eigenvalue(const Eigen::MatrixXd& m) {
  if (m.rows() == 0) return 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m, Eigen::EigenvaluesOnly);
  return es.eigenvalues()(0);
}
}  // namespace

std::string_view to_string(SdpSolver v) { return kSolverNames.name(v); }
SdpSolver sdp_solver_from_string(std::string_view s) { return kSolverNames.parse(s); }

void Sdp::validate() const {
  if (block_sizes.empty() && lp_size == 0)
    throw std::invalid_argument("convex::Sdp: no blocks and no orthant");
  if (lp_size < 0)
    throw std::invalid_argument(fmt::format("convex::Sdp: lp_size = {} (must be >= 0)", lp_size));
  for (std::size_t k = 0; k < block_sizes.size(); ++k)
    if (block_sizes[k] < 1)
      throw std::invalid_argument(
          fmt::format("convex::Sdp: block {} has size {} (must be >= 1)", k, block_sizes[k]));
  if (a.size() != b.size())
    throw std::invalid_argument(
        fmt::format("convex::Sdp: {} constraint matrices but {} right-hand sides", a.size(), b.size()));
  check_entries(block_sizes, c, "C");
  for (std::size_t i = 0; i < a.size(); ++i) {
    check_entries(block_sizes, a[i], fmt::format("A_{}", i));
    if (!std::isfinite(b[i])) throw std::invalid_argument(fmt::format("convex::Sdp: b_{} is not finite", i));
  }
  if (!lp_a.empty() && lp_a.size() != a.size())
    throw std::invalid_argument(
        fmt::format("convex::Sdp: {} orthant rows a_lp but {} constraints", lp_a.size(), a.size()));
  if (lp_size == 0 && (!lp_c.empty() || !lp_a.empty()))
    throw std::invalid_argument("convex::Sdp: orthant entries without an orthant (lp_size = 0)");
  check_lp_entries(lp_size, lp_c, "c_lp");
  for (std::size_t i = 0; i < lp_a.size(); ++i) check_lp_entries(lp_size, lp_a[i], fmt::format("a_lp,{}", i));
}

void SdpSettings::validate() const {
  if (!(gap_tolerance > 0))
    throw std::invalid_argument(
        fmt::format("convex::SdpSettings: gap_tolerance must be > 0 (got {})", gap_tolerance));
  if (max_iterations <= 0)
    throw std::invalid_argument(
        fmt::format("convex::SdpSettings: max_iterations must be > 0 (got {})", max_iterations));
}

std::vector<Eigen::MatrixXd> dense_blocks(const std::vector<int>& block_sizes,
                                          const std::vector<SdpEntry>& entries) {
  std::vector<Eigen::MatrixXd> out;
  out.reserve(block_sizes.size());
  for (int n : block_sizes) out.push_back(Eigen::MatrixXd::Zero(n, n));
  for (const SdpEntry& e : entries) {
    auto& m = out[static_cast<std::size_t>(e.block)];
    m(e.row, e.col) += e.value;
    if (e.row != e.col) m(e.col, e.row) += e.value;
  }
  return out;
}

SdpSolution solve_sdp(const Sdp& sdp, const SdpSettings& settings) {
  sdp.validate();
  settings.validate();
  switch (settings.solver) {
    case SdpSolver::dsdp:
      return detail::solve_with_dsdp(sdp, settings);
    case SdpSolver::sdpa:
      return detail::solve_with_sdpa(sdp, settings);
  }
  throw std::invalid_argument("convex::solve_sdp: unknown solver");
}

SdpCheck check_sdp(const Sdp& sdp, const SdpSolution& sol) {
  if (sol.x.size() != sdp.block_sizes.size() || sol.y.size() != sdp.constraints() ||
      (sdp.lp_size > 0 && sol.x_lp.size() != sdp.lp_size))
    throw std::invalid_argument("convex::check_sdp: the solution does not belong to this program");
  const bool lp = sdp.lp_size > 0;
  SdpCheck out;
  out.primal_objective = inner(sol.x, sdp.c);
  if (lp) out.primal_objective += inner_lp(sol.x_lp, sdp.lp_c);
  double bmax = 0.0, rmax = 0.0;
  for (int i = 0; i < sdp.constraints(); ++i) {
    const auto iu = static_cast<std::size_t>(i);
    out.dual_objective += sdp.b[iu] * sol.y(i);
    bmax = std::max(bmax, std::abs(sdp.b[iu]));
    double ax = inner(sol.x, sdp.a[iu]);
    if (lp && !sdp.lp_a.empty()) ax += inner_lp(sol.x_lp, sdp.lp_a[iu]);
    rmax = std::max(rmax, std::abs(ax - sdp.b[iu]));
  }
  out.primal_residual = rmax / (1.0 + bmax);
  out.s = dense_blocks(sdp.block_sizes, sdp.c);
  for (int i = 0; i < sdp.constraints(); ++i)
    for (const SdpEntry& e : sdp.a[static_cast<std::size_t>(i)]) {
      auto& m = out.s[static_cast<std::size_t>(e.block)];
      m(e.row, e.col) -= sol.y(i) * e.value;
      if (e.row != e.col) m(e.col, e.row) -= sol.y(i) * e.value;
    }
  out.x_min_eigenvalue = INFINITY;
  out.s_min_eigenvalue = INFINITY;
  for (std::size_t k = 0; k < out.s.size(); ++k) {
    out.x_min_eigenvalue = std::min(out.x_min_eigenvalue, min_eigenvalue(sol.x[k]));
    out.s_min_eigenvalue = std::min(out.s_min_eigenvalue, min_eigenvalue(out.s[k]));
  }
  if (lp) {
    out.s_lp = Eigen::VectorXd::Zero(sdp.lp_size);
    for (const LpEntry& e : sdp.lp_c) out.s_lp(e.row) += e.value;
    for (std::size_t i = 0; i < sdp.lp_a.size(); ++i)
      for (const LpEntry& e : sdp.lp_a[i]) out.s_lp(e.row) -= sol.y(static_cast<int>(i)) * e.value;
    out.x_min_eigenvalue = std::min(out.x_min_eigenvalue, sol.x_lp.minCoeff());
    out.s_min_eigenvalue = std::min(out.s_min_eigenvalue, out.s_lp.minCoeff());
  }
  out.relative_gap = std::abs(out.primal_objective - out.dual_objective) /
                     (1.0 + std::abs(out.primal_objective) + std::abs(out.dual_objective));
  return out;
}

}  // namespace keel::convex
