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
Solution<Graph> solve_impl(const Graph& g, const MaximumLikelihood& backend, const Estimate* initial) {
  backend.validate();
  pgo::Options o = backend.options;
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
CertifiedSolution<Graph> certified_impl(const Graph& g, const Certified& backend) {
  backend.validate();
  check_numeric_range(g);  // as solve_impl
  return pgo::certified_solution(g, backend.options);
}

}  // namespace

CertifiedSolution2 solve_certified(const graph::PoseGraph2D& g, const Certified& backend) {
  return certified_impl(g, backend);
}
CertifiedSolution3 solve_certified(const graph::PoseGraph3D& g, const Certified& backend) {
  return certified_impl(g, backend);
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

pgo::Options MaximumLikelihood::defaults() {
  pgo::Options o;
  o.initial_guess = pgo::InitialGuess::odometry;
  return o;
}

void MaximumLikelihood::validate() const { options.validate(); }

void Certified::validate() const {
  options.validate();
  if (options.max_rank < 2)
    throw std::invalid_argument(fmt::format(
        "CertifiedOptions: max_rank must be >= 2, the smallest dimension d (got {})", options.max_rank));
}

graph::InformationCheck information_check(const SolveBackend& backend) {
  return std::holds_alternative<Certified>(backend) ? graph::InformationCheck::diagonal_blocks
                                                    : graph::InformationCheck::positive_definite;
}

pgo::InitialGuess initial_guess_from_name(std::string name) {
  std::replace(name.begin(), name.end(), '-', '_');
  return pgo::initial_guess_from_string(name);
}

Solution2 solve(const graph::PoseGraph2D& g, const MaximumLikelihood& backend,
                const pgo::Estimate2D* initial) {
  return solve_impl(g, backend, initial);
}

Solution3 solve(const graph::PoseGraph3D& g, const MaximumLikelihood& backend,
                const pgo::Estimate3D* initial) {
  return solve_impl(g, backend, initial);
}

}  // namespace keel::app
