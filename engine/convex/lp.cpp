#include "convex/lp.hpp"

#include <coin/ClpDualRowDantzig.hpp>
#include <coin/ClpSimplex.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace keel::convex {

void LpRows::add(double row_lo, double row_hi, const std::vector<int>& cols,
                 const std::vector<double>& vals) {
  if (cols.size() != vals.size())
    throw std::invalid_argument(
        fmt::format("convex::LpRows::add: {} columns but {} values", cols.size(), vals.size()));
  lo.push_back(row_lo);
  hi.push_back(row_hi);
  columns.insert(columns.end(), cols.begin(), cols.end());
  values.insert(values.end(), vals.begin(), vals.end());
  starts.push_back(static_cast<int>(values.size()));
}

Lp::Lp(const std::vector<double>& cost, const std::vector<double>& col_lo, const std::vector<double>& col_hi,
       const LpOptions& options)
    : model_(std::make_unique<ClpSimplex>()) {
  const std::size_t n = cost.size();
  if (col_lo.size() != n || col_hi.size() != n)
    throw std::invalid_argument(fmt::format("convex::Lp: {} costs but {} lower and {} upper column bounds", n,
                                            col_lo.size(), col_hi.size()));
  model_->setLogLevel(0);
  if (options.dantzig_dual_pricing) {
    ClpDualRowDantzig pricing;
    model_->setDualRowPivotAlgorithm(pricing);
  }
  std::vector<CoinBigIndex> start(n + 1, 0);
  model_->loadProblem(static_cast<int>(n), 0, start.data(), nullptr, nullptr, col_lo.data(), col_hi.data(),
                      cost.data(), nullptr, nullptr);
  model_->setOptimizationDirection(1.0);
  if (!options.scaling) model_->scaling(0);
}

Lp::~Lp() = default;
Lp::Lp(Lp&&) noexcept = default;
Lp& Lp::operator=(Lp&&) noexcept = default;

int Lp::rows() const { return model_->numberRows(); }
int Lp::columns() const { return model_->numberColumns(); }

int Lp::add_rows(const LpRows& r) {
  const int first = model_->numberRows();
  if (r.size() == 0) return first;
  if (static_cast<int>(r.starts.size()) != r.size() + 1 || r.hi.size() != r.lo.size() ||
      r.columns.size() != r.values.size())
    throw std::invalid_argument("convex::Lp::add_rows: the compressed rows are inconsistent");
  const std::vector<CoinBigIndex> starts(r.starts.begin(), r.starts.end());
  model_->addRows(r.size(), r.lo.data(), r.hi.data(), starts.data(), r.columns.data(), r.values.data());
  return first;
}

void Lp::delete_rows(const std::vector<int>& rows) {
  if (!rows.empty()) model_->deleteRows(static_cast<int>(rows.size()), rows.data());
}

void Lp::set_coefficient(int row, int column, double value) {
  model_->modifyCoefficient(row, column, value, true);
}
void Lp::set_row_bounds(int row, double lo, double hi) { model_->setRowBounds(row, lo, hi); }
void Lp::set_column_bounds(int column, double lo, double hi) { model_->setColumnBounds(column, lo, hi); }

LpStatus Lp::solve(double objective_limit) {
  model_->setDualObjectiveLimit(objective_limit);
  // startFinishOptions bit 1 (ClpSimplex.hpp): the factorization's storage and the work areas stay allocated
  // after the solve, for the next solve of this model. Bits 2 and 4 (reuse the old factorization, skip the
  // set-up of work areas by whatsChanged) are not set: every solve factorizes its starting basis and rebuilds
  // its row copy as before, so the pivots, and the answers, are the same bits; only the allocations go.
  model_->dual(0, 1);
  // Status 1 with secondary status 1: "primal infeasible because dual limit reached" (ClpModel.hpp).
  // ClpModel::isDualObjectiveLimitReached() is not used: it also answers true for an infeasible problem.
  if (objective_limit < kLpInfinity && model_->status() == 1 && model_->secondaryStatus() == 1)
    return LpStatus::cut_off;
  if (model_->isProvenPrimalInfeasible()) return LpStatus::infeasible;
  if (!model_->isProvenOptimal()) return LpStatus::failed;
  // Secondary status 2–4: optimal for CLP's scaled problem only, infeasible once unscaled (ClpModel.hpp).
  // Such a point was up to 2 % above the optimum on keel.align's LPs, and as a lower bound it certified wrong
  // answers; it is not reported as optimal.
  if (model_->secondaryStatus() >= 2 && model_->secondaryStatus() <= 4) return LpStatus::failed;
  return LpStatus::optimal;
}

std::vector<unsigned char> Lp::basis() const {
  const unsigned char* st = model_->statusArray();
  const int n = model_->numberColumns() + model_->numberRows();
  return st ? std::vector<unsigned char>(st, st + n) : std::vector<unsigned char>{};
}

void Lp::set_basis(const std::vector<unsigned char>& basis) {
  const auto nc = static_cast<std::size_t>(model_->numberColumns()),
             nr = static_cast<std::size_t>(model_->numberRows());
  if (basis.size() < nc)
    throw std::invalid_argument(
        fmt::format("convex::Lp::set_basis: {} statuses for {} columns", basis.size(), nc));
  // Column statuses first, then rows (CLP's layout); rows added since the basis was taken are basic.
  std::vector<unsigned char> st(nc + nr, static_cast<unsigned char>(ClpSimplex::basic));
  std::copy(basis.begin(), basis.begin() + static_cast<std::ptrdiff_t>(std::min(basis.size(), st.size())),
            st.begin());
  model_->copyinStatus(st.data());
}

int Lp::iterations() const { return model_->numberIterations(); }
double Lp::objective() const { return model_->objectiveValue(); }
const double* Lp::solution() const { return model_->primalColumnSolution(); }
const double* Lp::row_duals() const { return model_->dualRowSolution(); }

}  // namespace keel::convex
