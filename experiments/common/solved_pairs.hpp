// Shared glue of the Manhattan3500 relative-pose experiments (Tables 5.1–5.2): read the dataset, solve it,
// extract the pair marginals in the Lie algebra, run the pair study, record timings and the solver summary,
// and draw the Figs. 5.10–5.14 panels. Include after `import keel.core; import keel.repro; import keel.lie;
// import keel.graph; import keel.pgo; import keel.cov;` (DESIGN rule 4). Drivers call engine functions only;
// no linear algebra here.
#pragma once

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace keel::experiments {

struct SolvedPairs {
  std::vector<keel::lie::SE2> poses;           // the maximum-likelihood solution
  std::vector<std::pair<int, int>> pairs;      // (i, i + k)
  std::vector<keel::lie::PairRecord> records;  // one per pair
  std::vector<int> offsets, figure_offsets;
};

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The pipeline shared by the Manhattan3500 relative-pose experiments: reads the parameters (read_samples(p)
// reads the Monte-Carlo sample size(s), the rest is shared), solves, extracts the joint marginal of every
// pair and hands them to monte_carlo(out, covs), which runs the pair study once or once per sample size.
// Records the solver metrics and timings.
template <class ReadSamples, class MonteCarlo>
inline SolvedPairs solve_pairs(keel::repro::Experiment& ex, ReadSamples&& read_samples,
                               MonteCarlo&& monte_carlo) {
  namespace core = keel::core;
  namespace repro = keel::repro;
  const auto& p = ex.params();
  const std::string dataset = p.string("dataset"), file = p.string("file");
  keel::pgo::Options options;
  options.initial_guess = p.parse("initial_guess", keel::pgo::initial_guess_from_string);
  const auto offsets_in = p.numbers("offsets"), figure_offsets_in = p.numbers("figure_offsets");
  const auto stride = static_cast<int>(p.count("pair_stride"));
  read_samples(p);
  ex.params_done();
  // One solver thread: Ceres sums cost and gradient per thread, so 1 and 2 threads differ in the last bits
  // and the result files would depend on the thread count. The solve takes well under a second either way.
  options.threads = 1;
  SolvedPairs out;
  for (double k : offsets_in) out.offsets.push_back(static_cast<int>(k));
  for (double k : figure_offsets_in) out.figure_offsets.push_back(static_cast<int>(k));
  auto& r = ex.results();

  auto t0 = std::chrono::steady_clock::now();
  const auto graph = keel::graph::read_pose_graph_2d(keel::datasets::resolve_dataset_file(dataset, file));
  r.timing("read", seconds_since(t0));
  t0 = std::chrono::steady_clock::now();
  const auto solved = keel::pgo::optimize(graph, options);
  r.timing("solve", seconds_since(t0));
  const auto& sum = solved.summary;
  if (sum.termination != keel::pgo::Termination::converged) {
    throw std::runtime_error(fmt::format("the solver did not converge: {}", sum.message));
  }
  r.metric("solver.final_cost", sum.final_cost);
  r.metric("solver.normalized_chi2", sum.normalized_chi2);
  r.metric("solver.poses", static_cast<double>(solved.estimate.poses.size()));
  r.metric("solver.edges", static_cast<double>(graph.edges.size()));
  out.poses = solved.estimate.poses;

  t0 = std::chrono::steady_clock::now();
  const auto info = keel::cov::information_matrix(graph, out.poses);
  const keel::cov::MarginalCovariance marginals(info);
  const int n = static_cast<int>(out.poses.size());
  for (int k : out.offsets) {
    if (k < 1 || k >= n)
      throw core::ConfigError(fmt::format("{}: offset {} out of range", p.where("offsets"), k));
    for (int i = 0; i + k < n; i += stride) out.pairs.emplace_back(i, i + k);
  }
  const auto covs = keel::cov::pair_marginals_2d(marginals, out.pairs, ex.threads());
  r.timing("marginals", seconds_since(t0));
  monte_carlo(out, covs);
  r.metric("pairs", static_cast<double>(out.pairs.size()));
  return out;
}

// Tables 5.1 and 5.2: one pair study with `samples` Monte-Carlo samples per pair.
inline SolvedPairs run_solved_pairs(keel::repro::Experiment& ex) {
  keel::lie::PairStudySetup setup;
  return solve_pairs(
      ex, [&](const keel::core::ConfigTable& p) { setup.samples = p.count("samples"); },
      [&](SolvedPairs& out, const auto& covs) {
        const auto t0 = std::chrono::steady_clock::now();
        setup.seed = ex.seed();
        setup.threads = ex.threads();
        keel::core::Progress progress(ex.id(), out.pairs.size());
        out.records = keel::lie::run_pair_study_2d(out.poses, out.pairs, covs, setup, &progress);
        progress.finish();
        ex.results().timing("monte_carlo", seconds_since(t0));
      });
}

// Records `<name>.mean` / `<name>.std` over all pairs and per offset (`offset<k>.<name>.mean`).
inline keel::lie::PairStatistics record_statistics(keel::repro::Results& r, const SolvedPairs& s,
                                                   double keel::lie::PairRecord::* field,
                                                   const std::string& name) {
  const auto all = keel::lie::pair_statistics(s.records, field);
  r.metric(fmt::format("{}.mean", name), all.mean);
  r.metric(fmt::format("{}.std", name), all.std);
  for (int k : s.offsets) {
    const auto st = keel::lie::pair_statistics(s.records, field, k);
    r.metric(fmt::format("offset{}.{}.mean", k, name), st.mean);
    r.metric(fmt::format("offset{}.{}.std", k, name), st.std);
  }
  return all;
}

// One panel of Figs. 5.10–5.14: every pair at `offset` drawn as a segment between the two positions, coloured
// by `field` on [0, vmax] with `cmap`.
inline keel::repro::Panel pair_panel(const SolvedPairs& s, int offset, double keel::lie::PairRecord::* field,
                                     const std::string& title, const std::string& cmap, double vmax) {
  keel::repro::Panel panel;
  panel.title = title;
  panel.aspect = "equal";
  panel.colorbar = title;
  keel::repro::Layer l;
  l.type = "segments";
  for (const auto& rec : s.records) {
    if (rec.j - rec.i != offset) continue;
    const auto& a = s.poses[static_cast<std::size_t>(rec.i)].translation();
    const auto& b = s.poses[static_cast<std::size_t>(rec.j)].translation();
    l.x0.push_back(a(0));
    l.y0.push_back(a(1));
    l.x1.push_back(b(0));
    l.y1.push_back(b(1));
    l.c.push_back(rec.*field);
  }
  l.cmap = cmap;
  l.vmin = 0.0;
  l.vmax = vmax > 0 ? vmax : 1.0;
  l.linewidth = 0.6;
  panel.layers.push_back(l);
  return panel;
}

}  // namespace keel::experiments
