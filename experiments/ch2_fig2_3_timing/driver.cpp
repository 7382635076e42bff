// Fig. 2.3 (§2.7.1.2): selection time against the number of measurements on simulated 1D worlds — thin driver over
// keel::eval::run_world1d_study. Wall times go through Results::timing (never diffed; the figure refers to them by
// name); deterministic quantities (mean selected sizes, heuristic match rates) are series.
import keel.core;
import keel.pcm;
import keel.sim;
import keel.eval;

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace core = keel::core;
namespace pcm = keel::pcm;
namespace sim = keel::sim;
namespace eval = keel::eval;

namespace {

// One curve of the figure: a selector (the combinatorial one in one of its two variants) and the largest m it runs at.
struct Curve {
  std::string name, label, color, marker;
  eval::Selector1D selector;
  eval::CombinatorialMethod combinatorial = eval::CombinatorialMethod::pruned;
  long long max_m = 0;  // 0: no cap
  bool runs_at(int m) const { return max_m == 0 || m <= max_m; }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  return core::experiment_main(argc, argv, [](core::Experiment& ex) {
    const auto& p = ex.params();
    eval::World1DStudyOptions base;
    sim::World1DOptions& w = base.world;
    w.x = p.number("x");
    w.sigma_inlier = p.number("sigma_inlier");
    w.outlier_mean_range = p.number("outlier_mean_range");
    w.outlier_sigma_min = p.number("outlier_sigma_min");
    w.outlier_sigma_max = p.number("outlier_sigma_max");
    const double inlier_fraction = p.number("inlier_fraction"), aliased_fraction = p.number("aliased_fraction");
    const auto sizes = p.numbers("measurements");
    const double pcm_p = p.number("pcm_p"), ransac_p = p.number("ransac_p");
    base.scgp.affinity_scale = p.number("scgp_affinity_scale");
    base.scgp.discretization = pcm::scgp_discretization_from_string(p.string("scgp_discretization"));
    base.scgp.min_eigen_ratio = p.number("scgp_min_eigen_ratio");
    const auto exhaustive_max = p.integer("combinatorial_exhaustive_max_measurements");
    const auto pruned_max = p.integer("combinatorial_pruned_max_measurements");
    base.worlds = p.count("worlds_per_size");
    ex.params_done();
    for (std::size_t k = 0; k < sizes.size(); ++k) {
      if (!(sizes[k] >= 1 && sizes[k] == std::floor(sizes[k])) || (k > 0 && sizes[k] <= sizes[k - 1])) {
        throw core::ConfigError(p.where("measurements") + ": sizes must be positive integers in increasing order");
      }
    }
    if (sizes.empty()) throw core::ConfigError(p.where("measurements") + ": must not be empty");
    if (exhaustive_max < 1 || exhaustive_max > eval::kCombinatorialExhaustiveMax) {
      throw core::ConfigError(p.where("combinatorial_exhaustive_max_measurements") + ": must be in [1, " +
                              std::to_string(eval::kCombinatorialExhaustiveMax) + "]");
    }
    if (pruned_max < 1 || pruned_max > eval::kCombinatorialPrunedMax) {
      throw core::ConfigError(p.where("combinatorial_pruned_max_measurements") + ": must be in [1, " +
                              std::to_string(eval::kCombinatorialPrunedMax) + "]");
    }
    base.pcm_gamma = pcm::consistency_threshold(pcm_p, 1);  // γ = χ²₁ quantile of 1 − p (dof 1)
    base.ransac_gamma = pcm::consistency_threshold(ransac_p, 1);
    base.seed = ex.seed();
    base.threads = ex.threads();

    using S = eval::Selector1D;
    const std::vector<Curve> curves = {
        {"combinatorial_exhaustive", "Combinatorial (all 2^m subsets)", "k", "x", S::combinatorial,
         eval::CombinatorialMethod::exhaustive, exhaustive_max},
        {"combinatorial_pruned", "Combinatorial (pruned subset search)", "0.5", "+", S::combinatorial,
         eval::CombinatorialMethod::pruned, pruned_max},
        {"pcm_exact", "PCM-Exact", "tab:blue", "o", S::pcm_exact},
        {"pcm_heuristic", "PCM-Heuristic", "tab:green", "s", S::pcm_heuristic},
        {"scgp", "SCGP", "tab:orange", "^", S::scgp},
        {"ransac", "RANSAC", "tab:red", "v", S::ransac},
    };

    std::size_t total = 0;
    for (double m : sizes) total += base.worlds * (1 + (m <= pruned_max ? 1 : 0));
    core::Progress progress(ex.id(), total);
    auto& r = ex.results();
    std::vector<std::vector<double>> xs(curves.size()), size_mean(curves.size());
    std::vector<std::vector<std::string>> timing_names(curves.size());
    std::vector<double> heuristic_match;
    long long comb_checked = 0, comb_mismatch = 0;
    for (std::size_t k = 0; k < sizes.size(); ++k) {
      const int m = static_cast<int>(sizes[k]);
      eval::World1DStudyOptions o = base;
      try {
        o.world = sim::world1d_options_with_total(w, m, inlier_fraction, aliased_fraction);
      } catch (const std::invalid_argument& e) {
        throw core::ConfigError(p.where("inlier_fraction") + ": " + e.what());
      }
      o.stream_base = static_cast<std::uint64_t>(k) << 32;  // independent worlds per size, the same for every curve
      // First pass: PCM, SCGP, RANSAC and the exhaustive enumeration; second pass (same worlds): the pruned search.
      o.selectors = {S::pcm_exact, S::pcm_heuristic, S::scgp, S::ransac};
      o.combinatorial = eval::CombinatorialMethod::exhaustive;
      if (curves[0].runs_at(m)) o.selectors.push_back(S::combinatorial);
      const eval::World1DStudy main = keel::eval::run_world1d_study(o, &progress);
      eval::World1DStudy pruned;
      if (curves[1].runs_at(m)) {
        o.selectors = {S::combinatorial};
        o.combinatorial = eval::CombinatorialMethod::pruned;
        pruned = keel::eval::run_world1d_study(o, &progress);
      }

      char tag[32];
      std::snprintf(tag, sizeof tag, "m%04d", m);
      const auto& exact = main.of(S::pcm_exact);
      for (std::size_t c = 0; c < curves.size(); ++c) {
        if (!curves[c].runs_at(m)) continue;
        const auto& out = (c == 1 ? pruned : main).of(curves[c].selector);
        std::vector<double> t;
        double n_sel = 0;
        for (std::size_t i = 0; i < out.size(); ++i) {
          t.push_back(out[i].time_s);
          n_sel += out[i].size;
          if (curves[c].selector == S::combinatorial) {
            ++comb_checked;
            comb_mismatch += out[i].size != exact[i].size;
          }
        }
        const std::string name = "time." + curves[c].name + "." + tag;
        r.timing(name, median(t));  // median wall time of one selection (s): robust to preemption
        timing_names[c].push_back(name);
        xs[c].push_back(m);
        size_mean[c].push_back(n_sel / out.size());
      }
      const auto& heur = main.of(S::pcm_heuristic);
      double match = 0;
      for (std::size_t i = 0; i < exact.size(); ++i) match += heur[i].size == exact[i].size;
      heuristic_match.push_back(match / exact.size());
    }
    progress.finish();

    r.series("measurements", sizes);
    for (std::size_t c = 0; c < 2; ++c) r.series("measurements." + curves[c].name, xs[c]);
    for (std::size_t c = 0; c < curves.size(); ++c) r.series("size.mean." + curves[c].name, size_mean[c]);
    r.series("match_rate.pcm_heuristic", heuristic_match);
    r.metric("worlds_per_size", static_cast<double>(base.worlds));
    r.metric("gamma.pcm", base.pcm_gamma);
    r.metric("gamma.ransac", base.ransac_gamma);

    char detail[200];
    std::snprintf(detail, sizeof detail, "%lld combinatorial runs (both variants), %lld with a different size",
                  comb_checked, comb_mismatch);
    r.check("PCM-Exact returns a set of the combinatorial maximum's size wherever the combinatorial search ran",
            comb_checked > 0 && comb_mismatch == 0, detail);

    // Fig. 2.3: median time per selection and, beside it, the mean selected size (both log-log).
    core::Figure f;
    f.file = ex.id() + ".png";
    f.title = "Fig. 2.3: selection time vs number of measurements (" + std::to_string(base.worlds) +
              " worlds per size; Q not timed; machine-dependent)";
    f.width = 13.0;
    f.height = 5.0;
    core::Panel tp, sp;
    tp.xlabel = sp.xlabel = "number of measurements m";
    tp.ylabel = "median wall time per selection (s)";
    sp.ylabel = "mean number of selected measurements";
    tp.xscale = tp.yscale = sp.xscale = sp.yscale = "log";
    tp.legend = "upper left";
    sp.legend = "none";
    for (std::size_t c = 0; c < curves.size(); ++c) {
      core::Layer l = core::line_layer(xs[c], {}, curves[c].label, curves[c].color, curves[c].marker);
      l.y_timings = timing_names[c];
      tp.layers.push_back(l);
      sp.layers.push_back(core::line_layer(xs[c], size_mean[c], curves[c].label, curves[c].color, curves[c].marker));
    }
    f.panels = {tp, sp};
    r.figure(f);
  });
}
