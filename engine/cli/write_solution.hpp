// The solved graph of keel solve --out and keel robust --out, for the commands that import keel.graph
// (include after the imports).
#pragma once

#include <filesystem>

namespace keel::cli {

// Writes a solved graph (the solution as its poses) in `format`.
template <class Graph>
void write_solution(const Graph& g, const std::filesystem::path& out, graph::GraphFormat format) {
  if (format == graph::GraphFormat::g2o)
    graph::write_g2o(g, out);
  else
    graph::write_isam(g, out);
}

}  // namespace keel::cli
