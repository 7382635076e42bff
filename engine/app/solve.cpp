#include "app/solve.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "app/files.hpp"
#include "core/timing.hpp"
#include "graph/io.hpp"
#include "graph/text_records.hpp"

namespace keel::app {

namespace {

template <class Graph, class Estimate>
Solution<Graph> solve_impl(const Graph& g, const SolveOptions& options, const Estimate* initial) {
  pgo::Options o = options.pgo_options();
  o.constant_poses = {g.gauge_pose};  // the graph's gauge (g2o's FIX line; pose 0 by default)
  check_numeric_range(g);  // the cost must be computable in double before a solver starts (files.hpp)
  const auto t0 = core::Clock::now();
  auto r = pgo::optimize(g, o, initial);
  Solution<Graph> out;
  out.solve_time_s = core::seconds_since(t0);
  out.graph = g;
  out.graph.poses = std::move(r.estimate.poses);
  if constexpr (requires { out.graph.landmarks; }) out.graph.landmarks = std::move(r.estimate.landmarks);
  out.summary = std::move(r.summary);
  out.edges = std::move(r.edges);
  return out;
}

template <class Graph>
CertifiedSolution<Graph> certified_impl(const Graph& g, const SolveOptions& options) {
  check_numeric_range(g);  // as solve_impl
  const pgo::CertifiedOptions o = options.certified_options();
  const auto t0 = core::Clock::now();
  auto r = pgo::solve_certified(g, o);
  CertifiedSolution<Graph> out;
  out.solve_time_s = core::seconds_since(t0);
  out.graph = g;
  out.graph.poses = std::move(r.poses);
  out.graph.has_initial_poses = true;
  out.summary = std::move(r.summary);
  if (g.indefinite_information > 0) {
    out.anisotropic_cost = std::numeric_limits<double>::quiet_NaN();  // undefined with indefinite information
  } else if constexpr (std::is_same_v<Graph, graph::PoseGraph2D>) {
    pgo::Estimate2D at;
    at.poses = out.graph.poses;
    out.anisotropic_cost = pgo::evaluate(g, at).cost;
  } else {
    pgo::Estimate3D at;
    at.poses = out.graph.poses;
    out.anisotropic_cost = pgo::evaluate(g, at).cost;
  }
  return out;
}

}  // namespace

CertifiedSolution2 solve_certified(const graph::PoseGraph2D& g, const SolveOptions& options) {
  return certified_impl(g, options);
}
CertifiedSolution3 solve_certified(const graph::PoseGraph3D& g, const SolveOptions& options) {
  return certified_impl(g, options);
}

GraphInput read_graph_input(const std::filesystem::path& file, graph::InformationCheck information) {
  // Read once and parse from memory, so a pipe or FIFO (`<(cat g.g2o)`) works.
  const std::string text = graph::read_file_text(file);
  std::istringstream in(text);
  GraphInput out;
  if (graph_dimension(text, file.string()) == 3)
    out.graph = graph::read_pose_graph_3d(in, file.string(), information);
  else
    out.graph = graph::read_pose_graph_2d(in, file.string(), information);
  out.format = graph::detect_graph_format(text, file.string()).value_or(graph::GraphFormat::g2o);
  return out;
}

AnyGraph read_graph(const std::filesystem::path& file, graph::InformationCheck information) {
  return read_graph_input(file, information).graph;
}

pgo::Options SolveOptions::pgo_options() const {
  std::string guess = init;
  std::replace(guess.begin(), guess.end(), '-', '_');
  pgo::Options o;
  o.initial_guess = pgo::initial_guess_from_string(guess);
  o.robust_kernel = pgo::robust_kernel_from_string(robust);
  o.robust_parameter = robust_parameter;
  o.seed = seed;
  o.threads = threads;
  o.max_iterations = max_iterations;
  o.validate();
  return o;
}

pgo::CertifiedOptions SolveOptions::certified_options() const {
  pgo::CertifiedOptions o;
  o.gap_tolerance = gap_tolerance;
  o.max_rank = max_rank;
  o.time_limit_s = time_limit_s;
  o.validate();
  if (max_rank < 2)
    throw std::invalid_argument(
        fmt::format("CertifiedOptions: max_rank must be >= 2, the smallest dimension d (got {})", max_rank));
  return o;
}

Solution2 solve(const graph::PoseGraph2D& g, const SolveOptions& options, const pgo::Estimate2D* initial) {
  return solve_impl(g, options, initial);
}

Solution3 solve(const graph::PoseGraph3D& g, const SolveOptions& options, const pgo::Estimate3D* initial) {
  return solve_impl(g, options, initial);
}

}  // namespace keel::app
