// Fig. 2.4 (§2.7.2.1): TPR, FPR and normalized χ² of PCM-Exact, PCM-Heuristic and RANSAC against the
// consistency threshold on the City10000 two-robot data sets of Table 2.1 — thin driver over keel.eval's
// two-robot study. Beyond the thesis: the same sweep with the poses composed as independent.
import keel.core;
import keel.repro;
import keel.pcm;
import keel.merge;
import keel.eval;

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ch2_fig2_4_threshold_sweep/report.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace pcm = keel::pcm;
namespace eval = keel::eval;
using namespace keel::experiments::fig2_4;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    const auto copt = eval::read_candidate_options(p);
    const std::size_t datasets = p.count("datasets");
    const std::vector<double> p_values = p.numbers("p_values");
    const double claim_p_max = p.number("claim_p_max"), claim_tpr_spread = p.number("claim_tpr_spread"),
                 claim_fpr_max = p.number("claim_fpr_max");
    std::vector<Family> families;
    const auto family_table = p.table("family");
    for (const auto& name : p.strings("families")) {
      const auto t = family_table.table(name);
      families.push_back({name, t.string("label"), t.string("color"),
                          t.parse("kind", keel::merge::merge_method_kind_from_string),
                          t.parse_or("composition", pcm::composition_from_string, pcm::Composition::joint)});
      if (families.back().kind == eval::MergeMethodKind::no_outliers ||
          families.back().kind == eval::MergeMethodKind::dcs ||
          families.back().kind == eval::MergeMethodKind::scgp)
        throw core::ConfigError(t.where("kind") +
                                ": a threshold sweep needs pcm_exact, pcm_heuristic or ransac");
    }
    const auto regimes = eval::read_regimes(p, "regimes", "regime");
    auto t0 = core::Clock::now();
    const auto base = eval::load_scenario_2d(p);
    ex.params_done();
    for (std::size_t k = 0; k < p_values.size(); ++k)
      if (!(p_values[k] > 0.0 && p_values[k] < 1.0) || (k > 0 && p_values[k] <= p_values[k - 1]))
        throw core::ConfigError(p.where("p_values") + ": must be increasing and inside (0, 1)");
    const auto family = [&](const char* name) {
      for (std::size_t f = 0; f < families.size(); ++f)
        if (families[f].name == name) return f;
      throw core::ConfigError(p.where("families") + ": the claims need pcm_exact, pcm_heuristic and ransac");
    };
    const std::size_t fe = family("pcm_exact"), fh = family("pcm_heuristic"), fr = family("ransac");

    // One method per (family, p); NO-OUT first (the χ² reference of the figure).
    std::vector<eval::MergeMethod> specs = {
        eval::MergeMethod::make("no_out", eval::MergeMethodKind::no_outliers)};
    for (const auto& f : families)
      for (double q : p_values) {
        specs.push_back(eval::MergeMethod::make(fmt::format("{}@{:g}", f.name, q), f.kind, q, f.composition));
        specs.back().validate();
      }
    const auto spec_index = [&](std::size_t f, std::size_t k) { return 1 + f * p_values.size() + k; };

    auto& r = ex.results();
    r.timing("read_and_split", core::seconds_since(t0));
    r.metric("scenario.pool", static_cast<double>(base.pool.size()));
    r.metric("datasets", static_cast<double>(datasets));
    r.metric("candidates", copt.total());
    r.series("p", p_values);
    repro::Figure fig;
    fig.file = ex.id() + ".png";
    fig.title = fmt::format(
        "Fig. 2.4: City10000 two-robot data sets ({} sets) against the tail probability p of "
        "γ(p) = F⁻¹χ²(3)(1 − p); larger p = stricter",
        datasets);
    fig.cols = 3;
    fig.rows = static_cast<int>(regimes.size());
    fig.width = 16.5;
    fig.height = 4.6 * fig.rows;

    for (const auto& g : regimes) {
      const auto scenario = eval::apply_regime(base, g);
      t0 = core::Clock::now();
      const auto local = eval::solve_local_pair(scenario);
      r.timing(g.name + ".local_solves", core::seconds_since(t0));
      t0 = core::Clock::now();
      core::Progress progress(ex.id() + " " + g.name, datasets);
      const auto runs = eval::run_merge_datasets(scenario, local, eval::apply_regime(copt, g), specs,
                                                 ex.seed(), datasets, ex.threads(), datasets, &progress);
      progress.finish();
      r.timing(g.name + ".datasets", core::seconds_since(t0));

      // Pooled TPR/FPR, mean normalized χ² and mean selection size per (family, p).
      const double chi2_no_out = eval::summarize_method(runs, 0).mean("chi2");
      r.metric(g.name + ".no_out.chi2", chi2_no_out);
      std::vector<Curve> curves(families.size());
      for (std::size_t f = 0; f < families.size(); ++f) {
        for (std::size_t k = 0; k < p_values.size(); ++k) {
          const auto s = eval::summarize_method(runs, spec_index(f, k));
          curves[f].tpr.push_back(s.pooled.tpr());
          curves[f].fpr.push_back(s.pooled.fpr());
          curves[f].chi2.push_back(s.mean("chi2"));
          curves[f].selected.push_back(s.mean("selected"));
          r.timing(g.name + "." + specs[spec_index(f, k)].name + ".time_s", s.mean("selection_time_s"));
        }
        const auto n = g.name + "." + families[f].name;
        r.series(n + ".tpr", curves[f].tpr);
        r.series(n + ".fpr", curves[f].fpr);
        r.series(n + ".chi2", curves[f].chi2);
        r.series(n + ".selected", curves[f].selected);
        for (std::size_t k = 0; k < p_values.size(); ++k)
          if (p_values[k] == 0.11) {
            r.metric(n + ".tpr@0.11", curves[f].tpr[k]);
            r.metric(n + ".fpr@0.11", curves[f].fpr[k]);
          }
      }

      check_fig2_4(r, p_values, curves, {fe, fh, fr}, chi2_no_out, claim_p_max, claim_tpr_spread,
                   claim_fpr_max, " [" + g.label + "]");
      add_fig2_4_row(fig, p_values, curves, families, chi2_no_out, g.label);
    }
    r.figure(fig);
  });
}
