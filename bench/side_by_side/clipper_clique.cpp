// CLIPPER's side of the maximum-clique side-by-side (bench/side_by_side/clique.sh): reads the same DIMACS
// "p edge" graphs as keel_clique.cpp and times CLIPPER's dense-cluster solver (clipper::CLIPPER::solve,
// MIT-ACL, https://github.com/mit-acl/clipper) with its default clipper::Params, one thread
// (OMP_NUM_THREADS=1), median of --repeat runs (more on graphs solved in microseconds). Built outside keel's
// CMake (g++ -fopenmp against CLIPPER's own library); clique.sh builds it.
//
// The graph is handed to CLIPPER as its binary consistency graph, affinity M = constraint C = adjacency +
// identity. CLIPPER keeps both as sparse upper-triangular matrices with the identity implicit
// (setMatrixData(M, C) takes the dense A + I and reduces it to exactly that), so by default they are passed
// that way through setSparseMatrixData; --dense passes the dense A + I through setMatrixData instead (the
// same solver input, slower and n^2 memory to build). Only solve() is timed, not building M and C. solve()
// draws its initial vector from std::random_device, as CLIPPER does by default, so repeats may select
// different sets.
//
// Usage: clipper_clique [--repeat=3] [--methods=clipper] [--dense] FILE...
// Output: one tab-separated line per graph, the format of keel_clique.cpp:
//   graph  clipper  median_ms  min_ms  size  nodes  valid
// (size: the selected set's size in the last run; nodes: 0; valid: 1 when every run's selected set is
// pairwise adjacent in the graph).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "clipper/clipper.h"
#include "dimacs.hpp"

namespace {

struct Graph {
  int n = 0;
  std::vector<std::pair<int, int>> edges;  // u < v, 0-based, sorted, no duplicates
  std::vector<std::vector<int>> adjacent;  // sorted

  bool is_clique(const std::vector<int>& s) const {
    for (std::size_t a = 0; a < s.size(); ++a) {
      if (s[a] < 0 || s[a] >= n) return false;
      for (std::size_t b = a + 1; b < s.size(); ++b) {
        const auto& row = adjacent[static_cast<std::size_t>(s[a])];
        if (!std::binary_search(row.begin(), row.end(), s[b])) return false;
      }
    }
    return true;
  }
};

Graph to_graph(const side_by_side::DimacsGraph& d) {
  Graph g;
  g.n = d.n;
  g.edges = d.edges;
  g.adjacent.assign(static_cast<std::size_t>(g.n), {});
  for (const auto& [u, v] : g.edges) {
    g.adjacent[static_cast<std::size_t>(u)].push_back(v);
    g.adjacent[static_cast<std::size_t>(v)].push_back(u);
  }
  for (auto& row : g.adjacent) std::sort(row.begin(), row.end());
  return g;
}

// The strictly upper-triangular adjacency, CLIPPER's internal form of M and C for a binary graph.
clipper::SpMat upper_adjacency(const Graph& g) {
  std::vector<clipper::SpTriplet> t;
  t.reserve(g.edges.size());
  for (const auto& [u, v] : g.edges) t.emplace_back(u, v, 1.0);
  clipper::SpMat a(g.n, g.n);
  a.setFromTriplets(t.begin(), t.end());
  a.makeCompressed();
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 3;
  std::string methods = "clipper";
  bool dense = false;
  std::vector<std::string> files;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg.rfind("--repeat=", 0) == 0)
      repeat = std::max(1, std::atoi(arg.c_str() + 9));
    else if (arg.rfind("--methods=", 0) == 0)
      methods = arg.substr(10);
    else if (arg == "--dense")
      dense = true;
    else
      files.push_back(arg);
  }
  if (("," + methods + ",").find(",clipper,") == std::string::npos) return 0;
  try {
    for (const auto& file : files) {
      const auto dimacs = side_by_side::read_dimacs(file);
      const Graph g = to_graph(dimacs);
      const std::string& name = dimacs.name;

      const clipper::SpMat a = upper_adjacency(g);
      Eigen::MatrixXd a_plus_i;
      if (dense) {
        a_plus_i = Eigen::MatrixXd(clipper::SpMat(a.selfadjointView<Eigen::Upper>()));
        a_plus_i.diagonal().setOnes();
      }

      std::vector<double> ms;
      std::size_t size = 0, min_size = static_cast<std::size_t>(-1), max_size = 0;
      bool valid = true;
      // At least `repeat` runs, and more on graphs solved in microseconds, until 50 ms have been spent (at
      // most 1000 runs), as keel_clique.cpp does.
      double total = 0;
      for (int k = 0; k < repeat || (total < 50.0 && k < 1000); ++k) {
        clipper::CLIPPER solver(nullptr, clipper::Params{});  // no invariant: M and C are given directly
        if (dense)
          solver.setMatrixData(a_plus_i, a_plus_i);
        else
          solver.setSparseMatrixData(a, a);
        const auto t0 = std::chrono::steady_clock::now();
        solver.solve();
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        total += ms.back();
        const std::vector<int>& nodes = solver.getSolution().nodes;
        size = nodes.size();
        min_size = std::min(min_size, size);
        max_size = std::max(max_size, size);
        valid = valid && g.is_clique(nodes);
      }
      if (min_size != max_size)
        std::fprintf(stderr, "clipper_clique: %s: the selected set's size varied over the runs, %zu to %zu\n",
                     name.c_str(), min_size, max_size);
      std::sort(ms.begin(), ms.end());
      std::printf("%s\tclipper\t%.4f\t%.4f\t%zu\t0\t%d\n", name.c_str(), ms[ms.size() / 2], ms.front(), size,
                  valid ? 1 : 0);
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "clipper_clique: %s\n", e.what());
    return 1;
  }
  return 0;
}
