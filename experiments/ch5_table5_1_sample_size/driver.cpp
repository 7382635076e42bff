// Tables 5.1 and 5.2, §5.9.2: how the mean covariance errors depend on the Monte-Carlo sample size M of the
// reference covariance (eqs. 5.57–5.59). The same pairs and marginals as ch5_table5_1_correlation; the pair
// study is rerun for each M, and a power law mean(M) = a·M^b fitted in log–log gives the M at which ours
// would meet the thesis's published means — thin driver over keel.graph / keel.pgo / keel.cov / keel.lie.
import keel.core;
import keel.repro;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.cov;
import keel.datasets;

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "common/solved_pairs.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace lie = keel::lie;

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

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    std::vector<double> ms;
    double match_joint = 0, match_lie = 0;
    // One row per M: the Table 5.1 and 5.2 means and standard deviations, and the sampling floor.
    struct Row {
      std::string key, label;
      double lie::PairRecord::* field;
      std::vector<double> mean, std;
    };
    std::vector<Row> rows{
        {"cov_error.joint", "Table 5.1, joint", &lie::PairRecord::error_joint, {}, {}},
        {"cov_error.independent",
         "Table 5.1, correlation ignored",
         &lie::PairRecord::error_independent,
         {},
         {}},
        {"norm_cov_error.lie", "Table 5.2, proposed", &lie::PairRecord::normalized_error_lie, {}, {}},
        {"norm_cov_error.ssc", "Table 5.2, SSC", &lie::PairRecord::normalized_error_ssc, {}, {}},
        {"norm_cov_error.mc_floor",
         "Table 5.2, sampling floor",
         &lie::PairRecord::normalized_mc_floor,
         {},
         {}}};
    keel::experiments::solve_pairs(
        ex,
        [&](const core::ConfigTable& p) {
          ms = p.numbers("samples");
          match_joint = p.number("match_cov_error_joint");
          match_lie = p.number("match_norm_cov_error_lie");
          if (ms.size() < 2)
            throw core::ConfigError(fmt::format("{}: need at least two sample sizes", p.where("samples")));
        },
        [&](keel::experiments::SolvedPairs& out, const auto& covs) {
          core::Progress progress(ex.id(), out.pairs.size() * ms.size());
          for (double m : ms) {
            const auto t0 = std::chrono::steady_clock::now();
            lie::PairStudySetup setup;
            setup.samples = static_cast<std::size_t>(m);
            setup.seed = ex.seed();  // the same streams for every M: pair k draws from Rng::stream(seed, k)
            setup.threads = ex.threads();
            out.records = lie::run_pair_study_2d(out.poses, out.pairs, covs, setup, &progress);
            ex.results().timing(fmt::format("monte_carlo.m{:g}", m), keel::experiments::seconds_since(t0));
            for (auto& row : rows) {
              const auto st = lie::pair_statistics(out.records, row.field);
              row.mean.push_back(st.mean), row.std.push_back(st.std);
              ex.results().metric(fmt::format("m{:g}.{}.mean", m, row.key), st.mean);
              ex.results().metric(fmt::format("m{:g}.{}.std", m, row.key), st.std);
            }
          }
          progress.finish();
        });
    auto& r = ex.results();
    r.series("M", ms);
    for (const auto& row : rows) {
      r.series(row.key + ".mean", row.mean);
      r.series(row.key + ".std", row.std);
    }
    // The power laws of the two errors the thesis's means are compared with, and the M at which each fit
    // meets the thesis's mean (extrapolated when outside the sweep).
    auto fit = [&](const Row& row, double target, const std::string& name) {
      const auto [log_a, b] = power_law(ms, row.mean);
      r.metric(name + ".exponent", b);
      r.metric(name + ".m_at_thesis", std::exp((std::log(target) - log_a) / b));
      return std::pair{log_a, b};
    };
    const auto fj = fit(rows[0], match_joint, "cov_error.joint");
    const auto fl = fit(rows[2], match_lie, "norm_cov_error.lie");
    r.check("the joint error falls with M (a Monte-Carlo-limited metric): fitted exponent below zero",
            fj.second < 0, fmt::format("mean ε ∝ M^{:.3f}", fj.second));
    r.check("the proposed method's normalized error falls with M: fitted exponent below zero", fl.second < 0,
            fmt::format("mean normalized ε ∝ M^{:.3f}", fl.second));

    repro::Figure f;
    f.file = fmt::format("{}.png", ex.id());
    f.title = "Tables 5.1–5.2: mean covariance errors against the Monte-Carlo sample size M";
    f.width = 13.0;
    f.height = 5.5;
    repro::Panel a, b;
    a.title = "Table 5.1: ε (eq. 5.56)";
    b.title = "Table 5.2: normalized ε";
    for (auto* p : {&a, &b}) {
      p->xlabel = "Monte-Carlo samples per pair M";
      p->ylabel = "mean over pairs";
      p->xscale = p->yscale = "log";
    }
    a.layers.push_back(repro::line_layer(ms, rows[0].mean, "joint (ours)", "tab:green", "o"));
    a.layers.push_back(repro::line_layer(ms, rows[1].mean, "correlation ignored (ours)", "tab:red", "s"));
    a.layers.push_back(repro::hline_layer(match_joint, "thesis, joint", "tab:green"));
    b.layers.push_back(repro::line_layer(ms, rows[2].mean, "proposed (ours)", "tab:green", "o"));
    b.layers.push_back(repro::line_layer(ms, rows[3].mean, "SSC (ours)", "tab:red", "s"));
    b.layers.push_back(repro::line_layer(ms, rows[4].mean, "sampling floor", "0.4", "x"));
    b.layers.push_back(repro::hline_layer(match_lie, "thesis, proposed", "tab:green"));
    f.panels = {a, b};
    r.figure(f);
  });
}
