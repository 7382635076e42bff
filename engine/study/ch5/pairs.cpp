#include "study/ch5/pairs.hpp"

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

void record_solved(Results& r, const SolvedPairs& s) {
  r.timing("read", s.read_time_s);
  r.timing("solve", s.solve_time_s);
  r.metric("solver.final_cost", s.final_cost);
  r.metric("solver.normalized_chi2", s.normalized_chi2);
  r.metric("solver.poses", static_cast<double>(s.poses.size()));
  r.metric("solver.edges", static_cast<double>(s.edges));
  r.timing("marginals", s.marginals_time_s);
  r.metric("pairs", static_cast<double>(s.pairs.size()));
}

PairsSetup PairsSetup::read(const core::ConfigTable& p) {
  PairsSetup s;
  s.dataset = p.string("dataset");
  s.file = p.string("file");
  s.initial_guess = p.parse("initial_guess", pgo::initial_guess_from_string);
  for (double k : p.numbers("offsets")) s.offsets.push_back(static_cast<int>(k));
  for (double k : p.numbers("figure_offsets")) s.figure_offsets.push_back(static_cast<int>(k));
  s.pair_stride = static_cast<int>(p.count("pair_stride"));
  s.offsets_key = p.where("offsets");
  return s;
}

SolvedPairs solve_pairs(const PairsSetup& setup, const RunContext& context) {
  pgo::Options options;
  options.initial_guess = setup.initial_guess;
  // One solver thread: Ceres sums cost and gradient per thread, so 1 and 2 threads differ in the last bits
  // and the result files would depend on the thread count. The solve takes well under a second either way.
  options.threads = 1;
  SolvedPairs out;
  auto t0 = core::Clock::now();
  const auto graph = graph::read_pose_graph_2d(datasets::resolve_dataset_file(setup.dataset, setup.file));
  out.read_time_s = core::seconds_since(t0);
  t0 = core::Clock::now();
  const auto solved = pgo::optimize(graph, options);
  out.solve_time_s = core::seconds_since(t0);
  const auto& sum = solved.summary;
  if (sum.termination != pgo::Termination::converged)
    throw std::runtime_error(fmt::format("the solver did not converge: {}", sum.message));
  out.final_cost = sum.final_cost;
  out.normalized_chi2 = sum.normalized_chi2;
  out.edges = graph.edges.size();
  out.poses = solved.estimate.poses;

  t0 = core::Clock::now();
  const auto info = cov::information_matrix(graph, out.poses);
  const cov::MarginalCovariance marginals(info);
  const int n = static_cast<int>(out.poses.size());
  for (int k : setup.offsets) {
    if (k < 1 || k >= n)
      throw core::ConfigError(fmt::format("{}: offset {} out of range", setup.offsets_key, k));
    for (int i = 0; i + k < n; i += setup.pair_stride) out.pairs.emplace_back(i, i + k);
  }
  out.covariances = cov::pair_marginals_2d(marginals, out.pairs, context.threads());
  out.marginals_time_s = core::seconds_since(t0);
  return out;
}

}  // namespace keel::study::ch5
