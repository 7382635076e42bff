// The densest selector's acceptance rule (docs/DESIGN.md "The densest selector's default"): on a
// pre-registered generator of fresh consistency graphs, the default DensestOptions against the options of the
// default it replaced (DensestOptions::before_acceptance_rule()), paired graph by graph:
//   1. every answer (the repaired selection) of either is a clique;
//   2. the rate of size = ω is not lower: over the graphs where ω is proven (exact search within a node
//      budget, started from the larger of the two answers), the discordant pairs (one reaches ω, the other
//      not) do not show the default missing more often, by a one-sided sign test at 5 %;
//   3. the size is not lower: over all graphs, the pairs with different sizes do not show the default
//      smaller more often, by a one-sided sign test at 5 %.
// Exit status: 0 when the rule holds, 1 when it does not, 2 on a usage error, 3 when a graph cannot be built
// (a data set missing: the rule is never judged on a partial sample).
//
// The generator (fixed before any of its numbers existed; --seed draws another sample from it):
//   planted     180 graphs: graph i from core::Rng::stream(seed, i): n = round(100 · 20^U) (100 … 2000,
//               uniform in log n), p = U(0.05, 0.7), k = round(3 · (min(200, n) / 3)^U') (3 … 200, uniform
//               in log k), sim::planted_clique_graph(n, k, p, next());
//   world1d     60 graphs: stream(seed, 1000 + i): m = round(100 · 20^U) measurements of the Fig. 2.3
//               generator (half inliers, a quarter aliased; sim::world1d_options_with_total), world 0 of
//               seed next(), thresholded at γ(0.11, 1);
//   city10000   50 graphs: the candidate sets of ch2_table2_1_city's scenario and candidate options (full
//               profile) for data sets 0 … 49 of `seed` (not the experiment's seed), Q joint at γ(0.11, 3);
//   sphere2500  30 graphs: those of ch2_table2_2_3d_substitute, alike, at γ(0.11, 6).
// The pre-registered sample is the default seed, kPreRegisteredSeed; CTest bench.densest_acceptance runs it.
//
// Usage: densest_acceptance [--seed=N] [--node-limit=N] [--tsv=FILE] [--write-graphs=DIR]
//                           [--only=planted,world1d,city10000,sphere2500]
// --write-graphs=DIR also writes every graph of the sample as DIR/<name>.clq (DIMACS, for the side-by-side
// scripts: fresh hold-out graphs for bench/side_by_side/clique.sh).
// One thread; each selector runs once per graph (times are one run each, for information, not part of the
// rule).
import keel.pcm;
import keel.sim;
import keel.core;
import keel.repro;
import keel.study;

#include "study_graphs.hpp"
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <set>
#include <string>
#include <vector>

namespace pcm = keel::pcm;
namespace sim = keel::sim;

namespace {

constexpr std::uint64_t kPreRegisteredSeed = 20261206;
constexpr int kPlanted = 180, kWorlds = 60, kCity = 50, kSphere = 30;
constexpr long long kDefaultNodeLimit = 20000;
constexpr double kAlpha = 0.05;

struct Fresh : keel::bench::NamedGraph {
  std::string family;
};

int log_uniform(keel::core::Rng& rng, double lo, double hi) {
  return static_cast<int>(std::lround(lo * std::pow(hi / lo, rng.uniform())));
}

std::vector<Fresh> generate(std::uint64_t seed, const std::set<std::string>& only) {
  std::vector<Fresh> out;
  auto wanted = [&](const char* f) { return only.empty() || only.count(f) > 0; };
  if (wanted("planted"))
    for (int i = 0; i < kPlanted; ++i) {
      auto rng = keel::core::Rng::stream(seed, static_cast<std::uint64_t>(i));
      const int n = log_uniform(rng, 100, 2000);
      const double p = rng.uniform(0.05, 0.7);
      const int k = log_uniform(rng, 3, std::min(200, n));
      const std::uint64_t s = rng.next();
      out.push_back({{fmt::format("planted_{:03}", i),
                      fmt::format("planted_clique_graph({}, {}, {:.4f}, {})", n, k, p, s),
                      sim::planted_clique_graph(n, k, p, s).graph},
                     "planted"});
    }
  if (wanted("world1d"))
    for (int i = 0; i < kWorlds; ++i) {
      auto rng = keel::core::Rng::stream(seed, 1000 + static_cast<std::uint64_t>(i));
      const int m = log_uniform(rng, 100, 2000);
      const std::uint64_t s = rng.next();
      const auto o = sim::world1d_options_with_total(sim::World1DOptions{}, m, 0.5, 0.25);
      const auto Q = sim::world1d_consistency_matrix(sim::generate_world1d(o, s, 0));
      out.push_back({{fmt::format("world1d_{:03}", i), fmt::format("1D world, m = {}, seed {}", m, s),
                      pcm::ConsistencyGraph::from_threshold(Q.n, Q.q, pcm::consistency_threshold(0.11, 1))},
                     "world1d"});
    }
  const std::string experiments = std::string(KEEL_SOURCE_DIR) + "/experiments/";
  auto add_sets = [&](const char* family, std::vector<keel::bench::NamedGraph> graphs) {
    for (auto& g : graphs) out.push_back({std::move(g), family});
  };
  if (wanted("city10000"))
    add_sets("city10000", keel::bench::study_graphs<keel::study::ch2::CityTable, false>(
                              experiments + "ch2_table2_1_city/experiment.toml", "ch2_table2_1_city",
                              "city10000", seed, kCity));
  if (wanted("sphere2500"))
    add_sets("sphere2500", keel::bench::study_graphs<keel::study::ch2::Substitute3D, true>(
                               experiments + "ch2_table2_2_3d_substitute/experiment.toml",
                               "ch2_table2_2_3d_substitute", "sphere2500", seed, kSphere));
  return out;
}

// P(X >= k) for X ~ Binomial(n, 1/2): the one-sided sign test's p-value for k or more of n discordant pairs
// going against the default.
double sign_test(int k, int n) {
  if (k <= 0) return 1.0;
  double tail = 0.0;
  for (int j = k; j <= n; ++j)
    tail +=
        std::exp(std::lgamma(n + 1.0) - std::lgamma(j + 1.0) - std::lgamma(n - j + 1.0) - n * std::log(2.0));
  return std::min(1.0, tail);
}

struct Side {
  std::vector<int> selection;
  std::size_t size = 0;
  bool clique = false;
  long long products = 0;
  double ms = 0;
};

Side run(const pcm::ConsistencyGraph& g, const pcm::DensestOptions& o) {
  auto r = pcm::densest_subgraph(g, o);
  const bool clique = g.is_clique(r.selection);
  const std::size_t size = r.selection.size();
  return {std::move(r.selection), size, clique, r.products, 1e3 * r.time_s};
}

int usage(const std::string& why) {
  std::fprintf(stderr,
               "densest_acceptance: %s\nusage: densest_acceptance [--seed=N] [--node-limit=N] [--tsv=FILE] "
               "[--write-graphs=DIR] [--only=planted,world1d,city10000,sphere2500]\n",
               why.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t seed = kPreRegisteredSeed;
  long long node_limit = kDefaultNodeLimit;
  std::string tsv_path, graphs_dir;
  std::set<std::string> only;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    auto value = [&](const char* flag) -> const char* {
      const std::size_t len = std::char_traits<char>::length(flag);
      return arg.compare(0, len, flag) == 0 ? argv[a] + len : nullptr;
    };
    try {
      if (const char* s = value("--seed=")) {
        seed = std::stoull(s);
      } else if (const char* l = value("--node-limit=")) {
        node_limit = std::stoll(l);
        if (node_limit < 1) return usage("--node-limit must be >= 1");
      } else if (const char* t = value("--tsv=")) {
        tsv_path = t;
      } else if (const char* w = value("--write-graphs=")) {
        graphs_dir = w;
      } else if (const char* o = value("--only=")) {
        std::string list = o;
        for (std::size_t start = 0; start <= list.size();) {
          const std::size_t end = std::min(list.find(',', start), list.size());
          const std::string f = list.substr(start, end - start);
          if (f != "planted" && f != "world1d" && f != "city10000" && f != "sphere2500")
            return usage("unknown family '" + f + "' in --only");
          only.insert(f);
          start = end + 1;
        }
      } else {
        return usage("unknown argument '" + arg + "'");
      }
    } catch (const std::exception&) {
      return usage("bad number in '" + arg + "'");
    }
  }

  std::vector<Fresh> graphs;
  try {
    graphs = generate(seed, only);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "densest_acceptance: cannot build the fresh graphs: %s\n", e.what());
    return 3;
  }
  if (!graphs_dir.empty()) {
    try {
      for (const auto& f : graphs)
        keel::bench::write_dimacs(graphs_dir, f.name,
                                  fmt::format("densest_acceptance seed {}: {}", seed, f.origin), f.graph);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "densest_acceptance: %s\n", e.what());
      return 2;
    }
  }
  std::FILE* tsv = nullptr;
  if (!tsv_path.empty()) {
    tsv = std::fopen(tsv_path.c_str(), "w");
    if (!tsv) {
      std::fprintf(stderr, "densest_acceptance: cannot write %s\n", tsv_path.c_str());
      return 2;
    }
    std::fprintf(tsv,
                 "family\tname\torigin\tn\tedges\tomega\tomega_proven\tbefore_size\tdefault_size\tbefore_ms\t"
                 "default_ms\tbefore_products\tdefault_products\n");
  }

  const pcm::DensestOptions before = pcm::DensestOptions::before_acceptance_rule();
  const pcm::DensestOptions now{};
  int not_cliques = 0, larger = 0, smaller = 0, proven = 0, hit_before = 0, hit_now = 0, only_before = 0,
      only_now = 0;
  double sum_before = 0, sum_now = 0, ms_before = 0, ms_now = 0;
  long long products_before = 0, products_now = 0;
  for (const auto& f : graphs) {
    const Side b = run(f.graph, before);
    const Side n = run(f.graph, now);
    not_cliques += (b.clique ? 0 : 1) + (n.clique ? 0 : 1);
    pcm::CliqueOptions co;
    co.node_limit = node_limit;
    // The larger answer that is a clique starts the search: it changes the work, never the proven ω.
    if (b.clique) co.initial_clique = b.selection;
    if (n.clique && n.size > co.initial_clique.size()) co.initial_clique = n.selection;
    const auto exact = pcm::maximum_clique(f.graph, pcm::CliqueAlgorithm::exact, co);
    const bool omega_known = exact.proven_optimal();
    const auto omega = exact.clique.size();
    larger += n.size > b.size ? 1 : 0;
    smaller += n.size < b.size ? 1 : 0;
    sum_before += static_cast<double>(b.size);
    sum_now += static_cast<double>(n.size);
    ms_before += b.ms;
    ms_now += n.ms;
    products_before += b.products;
    products_now += n.products;
    if (omega_known) {
      ++proven;
      const bool hb = b.size == omega, hn = n.size == omega;
      hit_before += hb ? 1 : 0;
      hit_now += hn ? 1 : 0;
      only_before += hb && !hn ? 1 : 0;
      only_now += hn && !hb ? 1 : 0;
    }
    if (tsv)
      std::fprintf(tsv, "%s\t%s\t%s\t%d\t%lld\t%zu\t%d\t%zu\t%zu\t%.4f\t%.4f\t%lld\t%lld\n", f.family.c_str(),
                   f.name.c_str(), f.origin.c_str(), f.graph.size(), f.graph.num_edges(), omega,
                   omega_known ? 1 : 0, b.size, n.size, b.ms, n.ms, b.products, n.products);
  }
  if (tsv) std::fclose(tsv);

  const int total = static_cast<int>(graphs.size());
  const double p_size = sign_test(smaller, larger + smaller);
  const double p_omega = sign_test(only_before, only_before + only_now);
  const bool cliques_ok = not_cliques == 0;
  const bool omega_ok = p_omega >= kAlpha;
  const bool size_ok = p_size >= kAlpha;
  std::printf("densest_acceptance: seed %llu%s, %d fresh graphs", static_cast<unsigned long long>(seed),
              seed == kPreRegisteredSeed ? " (pre-registered)" : "", total);
  for (const char* fam : {"planted", "world1d", "city10000", "sphere2500"}) {
    const auto c =
        std::count_if(graphs.begin(), graphs.end(), [&](const Fresh& f) { return f.family == fam; });
    if (c > 0) std::printf(", %s %ld", fam, static_cast<long>(c));
  }
  std::printf("\n  before = DensestOptions::before_acceptance_rule(), default = DensestOptions{}\n");
  std::printf("  1. answers that are not cliques: %d of %d          %s\n", not_cliques, 2 * total,
              cliques_ok ? "holds" : "FAILS");
  std::printf(
      "  2. size = omega (omega proven on %d, node limit %lld): before %d, default %d; only before %d, only "
      "default %d; sign test p = %.3g   %s\n",
      proven, node_limit, hit_before, hit_now, only_before, only_now, p_omega, omega_ok ? "holds" : "FAILS");
  std::printf(
      "  3. size: default larger on %d, smaller on %d, equal on %d; mean %.4g against %.4g; sign test p = "
      "%.3g   "
      "%s\n",
      larger, smaller, total - larger - smaller, total ? sum_now / total : 0.0,
      total ? sum_before / total : 0.0, p_size, size_ok ? "holds" : "FAILS");
  std::printf(
      "  time (one run each, for information): before %.1f ms, default %.1f ms; products %lld against %lld\n",
      ms_before, ms_now, products_before, products_now);
  const bool accepted = cliques_ok && omega_ok && size_ok && total > 0;
  std::printf("densest_acceptance: the rule %s\n", accepted ? "holds" : "does NOT hold");
  return accepted ? 0 : 1;
}
