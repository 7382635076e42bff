// keel::app — the solvers' summaries as named fields, written once for every face: `keel solve --json`,
// `keel marginals --json` and the Python module's dicts walk the same field list (records.cpp), so a field
// has one name everywhere and a figure of a proof is gated by the proof in one place.
//
// A FieldWriter receives the fields in order; the JSON writer (the keel command) and the dict writer (the
// Python module) are its two implementations. The text summaries of the keel command read the gated figures
// from proven_figures() below, the same function the records use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>

#include "app/robust.hpp"
#include "cov/marginal_covariance.hpp"
#include "pgo/certified.hpp"
#include "pgo/optimize.hpp"

namespace keel::app {

class FieldWriter {
 public:
  virtual ~FieldWriter() = default;
  virtual void null(std::string_view name) = 0;
  virtual void boolean(std::string_view name, bool value) = 0;
  virtual void integer(std::string_view name, std::int64_t value) = 0;
  virtual void text(std::string_view name, std::string_view value) = 0;
  /// A nested record whose fields `fill` writes into the writer it is given.
  virtual void record(std::string_view name, const std::function<void(FieldWriter&)>& fill) = 0;
  /// A list of n records; fill(k, w) writes record k.
  virtual void records(std::string_view name, std::size_t n,
                       const std::function<void(std::size_t, FieldWriter&)>& fill) = 0;
  /// A number; one that is not finite (NaN: undefined, ±∞: no bound) is written as null, as JSON has no
  /// such numbers.
  void number(std::string_view name, double value);
  /// `value` when it is there, null otherwise.
  void number(std::string_view name, const std::optional<double>& value);

 protected:
  virtual void finite_number(std::string_view name, double value) = 0;
};

/// What the proof behind a certificate's lower bound established, rounded outward (bound down, gap and shift
/// up). Engaged only when that proof succeeded (Certificate::proven): nothing else may be printed as proven.
struct ProvenFigures {
  double lower_bound;          // F* ≥ this, rounded down
  double relative_gap;         // (F − lower) / max(1, F), rounded up
  double dual_gap;             // (F − tr Λ) / max(1, |F|) at the multipliers, rounded up
  double shift;                // η: S + η·D ⪰ 0, so λ_min(S) ≥ −η on the rotations
  int proof_rank;              // rank of the point whose multipliers were proven
  double rounding_margin;      // μ of the scaled matrix that the factorization cleared
  double residual;             // the bound on the factor's residual that μ cleared
  double worst_case_residual;  // Higham's bound for the same factor
  double formation_error;
  bool extended_precision;  // the proof needed a double-double factor
};
[[nodiscard]] std::optional<ProvenFigures> proven_figures(const pgo::Certificate& c);

/// pgo::optimize's summary: termination, message, costs, χ², dimensions, iterations, times (not the
/// per-iteration trace).
void write_record(const pgo::Summary& s, FieldWriter& w);
/// The certified solve's summary and its certificate: every figure of a proof is null unless the proof behind
/// the lower bound succeeded; attempts that failed appear only under "failed_attempts".
void write_record(const pgo::CertifiedSummary& s, FieldWriter& w);
/// One rank of the staircase.
void write_record(const pgo::RankRecord& r, FieldWriter& w);
/// keel robust's report: sizes, threshold, the clique search, times per stage, the certified solve's record
/// ("certificate") and every candidate (candidate_list: its input edge, poses i and j, kept, and how many
/// kept closures it contradicts, q above γ either way).
void write_record(const RobustRun2& r, FieldWriter& w);
void write_record(const RobustRun3& r, FieldWriter& w);
/// What the covariance factorization did (ordering, sizes, nonzeros of L, times).
void write_record(const cov::FactorSummary& s, FieldWriter& w);

}  // namespace keel::app
