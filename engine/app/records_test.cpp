// app's records (records.hpp): a figure of a proof is written only when the proof succeeded, a failed attempt
// only as failed, a number that is not finite as null; the field names are each written once per record.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "app/records.hpp"
#include "core/fields.hpp"

using namespace keel;

namespace {

// Records what it is given: "name" → "null", "true", "int 3", "num 0.5", "text …"; nested names joined by
// '/'.
class Recorder final : public app::FieldWriter {
 public:
  explicit Recorder(std::string prefix = "") : prefix_(std::move(prefix)) {}
  std::map<std::string, std::string> fields;
  std::vector<std::string> order;

  void null(std::string_view n) override { put(n, "null"); }
  void boolean(std::string_view n, bool v) override { put(n, v ? "true" : "false"); }
  void integer(std::string_view n, std::int64_t v) override { put(n, "int " + std::to_string(v)); }
  void text(std::string_view n, std::string_view v) override { put(n, "text " + std::string(v)); }
  void record(std::string_view n, const std::function<void(app::FieldWriter&)>& fill) override {
    put(n, "record");
    Recorder r(prefix_ + std::string(n) + "/");
    fill(r);
    merge(r);
  }
  void records(std::string_view n, std::size_t count,
               const std::function<void(std::size_t, app::FieldWriter&)>& fill) override {
    put(n, "records " + std::to_string(count));
    for (std::size_t k = 0; k < count; ++k) {
      Recorder r(prefix_ + std::string(n) + "/" + std::to_string(k) + "/");
      fill(k, r);
      merge(r);
    }
  }

 protected:
  void finite_number(std::string_view n, double v) override { put(n, "num " + std::to_string(v)); }

 private:
  void put(std::string_view n, std::string v) {
    const std::string key = prefix_ + std::string(n);
    REQUIRE_MESSAGE(fields.count(key) == 0, "field written twice: " << key);
    fields[key] = std::move(v);
    order.push_back(key);
  }
  void merge(const Recorder& r) {
    for (const auto& k : r.order) {
      REQUIRE_MESSAGE(fields.count(k) == 0, "field written twice: " << k);
      fields[k] = r.fields.at(k);
      order.push_back(k);
    }
  }
  std::string prefix_;
};

const std::vector<std::string> kProofFields = {
    "lower_bound",       "relative_gap",    "dual_gap", "lambda_min_lower_bound", "shift",
    "proof_rank",        "rounding_margin", "residual", "worst_case_residual",    "formation_error",
    "extended_precision"};

pgo::CertifiedSummary summary_with(bool proven) {
  pgo::CertifiedSummary s;
  s.dimension = 2;
  s.final_cost = 10.0;
  auto& c = s.certificate;
  c.proven = proven;
  c.certified = proven;
  c.bound.upper = 10.0;
  c.bound.lower = proven ? 9.999999 : -std::numeric_limits<double>::infinity();
  c.trace_lambda = 9.9999995;
  c.rank = 2;
  // A proof's figures are zero when nothing was proven (pgo/certified.hpp); made nonzero here so that a
  // record that wrote them regardless would show them.
  c.shift = 1e-8;
  c.rounding_margin = 1e-12;
  c.residual = 1e-14;
  c.worst_case_residual = 1e-13;
  c.formation_error = 1e-17;
  c.extended_precision = true;
  c.tolerance_shift = 3e-8;
  c.failed_shift = proven ? 0.0 : 2e-8;
  c.attempts = 4;
  pgo::RankRecord r;
  r.rank = 2;
  r.cost = 10.0;
  s.staircase = {r, r};
  return s;
}

}  // namespace

TEST_CASE("a certificate's record writes a proof's figures only when the proof succeeded") {
  SUBCASE("proven") {
    Recorder w;
    app::write_record(summary_with(true), w);
    for (const auto& f : kProofFields) CHECK_MESSAGE(w.fields.at(f) != "null", f);
    CHECK(w.fields.at("lower_bound") == "num " + std::to_string(9.999999));
    CHECK(w.fields.at("lambda_min_lower_bound") == "num " + std::to_string(-1e-8));
    CHECK(w.fields.at("proof_rank") == "int 2");
    CHECK(w.fields.at("extended_precision") == "true");
    CHECK(w.fields.at("failed_attempts") == "null");
    CHECK(w.fields.at("returned_point") == "null");
    CHECK(w.fields.at("staircase") == "records 2");
    CHECK(w.fields.at("staircase/1/rank") == "int 2");
    CHECK(w.fields.at("times_s/total") == "num " + std::to_string(0.0));
    // The gap at the multipliers rounded up: (F − tr Λ) / F ≥ its value to nearest.
    const auto p = app::proven_figures(summary_with(true).certificate);
    REQUIRE(p);
    CHECK(p->dual_gap >= (10.0 - 9.9999995) / 10.0);
    CHECK(p->relative_gap >= (10.0 - 9.999999) / 10.0);
  }
  SUBCASE("not proven: every figure of a proof is null, the failed attempt is reported as failed") {
    Recorder w;
    app::write_record(summary_with(false), w);
    for (const auto& f : kProofFields) CHECK_MESSAGE(w.fields.at(f) == "null", f);
    CHECK_FALSE(app::proven_figures(summary_with(false).certificate));
    CHECK(w.fields.at("proven") == "false");
    CHECK(w.fields.at("failed_attempts") == "record");
    CHECK(w.fields.at("failed_attempts/proven") == "false");
    CHECK(w.fields.at("failed_attempts/attempts") == "int 4");
    CHECK(w.fields.at("tolerance_shift") != "null");  // a target of the gap tolerance, not a proof
  }
  SUBCASE("the returned point's own test, when the bound is a staircase point's") {
    auto s = summary_with(true);
    s.bound_from_staircase = true;
    s.returned_point.proven = false;
    s.returned_point.bound.lower = 5.0;  // not proven: never written
    s.returned_point.failed_shift = 1e-6;
    Recorder w;
    app::write_record(s, w);
    CHECK(w.fields.at("returned_point/proven") == "false");
    CHECK(w.fields.at("returned_point/lower_bound") == "null");
    CHECK(w.fields.at("returned_point/failed_attempts/proven") == "false");
  }
}

TEST_CASE("a number that is not finite is written as null") {
  pgo::Summary s;
  s.normalized_chi2 = std::numeric_limits<double>::quiet_NaN();  // no degrees of freedom
  s.final_cost = 2.5;
  Recorder w;
  app::write_record(s, w);
  CHECK(w.fields.at("normalized_chi2") == "null");
  CHECK(w.fields.at("final_cost") == "num " + std::to_string(2.5));
  CHECK(w.fields.at("termination") == "text failure");
  Recorder f;
  app::write_record(cov::FactorSummary{}, f);
  CHECK(f.fields.count("ordering") == 1);
  CHECK(f.fields.count("factorize_time_s") == 1);
}

TEST_CASE("the solver summary's record names its fields as pgo::Summary's members are named") {
  Recorder w;
  app::write_record(pgo::Summary{}, w);
  const auto names = core::field_names<pgo::Summary>();
  const std::set<std::string_view> members(names.begin(), names.end());
  for (const auto& name : w.order) CHECK_MESSAGE(members.count(name) == 1, name);
}
