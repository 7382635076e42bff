#include "study/ch2/threshold_sweep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "core/parallel.hpp"
#include "core/statistics.hpp"
#include "core/timing.hpp"
#include "study/ch2/table_common.hpp"

namespace keel::study::ch2 {

using repro::Figure;
using repro::Layer;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Fig. 2.4

ThresholdSweep::Options ThresholdSweep::Options::read(const core::ConfigTable& p) {
  Options o;
  o.candidates = read_candidate_options(p);
  o.datasets = p.count("datasets");
  o.p_values = p.numbers("p_values");
  o.claim_p_max = p.number("claim_p_max");
  o.claim_tpr_spread = p.number("claim_tpr_spread");
  o.claim_fpr_max = p.number("claim_fpr_max");
  const auto family_table = p.table("family");
  for (const auto& name : p.strings("families")) {
    const auto t = family_table.table(name);
    o.families.push_back({name, t.string("label"), t.string("color"),
                          t.parse("kind", merge::merge_method_kind_from_string),
                          t.parse_or("composition", pcm::composition_from_string, pcm::Composition::joint)});
    const auto kind = o.families.back().kind;
    if (kind == merge::MergeMethodKind::no_outliers || kind == merge::MergeMethodKind::dcs ||
        kind == merge::MergeMethodKind::scgp)
      throw core::ConfigError(t.where("kind") +
                              ": a threshold sweep needs pcm_exact, pcm_heuristic or ransac");
  }
  o.regimes = read_regimes(p, "regimes", "regime");
  o.scenario = ScenarioFiles::read(p);
  for (std::size_t k = 0; k < o.p_values.size(); ++k)
    if (!(o.p_values[k] > 0.0 && o.p_values[k] < 1.0) || (k > 0 && o.p_values[k] <= o.p_values[k - 1]))
      throw core::ConfigError(p.where("p_values") + ": must be increasing and inside (0, 1)");
  const auto family = [&](const char* name) {
    for (std::size_t f = 0; f < o.families.size(); ++f)
      if (o.families[f].name == name) return f;
    throw core::ConfigError(p.where("families") + ": the claims need pcm_exact, pcm_heuristic and ransac");
  };
  o.fe = family("pcm_exact"), o.fh = family("pcm_heuristic"), o.fr = family("ransac");
  return o;
}

ThresholdSweep::Outcome ThresholdSweep::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  auto t0 = core::Clock::now();
  const auto base = load_scenario_2d(o.scenario);
  out.read_time_s = core::seconds_since(t0);
  out.pool = base.pool.size();
  // One method per (family, p); NO-OUT first (the χ² reference of the figure).
  std::vector<merge::MergeMethod> specs = {
      merge::MergeMethod::make("no_out", merge::MergeMethodKind::no_outliers)};
  for (const auto& f : o.families)
    for (double q : o.p_values) {
      specs.push_back(merge::MergeMethod::make(fmt::format("{}@{:g}", f.name, q), f.kind, q, f.composition));
      specs.back().validate();
    }
  const auto spec_index = [&](std::size_t f, std::size_t k) { return 1 + f * o.p_values.size() + k; };
  for (const auto& g : o.regimes) {
    RegimeOutcome& ro = out.regimes.emplace_back();
    const auto scenario = apply_regime(base, g);
    t0 = core::Clock::now();
    const auto local = solve_local_pair(scenario);
    ro.local_time_s = core::seconds_since(t0);
    t0 = core::Clock::now();
    core::Progress progress = context.progress(o.datasets);
    const auto runs = run_merge_datasets(scenario, local, apply_regime(o.candidates, g), specs, context,
                                         o.datasets, o.datasets, &progress);
    progress.finish();
    ro.datasets_time_s = core::seconds_since(t0);
    // Pooled TPR/FPR, mean normalized χ² and mean selection size per (family, p).
    ro.chi2_no_out = summarize_method(runs, 0).mean("chi2");
    ro.curves.resize(o.families.size());
    for (std::size_t f = 0; f < o.families.size(); ++f)
      for (std::size_t k = 0; k < o.p_values.size(); ++k) {
        const auto s = summarize_method(runs, spec_index(f, k));
        ro.curves[f].tpr.push_back(s.pooled.tpr());
        ro.curves[f].fpr.push_back(s.pooled.fpr());
        ro.curves[f].chi2.push_back(s.mean("chi2"));
        ro.curves[f].selected.push_back(s.mean("selected"));
        ro.curves[f].selection_time_s.push_back(s.mean("selection_time_s"));
      }
  }
  return out;
}

void ThresholdSweep::record(Results& r, const Outcome& out) {
  const Options& o = out.options;
  const auto& p_values = o.p_values;
  r.timing("read_and_split", out.read_time_s);
  r.metric("scenario.pool", static_cast<double>(out.pool));
  r.metric("datasets", static_cast<double>(o.datasets));
  r.metric("candidates", o.candidates.total());
  r.series("p", p_values);
  for (std::size_t gi = 0; gi < o.regimes.size(); ++gi) {
    const auto& g = o.regimes[gi];
    const RegimeOutcome& ro = out.regimes[gi];
    const auto& curves = ro.curves;
    const auto regime = r.under(g.name);
    regime.timing("local_solves", ro.local_time_s);
    regime.timing("datasets", ro.datasets_time_s);
    regime.metric("no_out.chi2", ro.chi2_no_out);
    for (std::size_t f = 0; f < o.families.size(); ++f) {
      const auto n = regime.under(o.families[f].name);
      // One selection's wall time at each p: "<regime>.<family>@<p>.time_s".
      for (std::size_t k = 0; k < p_values.size(); ++k)
        regime.under(fmt::format("{}@{:g}", o.families[f].name, p_values[k]))
            .timing("time_s", curves[f].selection_time_s[k]);
      n.series("tpr", curves[f].tpr);
      n.series("fpr", curves[f].fpr);
      n.series("chi2", curves[f].chi2);
      n.series("selected", curves[f].selected);
      for (std::size_t k = 0; k < p_values.size(); ++k)
        if (p_values[k] == 0.11) {
          n.metric("tpr@0.11", curves[f].tpr[k]);
          n.metric("fpr@0.11", curves[f].fpr[k]);
        }
    }

    // The claims of §2.7.2.1 on this regime's curves (they may fail).
    const std::string in = " [" + g.label + "]";
    const std::size_t fe = o.fe, fh = o.fh, fr = o.fr;
    const double chi2_no_out = ro.chi2_no_out;
    double tmin = 1.0, tmax = 0.0, fmax = 0.0;
    std::string at;
    for (std::size_t k = 0; k < p_values.size(); ++k) {
      if (p_values[k] > o.claim_p_max) continue;
      tmin = std::min(tmin, curves[fe].tpr[k]);
      tmax = std::max(tmax, curves[fe].tpr[k]);
      fmax = std::max(fmax, curves[fe].fpr[k]);
      at += fmt::format("{}p={:g}: {:.3f}/{:.4f}", at.empty() ? "" : ", ", p_values[k], curves[fe].tpr[k],
                        curves[fe].fpr[k]);
    }
    const std::string detail = "PCM-Exact TPR/FPR " + at;
    r.check(
        fmt::format("PCM's TPR is relatively unaffected by the threshold for p <= {:g} (spread <= {:g}){}",
                    o.claim_p_max, o.claim_tpr_spread, in),
        tmax - tmin <= o.claim_tpr_spread, detail);
    r.check(fmt::format("PCM's FPR stays <= {:g} for p <= {:g}{}", o.claim_fpr_max, o.claim_p_max, in),
            fmax <= o.claim_fpr_max, detail);
    const double fmin = *std::min_element(curves[fr].fpr.begin(), curves[fr].fpr.end());
    r.check("RANSAC never reaches an FPR of zero" + in, fmin > 0.0,
            fmt::format("smallest RANSAC FPR over the sweep {:.4f}", fmin));
    std::size_t higher = 0, same = 0;
    double worst = 0.0;
    for (std::size_t k = 0; k < p_values.size(); ++k) {
      higher += curves[fr].fpr[k] > curves[fe].fpr[k];
      same += curves[fe].tpr[k] == curves[fh].tpr[k] && curves[fe].fpr[k] == curves[fh].fpr[k];
      worst = std::max(worst, std::abs(curves[fe].chi2[k] - chi2_no_out) / chi2_no_out);
    }
    r.check("RANSAC accepts more outliers than PCM at every threshold" + in, higher == p_values.size(),
            fmt::format("RANSAC FPR above PCM-Exact's at {} of {} thresholds", higher, p_values.size()));
    r.check(
        "PCM's merged graphs are consistent at every threshold (normalized chi2 within 10 % of NO-OUT's)" +
            in,
        worst <= 0.1,
        fmt::format("largest relative difference to NO-OUT's {:.4g}: {:.4f}", chi2_no_out, worst));
    r.check("PCM-Heuristic tracks PCM-Exact across the sweep (all but at most one threshold)" + in,
            same + 1 >= p_values.size(),
            fmt::format("identical pooled TPR and FPR at {} of {} thresholds", same, p_values.size()));
  }
}

std::vector<Figure> ThresholdSweep::figures(const Outcome& out) {
  const Options& o = out.options;
  Figure fig;
  fig.file = ".png";
  fig.title = fmt::format(
      "Fig. 2.4: City10000 two-robot data sets ({} sets) against the tail probability p of "
      "γ(p) = F⁻¹χ²(3)(1 − p); larger p = stricter",
      o.datasets);
  fig.cols = 3;
  fig.rows = static_cast<int>(o.regimes.size());
  fig.width = 16.5;
  fig.height = 4.6 * fig.rows;
  // One row of three panels (TPR, FPR, χ²) per regime.
  for (std::size_t gi = 0; gi < o.regimes.size(); ++gi) {
    const auto& curves = out.regimes[gi].curves;
    const char* names[3] = {"TPR", "FPR", "normalized χ²"};
    for (int panel = 0; panel < 3; ++panel) {
      Panel pa;
      pa.title = fmt::format("{} — {}", names[panel], o.regimes[gi].label);
      pa.xlabel = "p";
      pa.ylabel = names[panel];
      pa.xscale = "logit";  // p spans 0.001 … 0.99: both ends matter
      if (panel == 2) pa.yscale = "log";
      pa.legend = panel == 0 ? "" : "none";
      for (std::size_t f = 0; f < o.families.size(); ++f) {
        const auto& y = panel == 0 ? curves[f].tpr : panel == 1 ? curves[f].fpr : curves[f].chi2;
        pa.layers.push_back(repro::line_layer(o.p_values, y, o.families[f].label, o.families[f].color, "o",
                                              o.families[f].name == "pcm_heuristic" ? "--" : ""));
      }
      if (panel == 2) pa.layers.push_back(repro::hline_layer(out.regimes[gi].chi2_no_out, "NO-OUT", "0.3"));
      fig.panels.push_back(pa);
    }
  }
  return {fig};
}

}  // namespace keel::study::ch2
