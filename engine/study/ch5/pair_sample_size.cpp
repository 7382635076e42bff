#include "study/ch5/pair_sample_size.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "core/timing.hpp"
#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "datasets/manifest.hpp"
#include "graph/io.hpp"
#include "pgo/optimize.hpp"

namespace keel::study::ch5 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

namespace {

// Least-squares line through (log x, log y): y = a·x^b. Returns {log a, b}.
std::pair<double, double> power_law(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double lx = std::log(x[k]), ly = std::log(y[k]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  const double b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return {(sy - b * sx) / n, b};
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// Tables 5.1–5.2 against M

PairSampleSize::Options PairSampleSize::Options::read(const core::ConfigTable& p) {
  Options o;
  o.pairs = PairsSetup::read(p);
  o.samples = p.numbers("samples");
  o.match_cov_error_joint = p.number("match_cov_error_joint");
  o.match_norm_cov_error_lie = p.number("match_norm_cov_error_lie");
  if (o.samples.size() < 2)
    throw core::ConfigError(fmt::format("{}: need at least two sample sizes", p.where("samples")));
  for (std::size_t k = 0; k < o.samples.size(); ++k) {
    const double m = o.samples[k];
    if (!(m >= 2.0 && m <= 1e12 && m == std::floor(m)) || (k > 0 && !(m > o.samples[k - 1])))
      throw core::ConfigError(
          fmt::format("{}: sample sizes must be whole numbers >= 2 in ascending order (got {:g})",
                      p.where("samples"), m));
  }
  return o;
}

PairSampleSize::Outcome PairSampleSize::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  out.rows = {{repro::path("cov_error").under("joint"), "Table 5.1, joint", &PairRecord::error_joint, {}, {}},
              {repro::path("cov_error").under("independent"),
               "Table 5.1, correlation ignored",
               &PairRecord::error_independent,
               {},
               {}},
              {repro::path("norm_cov_error").under("lie"),
               "Table 5.2, proposed",
               &PairRecord::normalized_error_lie,
               {},
               {}},
              {repro::path("norm_cov_error").under("ssc"),
               "Table 5.2, SSC",
               &PairRecord::normalized_error_ssc,
               {},
               {}},
              {repro::path("norm_cov_error").under("mc_floor"),
               "Table 5.2, sampling floor",
               &PairRecord::normalized_mc_floor,
               {},
               {}}};
  out.solved = solve_pairs(o.pairs, context);
  // One pass: each pair's stream drawn once, up to the largest M, its record taken at every M on the way (the
  // same streams for every M: pair k draws from stream k, and a run at M alone draws its first M samples).
  std::vector<std::size_t> sizes;
  for (const double m : o.samples) sizes.push_back(static_cast<std::size_t>(m));
  core::Progress progress = context.progress(out.solved.pairs.size());
  const auto t0 = core::Clock::now();
  const auto records = simulate_pairs_2d_sizes(out.solved.poses, out.solved.pairs, out.solved.covariances,
                                               sizes, context, &progress);
  out.monte_carlo_time_s = core::seconds_since(t0);
  for (const auto& at_m : records)
    for (auto& row : out.rows) {
      const auto st = pair_statistics(at_m, row.field);
      row.mean.push_back(st.mean), row.std.push_back(st.std);
    }
  progress.finish();
  return out;
}

void PairSampleSize::record(Results& r, const Outcome& out) {
  const auto& ms = out.options.samples;
  record_solved(r, out.solved);
  r.timing("monte_carlo", out.monte_carlo_time_s);
  for (std::size_t k = 0; k < ms.size(); ++k) {
    for (const auto& row : out.rows) {
      r.under(fmt::format("m{:g}", ms[k])).under(row.key).metric("mean", row.mean[k]);
      r.under(fmt::format("m{:g}", ms[k])).under(row.key).metric("std", row.std[k]);
    }
  }
  r.series("M", ms);
  for (const auto& row : out.rows) {
    r.at(row.key).series("mean", row.mean);
    r.at(row.key).series("std", row.std);
  }
  // The power laws of the two errors the thesis's means are compared with, and the M at which each fit meets
  // the thesis's mean (extrapolated when outside the sweep).
  auto fit = [&](const Row& row, double target) {
    const auto [log_a, b] = power_law(ms, row.mean);
    r.at(row.key).metric("exponent", b);
    r.at(row.key).metric("m_at_thesis", std::exp((std::log(target) - log_a) / b));
    return std::pair{log_a, b};
  };
  const auto fj = fit(out.rows[0], out.options.match_cov_error_joint);
  const auto fl = fit(out.rows[2], out.options.match_norm_cov_error_lie);
  r.check("the joint error falls with M (a Monte-Carlo-limited metric): fitted exponent below zero",
          fj.second < 0, fmt::format("mean ε ∝ M^{:.3f}", fj.second));
  r.check("the proposed method's normalized error falls with M: fitted exponent below zero", fl.second < 0,
          fmt::format("mean normalized ε ∝ M^{:.3f}", fl.second));
}

std::vector<Figure> PairSampleSize::figures(const Outcome& out) {
  const auto& ms = out.options.samples;
  const auto& rows = out.rows;
  Figure f;
  f.file = ".png";
  f.title = "Tables 5.1–5.2: mean covariance errors against the Monte-Carlo sample size M";
  f.width = 13.0;
  f.height = 5.5;
  Panel a, b;
  a.title = "Table 5.1: ε (eq. 5.56)";
  b.title = "Table 5.2: normalized ε";
  for (auto* p : {&a, &b}) {
    p->xlabel = "Monte-Carlo samples per pair M";
    p->ylabel = "mean over pairs";
    p->xscale = p->yscale = "log";
  }
  a.layers.push_back(repro::line_layer(ms, rows[0].mean, "joint (ours)", "tab:green", "o"));
  a.layers.push_back(repro::line_layer(ms, rows[1].mean, "correlation ignored (ours)", "tab:red", "s"));
  a.layers.push_back(repro::hline_layer(out.options.match_cov_error_joint, "thesis, joint", "tab:green"));
  b.layers.push_back(repro::line_layer(ms, rows[2].mean, "proposed (ours)", "tab:green", "o"));
  b.layers.push_back(repro::line_layer(ms, rows[3].mean, "SSC (ours)", "tab:red", "s"));
  b.layers.push_back(repro::line_layer(ms, rows[4].mean, "sampling floor", "0.4", "x"));
  b.layers.push_back(
      repro::hline_layer(out.options.match_norm_cov_error_lie, "thesis, proposed", "tab:green"));
  f.panels = {a, b};
  return {f};
}

}  // namespace keel::study::ch5
