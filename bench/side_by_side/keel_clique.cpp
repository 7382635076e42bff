// keel's side of the maximum-clique side-by-side (bench/side_by_side/clique.sh): reads DIMACS "p edge" graphs
// (bench_clique --write-family) and times keel's exact search (the default, and where the build has them,
// colouring only and each bound alone at every candidate) and the densest-subgraph selector, one thread,
// median of
// --repeat runs (more on graphs solved in microseconds).
// Written against the headers that every keel commit since the densest selector (a1b7a03) has, so the same
// source is built at every commit the script compares; CliqueOptions' bound switches are used only where they
// exist.
//
// Output: one tab-separated line per graph and method:
//   graph  method  median_ms  min_ms  size  nodes  valid
// (size: the clique or selection size; nodes: the exact search's node count, 0 for the selector; valid: 1
// when the answer is a clique of the graph).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dimacs.hpp"
#include "pcm/clique.hpp"
#include "pcm/densest.hpp"

namespace {

using keel::pcm::ConsistencyGraph;

template <class O>
constexpr bool kHasBoundSwitches = requires(O o) {
  o.recolour;
  o.maxsat_bound;
};

template <class O>
constexpr bool kHasAdaptiveBounds = requires(O o) { o.adaptive_bounds; };

// Colouring only, or one bound alone run at every candidate (not adaptively, where the build can tell).
template <class O>
bool set_bounds(O& o, bool recolour, bool maxsat) {
  if constexpr (kHasBoundSwitches<O>) {
    o.recolour = recolour;
    o.maxsat_bound = maxsat;
    if constexpr (kHasAdaptiveBounds<O>) o.adaptive_bounds = false;
    return true;
  } else {
    return false;
  }
}

// The selector's options that this build has: CLIPPER's penalty schedule (DensestOptions::penalty_step =
// mean) and CLIPPER's line search steps (DensestOptions::line_search = clipper). False when one asked for is
// missing.
template <class O>
bool set_densest_options(O& o, bool mean_step, bool clipper_steps) {
  if (mean_step) {
    if constexpr (requires(O x) { x.penalty_step = O::PenaltyStep::mean; })
      o.penalty_step = O::PenaltyStep::mean;
    else
      return false;
  }
  if (clipper_steps) {
    if constexpr (requires(O x) { x.line_search = O::LineSearch::clipper; })
      o.line_search = O::LineSearch::clipper;
    else
      return false;
  }
  return true;
}

struct Run {
  double ms = 0;
  std::size_t size = 0;
  long long nodes = 0;
  bool valid = false;
};

template <class F>
void report(const std::string& graph, const char* method, int repeat, F&& once) {
  // At least `repeat` runs, and on graphs solved in microseconds more, until 50 ms have been spent (at most
  // 1000 runs): the median of three runs of 5 µs is mostly noise.
  std::vector<double> ms;
  Run last;
  double total = 0;
  for (int k = 0; k < repeat || (total < 50.0 && k < 1000); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    last = once();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    total += ms.back();
  }
  std::sort(ms.begin(), ms.end());
  std::printf("%s\t%s\t%.4f\t%.4f\t%zu\t%lld\t%d\n", graph.c_str(), method, ms[ms.size() / 2], ms.front(),
              last.size, last.nodes, last.valid ? 1 : 0);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 3;
  std::string methods = "exact,colouring,recolour,maxsat,densest,densest_mean,densest_steps,densest_clipper";
  std::vector<std::string> files;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg.rfind("--repeat=", 0) == 0)
      repeat = std::max(1, std::atoi(arg.c_str() + 9));
    else if (arg.rfind("--methods=", 0) == 0)
      methods = "," + arg.substr(10) + ",";
    else
      files.push_back(arg);
  }
  if (methods.front() != ',') methods = "," + methods + ",";
  const auto wants = [&](const char* m) {
    return methods.find(std::string(",") + m + ",") != std::string::npos;
  };
  try {
    for (const auto& file : files) {
      const auto dimacs = side_by_side::read_dimacs(file);
      const ConsistencyGraph g(dimacs.n, dimacs.edges);
      const std::string& name = dimacs.name;
      struct Variant {
        const char* name;
        bool recolour, maxsat;
      };
      for (const Variant v : {Variant{"exact", true, true}, Variant{"colouring", false, false},
                              Variant{"recolour", true, false}, Variant{"maxsat", false, true}}) {
        if (!wants(v.name)) continue;
        keel::pcm::CliqueOptions o;
        if (std::string(v.name) != "exact" && !set_bounds(o, v.recolour, v.maxsat)) continue;
        report(name, v.name, repeat, [&] {
          const auto r = keel::pcm::maximum_clique_exact(g, o);
          return Run{0, r.clique.size(), r.nodes_explored, g.is_clique(r.clique)};
        });
      }
      struct Densest {
        const char* name;
        bool mean_step, clipper_steps;
      };
      for (const Densest v :
           {Densest{"densest", false, false}, Densest{"densest_mean", true, false},
            Densest{"densest_steps", false, true}, Densest{"densest_clipper", true, true}}) {
        keel::pcm::DensestOptions o;
        if (!wants(v.name) || !set_densest_options(o, v.mean_step, v.clipper_steps)) continue;
        report(name, v.name, repeat, [&] {
          const auto r = keel::pcm::densest_subgraph(g, o);
          return Run{0, r.selection.size(), 0, g.is_clique(r.selection)};
        });
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "keel_clique: %s\n", e.what());
    return 1;
  }
  return 0;
}
