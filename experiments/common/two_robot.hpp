// Shared glue of the two-robot map-merging experiments of chapter 2 (Tables 2.1–2.2): timing, number formatting,
// summary statistics and the [params] readers for the split, the candidate generator and the method list. Include
// after `import keel.core; import keel.pcm; import keel.sim; import keel.eval;` (DESIGN rule 4); it imports nothing itself. Drivers call engine
// functions only; no linear algebra here.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace keel::experiments {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A number as printf's %g (for check descriptions).
inline std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

struct MeanStd {
  double mean = 0.0, std = 0.0, max = 0.0;
};
// Mean, sample standard deviation (n − 1) and maximum; all zero for an empty vector.
inline MeanStd mean_std(const std::vector<double>& v) {
  MeanStd s;
  if (v.empty()) return s;
  s.max = v[0];
  for (double x : v) {
    s.mean += x;
    s.max = std::max(s.max, x);
  }
  s.mean /= static_cast<double>(v.size());
  if (v.size() > 1) {
    for (double x : v) s.std += (x - s.mean) * (x - s.mean);
    s.std = std::sqrt(s.std / static_cast<double>(v.size() - 1));
  }
  return s;
}

struct MethodConfig {
  keel::eval::MergeMethod method;
  std::string label;  // for figures and tables
};

// `methods = [names]` and one [params.method.<name>] table each: label, kind, and optionally p, composition,
// dcs_phi, dcs_accept_scale, scgp_affinity_scale, scgp_discretization (defaults: MergeMethod's).
inline std::vector<MethodConfig> read_methods(const keel::core::ConfigTable& p) {
  namespace core = keel::core;
  namespace pcm = keel::pcm;
namespace sim = keel::sim;
namespace eval = keel::eval;
  std::vector<MethodConfig> out;
  const auto table = p.table("method");
  for (const auto& name : p.strings("methods")) {
    if (!table.has(name))
      throw core::ConfigError(p.where("methods") + ": no [params.method." + name + "] table");
    const auto t = table.table(name);
    MethodConfig m;
    m.method.name = name;
    m.label = t.string("label");
    m.method.kind = eval::merge_method_kind_from_string(t.string("kind"));
    m.method.p = t.number_or("p", m.method.p);
    m.method.composition = pcm::composition_from_string(t.string_or("composition", "joint"));
    m.method.dcs_phi = t.number_or("dcs_phi", m.method.dcs_phi);
    m.method.dcs_accept_scale = t.number_or("dcs_accept_scale", m.method.dcs_accept_scale);
    m.method.scgp.affinity_scale = t.number_or("scgp_affinity_scale", m.method.scgp.affinity_scale);
    if (t.has("scgp_discretization"))
      m.method.scgp.discretization = pcm::scgp_discretization_from_string(t.string("scgp_discretization"));
    m.method.validate();
    out.push_back(m);
  }
  return out;
}

// A `[min, max]` pair of numbers.
inline std::pair<double, double> range_of(const keel::core::ConfigTable& p, const char* key) {
  const auto v = p.numbers(key);
  if (v.size() != 2) throw keel::core::ConfigError(p.where(key) + ": expected [min, max]");
  return {v[0], v[1]};
}

// `first`, `split`, `last`: robot a = poses [first, split), robot b = [split, last).
inline keel::sim::SplitOptions read_split(const keel::core::ConfigTable& p) {
  keel::sim::SplitOptions split;
  split.first = static_cast<int>(p.integer("first"));
  split.split = static_cast<int>(p.integer("split"));
  split.last = static_cast<int>(p.integer("last"));
  return split;
}

// `num_inliers`, `aliased_groups`, `aliased_group_size`, `random_outliers`, `random_sigma_translation` and
// `random_sigma_rotation` ([min, max]); validated.
inline keel::sim::CandidateOptions read_candidate_options(const keel::core::ConfigTable& p) {
  keel::sim::CandidateOptions copt;
  copt.num_inliers = static_cast<int>(p.integer("num_inliers"));
  copt.aliased_groups = static_cast<int>(p.integer("aliased_groups"));
  copt.aliased_group_size = static_cast<int>(p.integer("aliased_group_size"));
  copt.random_outliers = static_cast<int>(p.integer("random_outliers"));
  std::tie(copt.random_sigma_translation_min, copt.random_sigma_translation_max) =
      range_of(p, "random_sigma_translation");
  std::tie(copt.random_sigma_rotation_min, copt.random_sigma_rotation_max) = range_of(p, "random_sigma_rotation");
  copt.validate();
  return copt;
}


// §2.6 step i for both robots of a scenario: solves and factorizes each local map once and records what Tables 2.1/2.2
// report about them (timings of the solves and factorizations; metrics: pool size, poses, own loop closures and the
// normalized χ² of each local solve).
template <class G>
std::pair<keel::eval::LocalSolution<G>, keel::eval::LocalSolution<G>> solve_local_maps(
    keel::core::Results& r, const keel::sim::TwoRobotScenario<G>& scenario) {
  auto a = keel::eval::solve_local(scenario.robot_a);
  auto b = keel::eval::solve_local(scenario.robot_b);
  r.timing("local.a.solve", a.solve_time_s);
  r.timing("local.b.solve", b.solve_time_s);
  r.timing("local.a.factorization", a.factorization_time_s);
  r.timing("local.b.factorization", b.factorization_time_s);
  int closures_a = 0, closures_b = 0;
  for (const auto& e : scenario.robot_a.edges) closures_a += std::abs(e.i - e.j) != 1;
  for (const auto& e : scenario.robot_b.edges) closures_b += std::abs(e.i - e.j) != 1;
  r.metric("scenario.pool", static_cast<double>(scenario.pool.size()));
  r.metric("scenario.robot_a.poses", static_cast<double>(scenario.truth_a.size()));
  r.metric("scenario.robot_b.poses", static_cast<double>(scenario.truth_b.size()));
  r.metric("scenario.robot_a.loop_closures", closures_a);
  r.metric("scenario.robot_b.loop_closures", closures_b);
  r.metric("local.a.normalized_chi2", a.summary.normalized_chi2);
  r.metric("local.b.normalized_chi2", b.summary.normalized_chi2);
  return {std::move(a), std::move(b)};
}

// Per data set: covariance extraction, the matrix Q and the independent-composition Q of the ablation, as timings
// (mean and max; never diffed).
template <class G>
void record_dataset_timings(keel::core::Results& r, const std::vector<keel::eval::MergeDataset<G>>& runs) {
  std::vector<double> t_cov, t_q, t_qi;
  for (const auto& d : runs) {
    t_cov.push_back(d.covariance_time_s);
    t_q.push_back(d.matrix_time_s);
    t_qi.push_back(d.matrix_independent_time_s);
  }
  for (const auto& [name, v] :
       {std::pair<const char*, const std::vector<double>*>{"dataset.cov_extraction", &t_cov},
        {"dataset.matrix", &t_q},
        {"dataset.matrix_independent", &t_qi}}) {
    const auto s = mean_std(*v);
    r.timing(std::string(name) + ".mean", s.mean);
    r.timing(std::string(name) + ".max", s.max);
  }
}

// Figs. 2.5 / 2.7: one panel per method with the merged trajectories of both robots (axes ax, ay of the translation)
// and every candidate as a segment between its two poses: blue accepted inliers, red accepted outliers, pink rejected
// inliers, grey rejected outliers. `d` must have been run with keep_solutions.
template <class G>
keel::core::Figure merged_maps_figure(const keel::eval::MergeDataset<G>& d, const std::vector<MethodConfig>& methods,
                                      const std::string& file, const std::string& title, int ax, int ay,
                                      double trajectory_width, const std::string& xlabel = "",
                                      const std::string& ylabel = "") {
  namespace core = keel::core;
  core::Figure f;
  f.file = file;
  f.title = title + " (blue: accepted inliers, red: accepted outliers, pink: rejected inliers, grey: rejected outliers)";
  f.cols = 4;
  f.rows = static_cast<int>((methods.size() + 3) / 4);
  f.width = 22.0;
  f.height = 5.5 * f.rows;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const auto& o = d.methods[k];
    const auto& m = o.merged;
    core::Panel panel;
    char text[160];
    std::snprintf(text, sizeof text, "%s: TP %d, FP %d", methods[k].label.c_str(), o.metrics.classification.tp,
                  o.metrics.classification.fp);
    panel.title = text;
    panel.xlabel = xlabel;
    panel.ylabel = ylabel;
    panel.aspect = "equal";
    panel.legend = "none";
    std::vector<double> xa, ya, xb, yb;
    for (const auto& T : m.poses_a) {
      xa.push_back(T.translation()(ax));
      ya.push_back(T.translation()(ay));
    }
    for (const auto& T : m.poses_b) {
      xb.push_back(T.translation()(ax));
      yb.push_back(T.translation()(ay));
    }
    auto la = core::line_layer(xa, ya, "robot a", "0.25");
    la.linewidth = trajectory_width;
    auto lb = core::line_layer(xb, yb, "robot b", "0.55");
    lb.linewidth = trajectory_width;
    panel.layers.push_back(la);
    panel.layers.push_back(lb);
    std::vector<char> chosen(d.candidates.candidates.size(), 0);
    for (int u : o.selection.selected) chosen[static_cast<std::size_t>(u)] = 1;
    // Drawing order: rejected outliers, rejected inliers, accepted inliers, accepted outliers (on top).
    const struct {
      bool accepted, inlier;
      const char *label, *color;
      double width, alpha;
    } groups[] = {{false, false, "rejected outliers", "0.6", 0.4, 0.35},
                  {false, true, "rejected inliers", "pink", 1.2, 1.0},
                  {true, true, "accepted inliers", "navy", 1.4, 1.0},
                  {true, false, "accepted outliers", "red", 1.4, 1.0}};
    for (const auto& g : groups) {
      core::Layer l;
      l.type = "segments";
      l.label = g.label;
      l.color = g.color;
      l.linewidth = g.width;
      l.alpha = g.alpha;
      for (std::size_t u = 0; u < d.candidates.candidates.size(); ++u) {
        if ((chosen[u] != 0) != g.accepted || d.candidates.labels[u].is_inlier() != g.inlier) continue;
        const auto& c = d.candidates.candidates[u];
        const auto& pa = m.poses_a[static_cast<std::size_t>(c.pose_a)].translation();
        const auto& pb = m.poses_b[static_cast<std::size_t>(c.pose_b)].translation();
        l.x0.push_back(pa(ax));
        l.y0.push_back(pa(ay));
        l.x1.push_back(pb(ax));
        l.y1.push_back(pb(ay));
      }
      if (!l.x0.empty()) panel.layers.push_back(l);
    }
    f.panels.push_back(panel);
  }
  return f;
}

}  // namespace keel::experiments
