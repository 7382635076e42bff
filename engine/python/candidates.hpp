// keel Python module — the candidate inter-robot loop closures of an edge-only g2o file (keel.Candidates).
#pragma once

#include <cstddef>
#include <string>
#include <variant>
#include <vector>

#include "graph/pose_graph.hpp"

namespace keel::python {

struct Candidates {
  std::variant<std::vector<graph::Edge2>, std::vector<graph::Edge3>> edges;
  std::string source;  // file read from ('' if made in Python)
  int dim() const { return edges.index() == 0 ? 2 : 3; }
  std::size_t size() const {
    return std::visit([](const auto& e) { return e.size(); }, edges);
  }
};

}  // namespace keel::python
