// Fig. 2.2 (§2.7.1.1): PCM-Exact, PCM-Heuristic, SCGP and RANSAC against the combinatorial maximum pairwise
// consistent set (eq. 2.5) on simulated 1D worlds (§2.7.1) — thin driver over keel::eval::run_world1d_study.
import keel.core;
import keel.pcm;
import keel.eval;

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace core = keel::core;
namespace pcm = keel::pcm;
namespace eval = keel::eval;

namespace {

// Outline of a histogram with unit-width bins centred on `bins` (a step curve for a line layer).
core::Layer step_layer(const std::vector<double>& bins, const std::vector<double>& freq, const std::string& label,
                       const std::string& color) {
  std::vector<double> x, y;
  for (std::size_t b = 0; b < bins.size(); ++b) {
    x.insert(x.end(), {bins[b] - 0.5, bins[b] - 0.5, bins[b] + 0.5, bins[b] + 0.5});
    y.insert(y.end(), {0.0, freq[b], freq[b], 0.0});
  }
  return core::line_layer(std::move(x), std::move(y), label, color);
}

}  // namespace

int main(int argc, char** argv) {
  return core::experiment_main(argc, argv, [](core::Experiment& ex) {
    const auto& p = ex.params();
    eval::World1DStudyOptions o;
    o.world.x = p.number("x");
    o.world.sigma_inlier = p.number("sigma_inlier");
    o.world.inliers_min = static_cast<int>(p.integer("inliers_min"));
    o.world.inliers_max = static_cast<int>(p.integer("inliers_max"));
    o.world.aliased_min = static_cast<int>(p.integer("aliased_min"));
    o.world.aliased_max = static_cast<int>(p.integer("aliased_max"));
    o.world.random_min = static_cast<int>(p.integer("random_min"));
    o.world.random_max = static_cast<int>(p.integer("random_max"));
    o.world.outlier_mean_range = p.number("outlier_mean_range");
    o.world.outlier_sigma_min = p.number("outlier_sigma_min");
    o.world.outlier_sigma_max = p.number("outlier_sigma_max");
    const double pcm_p = p.number("pcm_p"), ransac_p = p.number("ransac_p");
    o.scgp.affinity_scale = p.number("scgp_affinity_scale");
    o.scgp.discretization = pcm::scgp_discretization_from_string(p.string("scgp_discretization"));
    o.scgp.min_eigen_ratio = p.number("scgp_min_eigen_ratio");
    o.combinatorial = eval::combinatorial_method_from_string(p.string("combinatorial"));
    o.worlds = p.count("worlds");
    ex.params_done();
    o.pcm_gamma = pcm::consistency_threshold(pcm_p, 1);  // γ = χ²₁ quantile of 1 − p (dof 1: the 1D world)
    o.ransac_gamma = pcm::consistency_threshold(ransac_p, 1);
    o.seed = ex.seed();
    o.threads = ex.threads();
    try {
      o.validate();
    } catch (const std::invalid_argument& e) {
      throw core::ConfigError(p.file() + ": " + e.what());
    }

    core::Progress progress(ex.id(), o.worlds);
    const eval::World1DStudy study = keel::eval::run_world1d_study(o, &progress);
    progress.finish();

    const auto& comb = study.of(eval::Selector1D::combinatorial);
    const std::vector<eval::Selector1D> methods = {eval::Selector1D::pcm_exact, eval::Selector1D::pcm_heuristic,
                                                  eval::Selector1D::scgp, eval::Selector1D::ransac};
    const std::size_t n = o.worlds;
    auto& r = ex.results();

    // Histogram ranges shared by all methods (size difference to the maximum; inconsistent pairs).
    int dmin = 0, dmax = 0, imax = 0;
    for (auto m : methods) {
      const auto& out = study.of(m);
      for (std::size_t i = 0; i < n; ++i) {
        dmin = std::min(dmin, out[i].size - comb[i].size);
        dmax = std::max(dmax, out[i].size - comb[i].size);
        imax = std::max(imax, out[i].inconsistent_pairs);
      }
    }
    std::vector<double> dbins, ibins;
    for (int d = dmin; d <= dmax; ++d) dbins.push_back(d);
    for (int k = 0; k <= imax; ++k) ibins.push_back(k);
    r.series("hist.size_diff.bins", dbins);
    r.series("hist.inconsistent_pairs.bins", ibins);

    double m_sum = 0, max_sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      m_sum += study.measurements[i];
      max_sum += comb[i].size;
    }
    r.metric("worlds", static_cast<double>(n));
    r.metric("measurements.mean", m_sum / n);
    r.metric("max_consistent_set.mean", max_sum / n);
    r.metric("gamma.pcm", o.pcm_gamma);
    r.metric("gamma.ransac", o.ransac_gamma);

    struct Row {
      std::string name;
      double match = 0, more = 0, fewer = 0, incons_mean = 0, incons_rate = 0, time_mean = 0;
      long long incons_total = 0;
      std::vector<double> dhist, ihist;
    };
    std::vector<Row> rows;
    int heuristic_above_exact = 0;
    const auto& exact = study.of(eval::Selector1D::pcm_exact);
    const auto& heur = study.of(eval::Selector1D::pcm_heuristic);
    for (std::size_t i = 0; i < n; ++i) heuristic_above_exact += heur[i].size > exact[i].size;
    double comb_time = 0;
    for (std::size_t i = 0; i < n; ++i) comb_time += comb[i].time_s;
    r.timing("mean_time.combinatorial", comb_time / n);

    for (auto m : methods) {
      const auto& out = study.of(m);
      Row row;
      row.name = eval::to_string(m);
      row.dhist.assign(dbins.size(), 0.0);
      row.ihist.assign(ibins.size(), 0.0);
      for (std::size_t i = 0; i < n; ++i) {
        const int d = out[i].size - comb[i].size;
        row.match += d == 0;
        row.more += d > 0;
        row.fewer += d < 0;
        row.incons_total += out[i].inconsistent_pairs;
        row.incons_rate += out[i].inconsistent_pairs > 0;
        row.time_mean += out[i].time_s;
        row.dhist[d - dmin] += 1.0;
        row.ihist[out[i].inconsistent_pairs] += 1.0;
      }
      for (auto& c : row.dhist) c /= n;  // fractions of worlds
      for (auto& c : row.ihist) c /= n;
      row.match /= n;
      row.more /= n;
      row.fewer /= n;
      row.incons_mean = static_cast<double>(row.incons_total) / n;
      row.incons_rate /= n;
      row.time_mean /= n;
      r.metric("match_rate." + row.name, row.match);
      r.metric("larger_rate." + row.name, row.more);
      r.metric("smaller_rate." + row.name, row.fewer);
      r.metric("inconsistent_pairs.mean." + row.name, row.incons_mean);
      r.metric("inconsistent_rate." + row.name, row.incons_rate);
      r.series("hist.size_diff." + row.name, row.dhist);
      r.series("hist.inconsistent_pairs." + row.name, row.ihist);
      r.timing("mean_time." + row.name, row.time_mean);
      rows.push_back(std::move(row));
    }
    const Row &rx = rows[0], &rh = rows[1], &rs = rows[2], &rr = rows[3];
    // Plot range of the inconsistent-pair histograms: what covers 99.9 % of the worlds of every method (the series
    // keep the whole range).
    int ishow = 1;
    for (const auto& row : rows) {
      double cum = 0;
      for (std::size_t b = 0; b < row.ihist.size(); ++b) {
        cum += row.ihist[b];
        if (cum >= 0.999) {
          ishow = std::max(ishow, static_cast<int>(b) + 1);
          break;
        }
      }
    }

    char detail[320];
    std::snprintf(detail, sizeof detail, "PCM-Exact has the combinatorial maximum's size in %.0f of %zu worlds",
                  rx.match * n, n);
    r.check("PCM-Exact returns a set of the combinatorial maximum's size in every world (eq. 2.5)", rx.match == 1.0,
            detail);
    std::snprintf(detail, sizeof detail,
                  "inconsistent pairs in PCM selections: exact %lld, heuristic %lld (%zu worlds)", rx.incons_total,
                  rh.incons_total, n);
    r.check("PCM selections are always pairwise consistent (0 inconsistent pairs, eq. 2.3)",
            rx.incons_total == 0 && rh.incons_total == 0, detail);
    std::snprintf(detail, sizeof detail,
                  "heuristic larger than exact in %d worlds; heuristic matches the maximum in %.4f of worlds",
                  heuristic_above_exact, rh.match);
    r.check("PCM-Heuristic never returns more than PCM-Exact", heuristic_above_exact == 0 && rh.more == 0.0, detail);
    std::snprintf(detail, sizeof detail,
                  "worlds with >= 1 inconsistent pair: SCGP %.4f, RANSAC %.4f; mean pairs: SCGP %.3f, RANSAC %.3f",
                  rs.incons_rate, rr.incons_rate, rs.incons_mean, rr.incons_mean);
    r.check("SCGP and RANSAC do not enforce pairwise consistency (some of their selections hold inconsistent pairs)",
            rs.incons_rate > 0.0 && rr.incons_rate > 0.0, detail);
    std::snprintf(detail, sizeof detail, "RANSAC larger than the maximum in %.4f of worlds, smaller in %.4f", rr.more,
                  rr.fewer);
    r.check("RANSAC sometimes returns more and sometimes fewer measurements than the combinatorial maximum",
            rr.more > 0.0 && rr.fewer > 0.0, detail);

    // Fig. 2.2: first row, size returned − maximum size; second row, inconsistent pairs of the returned set.
    const char* titles[] = {"PCM-Exact", "PCM-Heuristic", "SCGP", "RANSAC"};
    const char* colors[] = {"tab:blue", "tab:green", "tab:orange", "tab:red"};
    core::Figure f;
    f.file = ex.id() + ".png";
    f.title = "Fig. 2.2: selections on " + std::to_string(n) + " 1D worlds vs the combinatorial maximum (eq. 2.5)";
    f.rows = 2;
    f.cols = 4;
    f.width = 16.0;
    f.height = 7.5;
    for (int row = 0; row < 2; ++row) {
      for (std::size_t k = 0; k < rows.size(); ++k) {
        core::Panel panel;
        panel.title = titles[k];
        panel.xlabel = row == 0 ? "size returned − maximum size" : "inconsistent pairs returned (99.9 % of worlds)";
        panel.ylabel = "fraction of worlds";
        panel.ylim = std::make_pair(0.0, 1.05);
        if (row == 1) panel.xlim = std::make_pair(-1.0, ishow + 0.5);
        panel.legend = "none";
        panel.layers.push_back(row == 0 ? step_layer(dbins, rows[k].dhist, "", colors[k])
                                        : step_layer(ibins, rows[k].ihist, "", colors[k]));
        f.panels.push_back(panel);
      }
    }
    r.figure(f);
  });
}
