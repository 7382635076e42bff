// Maximum clique at scale (beyond the thesis): PCM's exact search, its heuristic and the densest-subgraph
// relaxation (pcm/densest.hpp, Lusk, Fathian and How, "CLIPPER", ICRA 2021) on the same consistency graphs,
// scored against a reference set (the planted clique, or the inliers of a 1D world or of a two-robot data
// set). Three families of graphs:
//   planted   G(n, p) with a clique planted on k vertices (sim::planted_clique_graph): k inliers among n
//             candidates whose other pairs are consistent by chance with probability p;
//   world1d   the 1D worlds of §2.7.1 (sim/world1d.hpp) at their consistency threshold γ;
//   two-robot the candidate sets of the Table 2.1 data sets (§2.7.2) at γ(p).
// Each graph is one trial of repro::trial_loop, so the studies shard (docs/DESIGN.md "Sharding").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/config.hpp"
#include "study/ch2/config.hpp"
#include "study/ch2/two_robot.hpp"
#include "pcm/clique.hpp"
#include "pcm/densest.hpp"
#include "sim/world1d.hpp"

namespace keel::core {
class Progress;
}  // namespace keel::core
namespace keel::repro {
class Results;
struct Figure;
}  // namespace keel::repro

namespace keel::study::ch2 {

// ω₀(n, p): the largest k in [1, n] with C(n, k) · p^(k(k−1)/2) >= 1, the first-moment estimate of the clique
// number of G(n, p) (the expected number of k-cliques drops below one past it; Matula 1976, Bollobás and
// Erdős 1976: the clique number concentrates on two values near 2 log_{1/p} n). A planted clique of k <= ω₀
// vertices is not expected to be the maximum clique: cliques of chance are as large. Computed in logarithms
// (lgamma). Throws std::invalid_argument for n < 1 or p outside [0, 1]; p = 1 gives n, p = 0 gives 1.
[[nodiscard]] int first_moment_clique_number(int n, double p);

enum class CliqueScaleMethod { exact, heuristic, densest };
inline constexpr std::size_t kCliqueScaleMethods = 3;
inline constexpr std::array<CliqueScaleMethod, kCliqueScaleMethods> kAllCliqueScaleMethods = {
    CliqueScaleMethod::exact, CliqueScaleMethod::heuristic, CliqueScaleMethod::densest};
std::string_view to_string(CliqueScaleMethod m);                        // "exact" | "heuristic" | "densest"
CliqueScaleMethod clique_scale_method_from_string(std::string_view s);  // throws std::invalid_argument

struct CliqueScaleOptions {
  // The exact search stops after this many branch-and-bound nodes (not a time limit, so that its result does
  // not depend on the machine) and reports the best clique, the proven upper bound and status node_limit.
  long long exact_node_limit = 1000000;  // >= 1
  pcm::DensestOptions densest;  // binary affinities (adjacency + I): the relaxation of the maximum clique
  // Graphs of at most this many vertices are solved a second time by the exact search with greedy colouring
  // bounds only (CliqueOptions::recolour and maxsat_bound off) and no node limit: a reference for the maximum
  // size that does not depend on the re-colouring and MaxSAT bounds. 0: none.
  int reference_max_vertices = 0;  // >= 0
  void validate() const;           // throws std::invalid_argument naming the field
};

// One method on one graph. Plain data (saved as bytes in a shard's record).
struct CliqueMethodOutcome {
  int size = 0;                  // vertices returned
  int hits = 0;                  // of them in the reference set
  long long violations = 0;      // non-adjacent pairs among the vertices returned (0 for a clique)
  int raw_size = 0;              // densest: the rounding before its repair; the others: size
  long long raw_violations = 0;  // densest: non-adjacent pairs in the rounding; the others: violations
  int upper_bound = 0;  // exact and heuristic: no clique is larger (heuristic: max core + 1); densest: 0
  pcm::SearchStatus status = pcm::SearchStatus::unproven;  // exact: optimal or node_limit
  long long nodes = 0;                                     // exact: branch-and-bound nodes
  double time_s = 0.0;                                     // wall time of the method (graph given)
};

// Every method on one graph.
struct CliqueGraphOutcome {
  int vertices = 0;
  long long edges = 0;
  int reference = 0;  // size of the reference set
  std::array<CliqueMethodOutcome, kCliqueScaleMethods> methods{};
  int reference_size =
      -1;  // the colouring-only exact search's maximum (-1: not run, see reference_max_vertices)
  const CliqueMethodOutcome& of(CliqueScaleMethod m) const { return methods[static_cast<std::size_t>(m)]; }
};

// Non-adjacent pairs among `vertices` (distinct ids of g).
[[nodiscard]] long long non_adjacent_pairs(const pcm::ConsistencyGraph& g, const std::vector<int>& vertices);

// Runs exact, heuristic and densest on g and scores each against `reference` (distinct vertex ids of g).
[[nodiscard]] CliqueGraphOutcome compare_clique_methods(const pcm::ConsistencyGraph& g,
                                                        const std::vector<int>& reference,
                                                        const CliqueScaleOptions& options);

// One method over a set of graphs: precision and recall pooled (Σ hits / Σ size, Σ hits / Σ reference; 0 when
// the denominator is 0), the other quantities as means, maxima or counts.
struct CliqueMethodSummary {
  std::size_t graphs = 0;
  double size_mean = 0.0;
  int size_min = 0, size_max = 0;
  double precision = 0.0, recall = 0.0;
  double raw_size_mean = 0.0, raw_violations_mean = 0.0;
  std::size_t raw_violating_graphs = 0;  // graphs whose raw output holds a non-adjacent pair
  long long violations_total = 0;        // non-adjacent pairs in the outputs, over the graphs
  std::size_t optimal_graphs = 0;        // status optimal
  double upper_bound_mean = 0.0;
  double gap_mean = 0.0;  // upper_bound − size (exact and heuristic; 0 for densest)
  int gap_max = 0;
  double nodes_mean = 0.0;
  double time_mean_s = 0.0, time_max_s = 0.0;
};
// Over outcomes[first, last). Throws std::invalid_argument for an empty or out-of-range span.
[[nodiscard]] CliqueMethodSummary summarize_clique_method(const std::vector<CliqueGraphOutcome>& outcomes,
                                                          std::size_t first, std::size_t last,
                                                          CliqueScaleMethod method);

// ---------------------------------------------------------------------------------------------------------------
// Planted cliques: every (n, k, p) cell, `seeds` graphs each.

struct PlantedCliqueCell {
  int n = 0, k = 0;
  double p = 0.0;
  int omega0 = 0;  // first_moment_clique_number(n, p)
  // k > ω₀: the planted clique is expected to be the maximum one, so precision and recall against it are
  // meaningful; otherwise cliques of chance are as large.
  bool planted_is_maximum() const { return k > omega0; }
};

struct PlantedCliqueStudyOptions {
  std::vector<int> sizes;                // n, each >= 2
  std::vector<double> clique_fractions;  // k = max(clique_min, round(f · n)), f in (0, 1]
  int clique_min = 2;                    // >= 1
  std::vector<double> densities;         // p in [0, 1]
  std::size_t seeds = 1;                 // graphs per cell, >= 1
  CliqueScaleOptions methods;
  void validate() const;  // throws std::invalid_argument naming the field
  // The cells in order n, then fraction, then p; a cell whose (n, k) repeats an earlier fraction's is left
  // out (two fractions can round to the same k at small n).
  [[nodiscard]] std::vector<PlantedCliqueCell> cells() const;
};

struct PlantedCliqueStudy {
  std::vector<PlantedCliqueCell> cells;
  std::size_t seeds = 0;
  std::vector<CliqueGraphOutcome> outcomes;  // cell c, seed s at c · seeds + s
};
// One trial_loop over every graph (progress advanced once per graph; may be null): graph s of cell c is
// planted_clique_graph(n, k, p, streams.stream(c << 32 | s).next()).
[[nodiscard]] PlantedCliqueStudy run_planted_clique_study(const PlantedCliqueStudyOptions& options,
                                                          const repro::RunContext& context,
                                                          core::Progress* progress = nullptr);

// ---------------------------------------------------------------------------------------------------------------
// 1D worlds (§2.7.1): world i from sim::generate_world1d(world, streams.seed(), streams.index(i)), its
// consistency graph at γ, the inliers as the reference set.
struct World1DCliqueOptions {
  sim::World1DOptions world;
  double gamma = 0.0;  // > 0
  std::size_t worlds = 1;
  CliqueScaleOptions methods;
  void validate() const;
};
[[nodiscard]] std::vector<CliqueGraphOutcome> run_world1d_clique_study(const World1DCliqueOptions& options,
                                                                       const repro::RunContext& context,
                                                                       core::Progress* progress = nullptr);

// Two-robot data sets (§2.7.2): data set i's candidates from sim::generate_candidates(scenario, candidates,
// streams.seed(), streams.index(i)) — the candidate sets of run_merge_datasets on the same streams —, Q with
// `composition`, the graph at γ(p) = consistency_threshold(p, dof), the inliers as the reference set. No
// merged solve is run.
[[nodiscard]] std::vector<CliqueGraphOutcome> run_two_robot_clique_study(
    const sim::TwoRobotScenario2& scenario, const LocalPair<lie::SE2>& local,
    const sim::CandidateOptions& candidates, double p, pcm::Composition composition,
    const CliqueScaleOptions& options, const repro::RunContext& context, std::size_t count,
    core::Progress* progress = nullptr);

// ---------------------------------------------------------------------------------------------------------------
// Recording (ext_clique_scale): metrics per group of graphs, the checks over every graph, and the figure.

// What the checks of ext_clique_scale count, over every graph recorded.
struct CliqueScaleTally {
  std::size_t graphs = 0, exact_below_heuristic = 0, not_cliques = 0, above_bound = 0, optimal = 0,
              optimal_inconsistent = 0, below_planted = 0, densest_raw_violating = 0, reference_checked = 0,
              reference_mismatch = 0;
  // Adds outcomes[first, last); `planted_k` > 0 is the planted clique's size (0: no planted clique).
  void add(const std::vector<CliqueGraphOutcome>& outcomes, std::size_t first, std::size_t last,
           int planted_k);
  // The all.* metrics and the five checks (reference_max_vertices: CliqueScaleOptions's, named in a check).
  void record(repro::Results& results, int reference_max_vertices) const;
};

// Per method, under "<prefix>.<method>.": size, size_min, precision, recall, violations; for the densest
// subgraph its raw rounding; for the exact search optimal (fraction), upper_bound, gap, gap_max, nodes;
// timings time_s and time_s.max. Then adds the graphs to `tally`.
void record_clique_group(repro::Results& results, const repro::KeyPath& prefix,
                         const std::vector<CliqueGraphOutcome>& outcomes, std::size_t first, std::size_t last,
                         int planted_k, CliqueScaleTally& tally);

// planted.n<n:04>.k<k:04>.p<100p:02>, the key path of a planted cell.
[[nodiscard]] repro::KeyPath planted_cell_path(const PlantedCliqueCell& cell);

// Every cell of the study: k, omega0, planted_is_maximum and its group (record_clique_group); then
// planted.cells and planted.seeds.
void record_planted_clique_study(repro::Results& results, const PlantedCliqueStudy& study,
                                 CliqueScaleTally& tally);

// Per density, mean wall time (the cells' time_s timings) and recall of each method against n, for the cells
// whose k is that of clique fraction `fraction` (k = max(clique_min, round(fraction · n)), at most n).
[[nodiscard]] repro::Figure planted_clique_figure(const PlantedCliqueStudy& study,
                                                  const PlantedCliqueStudyOptions& options, double fraction,
                                                  std::string file);

// ---------------------------------------------------------------------------------------------------------------
// The study of ext_clique_scale (beyond the thesis): exact, heuristic and densest subgraph on planted
// cliques, on 1D worlds of exactly `world1d.measurements` measurements (the fractions of Fig. 2.3) and on the
// Table 2.1 candidate sets (ch2_table2_1_city's scenario and candidate seed).
struct CliqueScale {
  struct Options {
    PlantedCliqueStudyOptions planted;
    World1DCliqueOptions world1d;  // its methods are planted.methods
    int world1d_measurements = 0;
    ScenarioFiles city;
    sim::CandidateOptions city_candidates;
    std::size_t city_datasets = 0;
    double city_p = 0.11;
    std::uint64_t city_seed = 0;  // the candidate seed of ch2_table2_1_city (its data sets, not this run's)
    double figure_clique_fraction = 0.1;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    PlantedCliqueStudy planted;
    std::vector<CliqueGraphOutcome> worlds, city;
    double planted_time_s = 0, world1d_time_s = 0, city_time_s = 0;
  };
  // The planted graphs draw from the run's streams, the worlds from its streams shifted by 2^48 (apart from
  // the planted graphs'), the candidate sets from city_seed's.
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch2
