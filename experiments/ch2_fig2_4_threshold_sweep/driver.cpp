// Fig. 2.4 (§2.7.2.1): TPR, FPR and normalized χ² of PCM-Exact, PCM-Heuristic and RANSAC against the consistency
// threshold on the City10000 two-robot data sets of Table 2.1 — thin driver over keel.pcm (scenario, consistency,
// selection, merge) and keel.core. Beyond the thesis: the same sweep with the poses composed as independent.
import keel.core;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.cov;
import keel.pcm;
import keel.sim;
import keel.eval;

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "common/two_robot.hpp"

namespace core = keel::core;
namespace pcm = keel::pcm;
namespace sim = keel::sim;
namespace eval = keel::eval;
namespace ke = keel::experiments;

namespace {

struct Family {
  std::string name, label, color;
  eval::MergeMethodKind kind = eval::MergeMethodKind::pcm_exact;
  pcm::Composition composition = pcm::Composition::joint;
};

}  // namespace

int main(int argc, char** argv) {
  return core::experiment_main(argc, argv, [](core::Experiment& ex) {
    const auto& p = ex.params();
    const std::string dataset = p.string("dataset"), graph_file = p.string("graph_file"),
                      truth_file = p.string("ground_truth_file");
    const auto split = ke::read_split(p);
    const auto copt = ke::read_candidate_options(p);
    const std::size_t datasets = p.count("datasets");
    const std::vector<double> p_values = p.numbers("p_values");
    const double claim_p_max = p.number("claim_p_max"), claim_tpr_spread = p.number("claim_tpr_spread"),
                 claim_fpr_max = p.number("claim_fpr_max");
    std::vector<Family> families;
    {
      const auto table = p.table("family");
      for (const auto& name : p.strings("families")) {
        if (!table.has(name))
          throw core::ConfigError(p.where("families") + ": no [params.family." + name + "] table");
        const auto t = table.table(name);
        Family f;
        f.name = name;
        f.label = t.string("label");
        f.color = t.string("color");
        f.kind = eval::merge_method_kind_from_string(t.string("kind"));
        f.composition = pcm::composition_from_string(t.string_or("composition", "joint"));
        if (f.kind != eval::MergeMethodKind::pcm_exact && f.kind != eval::MergeMethodKind::pcm_heuristic &&
            f.kind != eval::MergeMethodKind::ransac)
          throw core::ConfigError(t.where("kind") + ": a threshold sweep needs pcm_exact, pcm_heuristic or ransac");
        families.push_back(f);
      }
    }
    struct Regime {
      std::string name, label, measurements;
      double noise_scale = 1.0;
      std::uint64_t resample_seed = 0;
    };
    std::vector<Regime> regimes;
    {
      const auto table = p.table("regime");
      for (const auto& name : p.strings("regimes")) {
        if (!table.has(name))
          throw core::ConfigError(p.where("regimes") + ": no [params.regime." + name + "] table");
        const auto t = table.table(name);
        Regime g;
        g.name = name;
        g.label = t.string("label");
        g.measurements = t.string("measurements");
        if (g.measurements == "resampled") {
          g.noise_scale = t.number("noise_scale");
          g.resample_seed = static_cast<std::uint64_t>(t.integer("resample_seed"));
        } else if (g.measurements != "dataset") {
          throw core::ConfigError(t.where("measurements") + ": expected \"dataset\" or \"resampled\"");
        }
        regimes.push_back(g);
      }
    }
    ex.params_done();
    for (std::size_t k = 0; k < p_values.size(); ++k)
      if (!(p_values[k] > 0.0 && p_values[k] < 1.0) || (k > 0 && p_values[k] <= p_values[k - 1]))
        throw core::ConfigError(p.where("p_values") + ": must be increasing and inside (0, 1)");
    const auto find_family = [&](const std::string& name) -> const Family* {
      for (const auto& f : families)
        if (f.name == name) return &f;
      return nullptr;
    };
    const Family* exact = find_family("pcm_exact");
    const Family* heuristic = find_family("pcm_heuristic");
    const Family* ransac = find_family("ransac");
    if (!exact || !heuristic || !ransac)
      throw core::ConfigError(p.where("families") + ": the claims need pcm_exact, pcm_heuristic and ransac");

    // One method per (family, p); NO-OUT first (the χ² reference of the figure).
    std::vector<eval::MergeMethod> specs;
    {
      eval::MergeMethod m;
      m.name = "no_out";
      m.kind = eval::MergeMethodKind::no_outliers;
      specs.push_back(m);
    }
    for (const auto& f : families)
      for (std::size_t k = 0; k < p_values.size(); ++k) {
        eval::MergeMethod m;
        m.name = f.name + "@" + ke::fmt(p_values[k]);
        m.kind = f.kind;
        m.p = p_values[k];
        m.composition = f.composition;
        m.validate();
        specs.push_back(m);
      }
    auto spec_index = [&](std::size_t family, std::size_t k) { return 1 + family * p_values.size() + k; };

    auto& r = ex.results();
    auto t0 = std::chrono::steady_clock::now();
    const auto graph = keel::graph::read_pose_graph_2d(keel::graph::resolve_dataset_file(dataset, graph_file));
    const auto truth = keel::graph::read_poses_2d(keel::graph::resolve_dataset_file(dataset, truth_file));
    const auto base = sim::split_two_robots(graph, truth, split);
    r.timing("read_and_split", ke::seconds_since(t0));
    r.metric("scenario.pool", static_cast<double>(base.pool.size()));
    r.metric("datasets", static_cast<double>(datasets));
    r.metric("candidates", copt.total());
    r.series("p", p_values);

    const std::size_t fe = static_cast<std::size_t>(exact - families.data()),
                      fh = static_cast<std::size_t>(heuristic - families.data()),
                      fr = static_cast<std::size_t>(ransac - families.data());
    core::Figure fig;
    fig.file = ex.id() + ".png";
    fig.title = "Fig. 2.4: City10000 two-robot data sets (" + std::to_string(datasets) +
                " sets) against the tail probability p of γ(p) = F⁻¹χ²(3)(1 − p); larger p = stricter";
    fig.cols = 3;
    fig.rows = static_cast<int>(regimes.size());
    fig.width = 16.5;
    fig.height = 4.6 * fig.rows;

    for (const auto& g : regimes) {
      // The regime's scenario: the file's measurements, or all of them redrawn with scaled noise.
      auto scenario = base;
      auto c = copt;
      if (g.measurements == "resampled") {
        sim::resample_measurements(scenario, g.noise_scale, g.resample_seed);
        c.aliased_noise_scale = g.noise_scale;
      }
      t0 = std::chrono::steady_clock::now();
      const auto a = eval::solve_local(scenario.robot_a);
      const auto b = eval::solve_local(scenario.robot_b);
      r.timing(g.name + ".local_solves", ke::seconds_since(t0));
      std::vector<eval::MergeDataset2> runs(datasets);
      t0 = std::chrono::steady_clock::now();
      {
        core::Progress progress(ex.id() + " " + g.name, datasets);
        core::parallel_for(
            datasets, [&](std::size_t i) { runs[i] = eval::run_merge_dataset(scenario, a, b, c, specs, ex.seed(), i); },
            ex.threads(), &progress);
        progress.finish();
      }
      r.timing(g.name + ".datasets", ke::seconds_since(t0));

      // Pooled TPR/FPR and mean normalized χ² per (family, p).
      struct Curve {
        std::vector<double> tpr, fpr, chi2, selected;
      };
      auto pooled = [&](std::size_t sp, eval::Classification& cl, std::vector<double>& chi2,
                        std::vector<double>& sel) {
        for (const auto& d : runs) {
          const auto& o = d.methods[sp];
          cl.tp += o.metrics.classification.tp;
          cl.fp += o.metrics.classification.fp;
          cl.fn += o.metrics.classification.fn;
          cl.tn += o.metrics.classification.tn;
          chi2.push_back(o.metrics.normalized_chi2);
          sel.push_back(static_cast<double>(o.selection.selected.size()));
        }
      };
      double chi2_no_out = 0.0;
      {
        eval::Classification cl;
        std::vector<double> chi2, sel;
        pooled(0, cl, chi2, sel);
        chi2_no_out = ke::mean_std(chi2).mean;
        r.metric(g.name + ".no_out.chi2", chi2_no_out);
      }
      std::vector<Curve> curves(families.size());
      for (std::size_t f = 0; f < families.size(); ++f) {
        for (std::size_t k = 0; k < p_values.size(); ++k) {
          eval::Classification cl;
          std::vector<double> chi2, sel;
          pooled(spec_index(f, k), cl, chi2, sel);
          curves[f].tpr.push_back(cl.tpr());
          curves[f].fpr.push_back(cl.fpr());
          curves[f].chi2.push_back(ke::mean_std(chi2).mean);
          curves[f].selected.push_back(ke::mean_std(sel).mean);
          std::vector<double> t_sel;
          for (const auto& d : runs) t_sel.push_back(d.methods[spec_index(f, k)].selection.time_s);
          r.timing(g.name + "." + specs[spec_index(f, k)].name + ".time_s", ke::mean_std(t_sel).mean);
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

      // Claims of §2.7.2.1 on our numbers, per regime (they may fail).
      const std::string in = " [" + g.label + "]";
      char detail[768];
      {
        double tmin = 1.0, tmax = 0.0, fmax = 0.0;
        std::string at;
        for (std::size_t k = 0; k < p_values.size(); ++k) {
          if (p_values[k] > claim_p_max) continue;
          tmin = std::min(tmin, curves[fe].tpr[k]);
          tmax = std::max(tmax, curves[fe].tpr[k]);
          fmax = std::max(fmax, curves[fe].fpr[k]);
          char one[64];
          std::snprintf(one, sizeof one, "%sp=%g: %.3f/%.4f", at.empty() ? "" : ", ", p_values[k],
                        curves[fe].tpr[k], curves[fe].fpr[k]);
          at += one;
        }
        std::snprintf(detail, sizeof detail, "PCM-Exact TPR/FPR %s", at.c_str());
        r.check("PCM's TPR is relatively unaffected by the threshold for p <= " + ke::fmt(claim_p_max) +
                    " (spread <= " + ke::fmt(claim_tpr_spread) + ")" + in,
                tmax - tmin <= claim_tpr_spread, detail);
        r.check("PCM's FPR stays <= " + ke::fmt(claim_fpr_max) + " for p <= " + ke::fmt(claim_p_max) + in,
                fmax <= claim_fpr_max, detail);
      }
      {
        const double fmin = *std::min_element(curves[fr].fpr.begin(), curves[fr].fpr.end());
        std::snprintf(detail, sizeof detail, "smallest RANSAC FPR over the sweep %.4f", fmin);
        r.check("RANSAC never reaches an FPR of zero" + in, fmin > 0.0, detail);
        std::size_t higher = 0;
        for (std::size_t k = 0; k < p_values.size(); ++k) higher += curves[fr].fpr[k] > curves[fe].fpr[k];
        std::snprintf(detail, sizeof detail, "RANSAC FPR above PCM-Exact's at %zu of %zu thresholds", higher,
                      p_values.size());
        r.check("RANSAC accepts more outliers than PCM at every threshold" + in, higher == p_values.size(), detail);
      }
      {
        double worst = 0.0;
        for (std::size_t k = 0; k < p_values.size(); ++k)
          worst = std::max(worst, std::abs(curves[fe].chi2[k] - chi2_no_out) / chi2_no_out);
        std::snprintf(detail, sizeof detail, "largest relative difference to NO-OUT's %.4g: %.4f", chi2_no_out, worst);
        r.check("PCM's merged graphs are consistent at every threshold (normalized chi2 within 10 % of NO-OUT's)" + in,
                worst <= 0.1, detail);
        std::size_t same = 0;
        for (std::size_t k = 0; k < p_values.size(); ++k)
          same += curves[fe].tpr[k] == curves[fh].tpr[k] && curves[fe].fpr[k] == curves[fh].fpr[k];
        std::snprintf(detail, sizeof detail, "identical pooled TPR and FPR at %zu of %zu thresholds", same,
                      p_values.size());
        r.check("PCM-Heuristic tracks PCM-Exact across the sweep (all but at most one threshold)" + in,
                same + 1 >= p_values.size(), detail);
      }

      // Fig. 2.4: one row of three panels per regime.
      const char* names[3] = {"TPR", "FPR", "normalized χ²"};
      for (int panel = 0; panel < 3; ++panel) {
        core::Panel pa;
        pa.title = std::string(names[panel]) + " — " + g.label;
        pa.xlabel = "p";
        pa.ylabel = names[panel];
        pa.xscale = "logit";  // p spans 0.001 … 0.99: both ends matter
        if (panel == 2) pa.yscale = "log";
        pa.legend = panel == 0 ? "" : "none";
        for (std::size_t f = 0; f < families.size(); ++f) {
          const auto& y = panel == 0 ? curves[f].tpr : panel == 1 ? curves[f].fpr : curves[f].chi2;
          pa.layers.push_back(core::line_layer(p_values, y, families[f].label, families[f].color, "o",
                                               families[f].name == "pcm_heuristic" ? "--" : ""));
        }
        if (panel == 2) pa.layers.push_back(core::hline_layer(chi2_no_out, "NO-OUT", "0.3"));
        fig.panels.push_back(pa);
      }
    }
    r.figure(fig);
  });
}
