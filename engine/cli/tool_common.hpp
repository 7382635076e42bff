// What the file commands share: stage lines on stderr, --quiet/--json, JSON output, and the solver options of
// `keel solve` and `keel marginals`. Included after `import keel.core; import keel.pgo; import keel.app;`
// (DESIGN rule 4).
#pragma once

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "commands.hpp"

namespace keel::cli {

using nlohmann::json;

// Stage lines on stderr: "keel solve [0.4 s] solving …".
class Stages {
 public:
  // Also routes Ceres's own log (app::route_solver_log): dropped under --quiet, otherwise stage lines.
  Stages(const char* command, bool quiet) : command_(command), quiet_(quiet), t0_(core::Clock::now()) {
    if (quiet) {
      app::route_solver_log({});
      return;
    }
    app::route_solver_log([command, t0 = t0_](std::string_view severity, std::string_view message) {
      // Ceres's message on its own lines, indented under the stage line that names it.
      std::string text;
      std::size_t start = 0;
      while (start < message.size()) {
        const auto end = std::min(message.find('\n', start), message.size());
        const auto line = message.substr(start, end - start);
        if (line.find_first_not_of(" \t\r") != std::string_view::npos) text += fmt::format("    {}\n", line);
        start = end + 1;
      }
      fmt::print(stderr, "keel {} [{:.1f} s] Ceres {}:\n{}", command, core::seconds_since(t0), severity,
                 text);
      std::fflush(stderr);
    });
  }
  void operator()(std::string_view stage) const {
    if (quiet_) return;
    fmt::print(stderr, "keel {} [{:.1f} s] {}\n", command_, elapsed(), stage);
    std::fflush(stderr);
  }
  double elapsed() const { return core::seconds_since(t0_); }
  // As an app::Progress.
  app::Progress progress() const {
    return [this](std::string_view s) { (*this)(s); };
  }

 private:
  const char* command_;
  bool quiet_;
  core::Clock::time_point t0_;
};

inline void add_common(CLI::App* c, Common& o) {
  c->add_flag("--quiet,-q", o.quiet, "no progress lines and no solver log on stderr");
  c->add_flag("--json", o.json, "print one JSON document on stdout instead of the text summary");
}

// Writes j to the output `file` reserved in `outputs` (renamed into place by outputs.commit()).
inline void write_json(app::Outputs& outputs, const std::filesystem::path& file, const json& j) {
  outputs.write_text(file, j.dump() + "\n");
}

template <class M>
json matrix_json(const M& m) {
  json rows = json::array();
  for (int r = 0; r < m.rows(); ++r) {
    json row = json::array();
    for (int c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

// app's records (app/records.hpp) as JSON: the field list the Python module's dicts walk too.
class JsonWriter final : public app::FieldWriter {
 public:
  explicit JsonWriter(json& out) : out_(out) { out_ = json::object(); }
  void null(std::string_view name) override { out_[std::string(name)] = nullptr; }
  void boolean(std::string_view name, bool v) override { out_[std::string(name)] = v; }
  void integer(std::string_view name, std::int64_t v) override { out_[std::string(name)] = v; }
  void text(std::string_view name, std::string_view v) override { out_[std::string(name)] = std::string(v); }
  void record(std::string_view name, const std::function<void(app::FieldWriter&)>& fill) override {
    json r;
    JsonWriter w(r);
    fill(w);
    out_[std::string(name)] = std::move(r);
  }
  void records(std::string_view name, std::size_t n,
               const std::function<void(std::size_t, app::FieldWriter&)>& fill) override {
    json list = json::array();
    for (std::size_t k = 0; k < n; ++k) {
      json r;
      JsonWriter w(r);
      fill(k, w);
      list.push_back(std::move(r));
    }
    out_[std::string(name)] = std::move(list);
  }

 protected:
  void finite_number(std::string_view name, double v) override { out_[std::string(name)] = v; }

 private:
  json& out_;
};

template <class Summary>
json record_json(const Summary& s) {
  json j;
  JsonWriter w(j);
  app::write_record(s, w);
  return j;
}

// The arguments of `keel solve` and the solve of `keel marginals`: each back end's own options
// (app/solve.hpp), bound to the command line; --init and --robust are read as names and set by
// check_solve_options.
struct SolveArgs {
  Common common;
  std::string file, out;
  std::string init = "odometry", robust = "none";  // names, as given
  std::string preconditioner = "auto";             // --certify's --preconditioner, as given
  app::MaximumLikelihood likelihood;               // the anisotropic solve (keel solve's default back end)
  app::Certified certified;                        // --certify
  bool certify = false;
  [[nodiscard]] app::SolveBackend backend() const {
    return certify ? app::SolveBackend{certified} : app::SolveBackend{likelihood};
  }
};

inline void add_solve_options(CLI::App* c, SolveArgs& a) {
  auto& o = a.likelihood.options;
  c->add_option("--init", a.init, "initial estimate: odometry, as-read (the file's vertices) or random")
      ->capture_default_str();
  c->add_option("--seed", o.seed, "seed of --init random")->capture_default_str();
  c->add_option("--robust", a.robust, "robust kernel on the loop closures: none, huber, cauchy or dcs")
      ->capture_default_str();
  c->add_option("--robust-param", o.robust_parameter, "Huber/Cauchy a or DCS φ, in 1e-150 … 1e150")
      ->capture_default_str();
  c->add_option("--threads", o.threads,
                "Ceres threads (the last bits of the result depend on it); 0 = all cores")
      ->capture_default_str();
  c->add_option("--max-iterations", o.max_iterations, "trust-region iterations")->capture_default_str();
}

// The engine's own check of option values (a validate() or from_string) run right after parsing, before any
// input is read: a value it refuses (std::invalid_argument) is a bad command line, exit 2, named by its
// option.
template <class Check>
void check_option(const char* option, Check&& check) {
  try {
    check();
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError(option, e.what());
  }
}

// The solver options of `keel solve` and `keel marginals`, each checked alone by its back end's own checks
// (app::MaximumLikelihood::validate, app::Certified::validate) so that a refusal names its option; the names
// of --init and --robust are read into the options here. --robust-param is checked as a parameter of the
// chosen kernel (of huber when --robust is none).
inline void check_solve_options(SolveArgs& a) {
  auto& given = a.likelihood.options;
  check_option("--init", [&] { given.initial_guess = app::initial_guess_from_name(a.init); });
  check_option("--robust", [&] { given.robust_kernel = pgo::robust_kernel_from_string(a.robust); });
  check_option("--preconditioner", [&] {
    a.certified.options.preconditioner = pgo::trust_region_preconditioner_from_string(a.preconditioner);
  });
  const auto alone = [](const char* option, auto set) {
    check_option(option, [&] {
      app::MaximumLikelihood m;
      set(m.options);
      m.validate();
    });
  };
  alone("--robust-param", [&](pgo::Options& o) {
    o.robust_kernel =
        given.robust_kernel == pgo::RobustKernel::none ? pgo::RobustKernel::huber : given.robust_kernel;
    o.robust_parameter = given.robust_parameter;
  });
  alone("--max-iterations", [&](pgo::Options& o) { o.max_iterations = given.max_iterations; });
  const auto& certified = a.certified.options;
  const auto alone_certified = [](const char* option, auto set) {
    check_option(option, [&] {
      app::Certified c;
      set(c.options);
      c.validate();
    });
  };
  alone_certified("--gap-tolerance",
                  [&](pgo::CertifiedOptions& o) { o.gap_tolerance = certified.gap_tolerance; });
  alone_certified("--max-rank", [&](pgo::CertifiedOptions& o) { o.max_rank = certified.max_rank; });
  alone_certified("--time-limit", [&](pgo::CertifiedOptions& o) { o.time_limit_s = certified.time_limit_s; });
  alone_certified("--staircase-stationarity", [&](pgo::CertifiedOptions& o) {
    o.staircase_stationarity = certified.staircase_stationarity;
  });
  alone_certified("--staircase-relative-decrease", [&](pgo::CertifiedOptions& o) {
    o.staircase_relative_decrease = certified.staircase_relative_decrease;
  });
}

inline void print_certified_summary(const std::string& file, const pgo::CertifiedSummary& s,
                                    double anisotropic) {
  const auto& c = s.certificate;
  fmt::print("solved       {} ({} poses, {} edges, SE({}))\n", file, s.poses, s.edges, s.dimension);
  fmt::print("problem      {}\n", s.problem);
  fmt::print("termination  {} ({})\n", pgo::to_string(s.termination), s.message);
  fmt::print("cost         F = {:.10g} (chordal initialization {:.10g}); anisotropic ½Σ rᵀΩr here {}\n",
             s.final_cost, s.initial_cost,
             std::isfinite(anisotropic)
                 ? fmt::format("{:.10g}", anisotropic)
                 : std::string("n/a (not every information matrix is positive definite)"));
  // Only what the proof behind the lower bound established is printed, rounded outward (the lower bound down,
  // the gap and the shift up); a failed attempt is printed as failed. The word "proven" is kept for a
  // certified estimate: when the estimate is not certified, a lower bound from a staircase point still holds
  // and is printed as a bound, without a word that could be read as the estimate's optimality.
  if (const auto p = app::proven_figures(c)) {
    const std::string figures = fmt::format(
        "relative gap (F − bound) / F ≤ {0} ((F − tr Λ) / F = {1} at the multipliers, plus the shift η·d·n / "
        "F "
        "chosen from the gap tolerance); λ_min(S) ≥ −{2} on the rotations with rounding margin {3:.3g} (S of "
        "order "
        "{4}{5})",
        core::format_upper(p->relative_gap, 3), core::format_upper(p->dual_gap, 3),
        core::format_upper(p->shift, 3), p->rounding_margin, c.size,
        p->proof_rank > s.dimension
            ? fmt::format(", multipliers of the rank-{} staircase point", p->proof_rank)
            : "");
    if (c.certified)
      fmt::print("certificate  F* ≥ {} proven (certified), {}\n", core::format_lower(p->lower_bound, 10),
                 figures);
    else
      fmt::print(
          "certificate  not certified: the estimate's optimality is not shown; the lower bound F* ≥ {} "
          "holds, "
          "{}\n",
          core::format_lower(p->lower_bound, 10), figures);
  } else {
    fmt::print("certificate  not certified: {}\n", c.message);  // "no lower bound: " and what failed
  }
  if (c.failed_shift > 0.0)
    fmt::print(
        "failed       S + η·D ⪰ 0 could not be shown for η up to {:.3g} at the rank-{} point ({} attempts; "
        "not a bound)\n",
        c.failed_shift, c.rank, c.attempts);
  if (s.bound_from_staircase)
    fmt::print("returned     the returned estimate's own test: {}\n",
               s.returned_point.proven ? s.returned_point.message : "failed, " + s.returned_point.message);
  // A staircase point whose S passed the test is optimal for the relaxation; the answer is certified only
  // when the rounded estimate is too (the exactness counterexample: its rank-4 point is, the rounded K4
  // estimate is not), so the per-rank word says the former.
  std::string stairs;
  for (const auto& r : s.staircase)
    stairs += fmt::format(
        "{}rank {} ({} it, F {:.8g}{})", stairs.empty() ? "" : " → ", r.rank, r.iterations, r.cost,
        r.certified ? ", optimal for the relaxation" : fmt::format(", λ ≈ {:.3g}", r.lambda_min_estimate));
  fmt::print("staircase    {}\n", stairs);
  fmt::print(
      "time         {:.3f} s (initialization {:.3f}, local {:.3f}, certificate {:.3f}, rounding {:.3f}); {} "
      "iterations ({} factorized, {} by CG on an earlier factor, {} Steihaug–Toint CG iterations in "
      "trust-region steps), CHOLMOD ordering {}\n",
      s.total_time_s, s.initialization_time_s, s.local_time_s, s.certificate_time_s, s.rounding_time_s,
      s.iterations, s.factorizations, s.cg_steps, s.tcg_iterations, s.ordering);
}

inline void check_solved(const pgo::Summary& s) {
  if (s.termination == pgo::Termination::failure)
    throw CommandFailed(fmt::format("the solve failed: {}", s.message));
}

inline void print_solve_summary(const std::string& file, const pgo::Summary& s, std::size_t poses) {
  fmt::print("solved       {} ({} poses)\n", file, poses);
  fmt::print("termination  {} after {} iterations ({})\n", pgo::to_string(s.termination), s.iterations,
             s.message);
  // Normalized χ² is undefined (NaN) when the graph has no redundancy: say so instead of printing "nan".
  fmt::print("cost         {:.10g} (initial {:.10g}); χ² {:.10g}; normalized χ² {}\n", s.final_cost,
             s.initial_cost, s.final_chi2,
             std::isfinite(s.normalized_chi2) ? fmt::format("{:.6g}", s.normalized_chi2)
                                              : std::string("n/a (no redundant measurements)"));
  fmt::print("time         {:.3f} s\n", s.total_time_s);
}

}  // namespace keel::cli
