// Fig. 2.2 and Fig. 2.3 (§2.7.1) on the simulated 1D world (sim/world1d.hpp): the combinatorial "gold
// standard" of eq. 2.5 — a search over the subsets S ∈ {0,1}^m that does not use the clique code — the count
// of inconsistent pairs of a returned set (Fig. 2.2's second row), and the Monte-Carlo study that runs every
// selector on the same worlds.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"
#include "sim/world1d.hpp"

namespace keel::core {
class Progress;
}

namespace keel::eval {

// Combinatorial solution of eq. 2.5 straight from Q and γ, independent of the clique code: the largest S ⊆
// {0..m−1} with q_uv <= γ and q_vu <= γ for all u ≠ v in S.
enum class CombinatorialMethod {
  exhaustive,  // all 2^m subsets, each tested for pairwise consistency (m <= kCombinatorialExhaustiveMax)
  pruned,      // depth-first include/exclude over the candidates in index order; a candidate is only included
               // when consistent with every included one, and a branch stops when even taking all remaining
               // candidates could not reach the best size (m <= kCombinatorialPrunedMax)
};
std::string_view to_string(CombinatorialMethod m);
CombinatorialMethod combinatorial_method_from_string(std::string_view s);  // "exhaustive" | "pruned"
inline constexpr int kCombinatorialExhaustiveMax = 30;
inline constexpr int kCombinatorialPrunedMax = 64;

struct CombinatorialResult {
  std::vector<int> selected;   // one maximum pairwise consistent set, sorted (exhaustive: smallest bitmask)
  long long optimal_sets = 0;  // number of distinct maximum pairwise consistent sets
  long long subsets_visited = 0;  // exhaustive: 2^m; pruned: search nodes
  double time_s = 0.0;
};
// Throws std::invalid_argument for a bad Q or γ (as select_pcm) or m above the method's limit.
[[nodiscard]] CombinatorialResult max_consistent_set_combinatorial(
    const pcm::ConsistencyMatrix& Q, double gamma, CombinatorialMethod method = CombinatorialMethod::pruned);

// ---------------------------------------------------------------------------------------------------------------
// Monte-Carlo study over 1D worlds (Figs. 2.2 and 2.3): every world is generated from its own random stream,
// its Q is built once (not timed), and each selector runs on the same Q.

enum class Selector1D { combinatorial, pcm_exact, pcm_heuristic, scgp, ransac };
std::string_view to_string(
    Selector1D s);  // "combinatorial" | "pcm_exact" | "pcm_heuristic" | "scgp" | "ransac"
Selector1D selector1d_from_string(std::string_view s);

struct World1DStudyOptions {
  sim::World1DOptions world;
  double pcm_gamma = 0.0;  // γ of PCM and of the combinatorial solution (eq. 2.5); also the γ against which
                           // inconsistent pairs are counted for every method (Fig. 2.2); > 0
  double ransac_gamma = 0.0;  // RANSAC's own likelihood threshold on q_uv; > 0
  pcm::ScgpOptions scgp;
  CombinatorialMethod combinatorial = CombinatorialMethod::pruned;
  std::vector<Selector1D> selectors = {Selector1D::combinatorial, Selector1D::pcm_exact,
                                       Selector1D::pcm_heuristic, Selector1D::scgp, Selector1D::ransac};
  std::uint64_t seed = 0;         // experiment seed
  std::uint64_t stream_base = 0;  // world i draws from Rng::stream(seed, stream_base + i)
  std::size_t worlds = 1000;      // >= 1
  unsigned threads = 0;           // 0 = keel::core::default_threads(); results do not depend on it
  void validate() const;          // throws std::invalid_argument naming the field
};

// One selector on one world.
struct World1DOutcome {
  int size = 0;                // number of selected measurements
  int inconsistent_pairs = 0;  // pairs of the selection with q > pcm_gamma (count_inconsistent_pairs)
  int inliers = 0;             // selected measurements labelled inlier
  double time_s = 0.0;         // wall time of the selection (Selection::time_s / CombinatorialResult::time_s)
};

struct World1DStudy {
  std::vector<Selector1D> selectors;                          // as requested
  std::vector<int> measurements;                              // m of each world
  std::vector<int> inliers;                                   // inliers in each world
  std::vector<std::vector<World1DOutcome>> outcome;           // [selector][world]
  const std::vector<World1DOutcome>& of(Selector1D s) const;  // throws std::invalid_argument if not run
};

// Runs the study on options.threads threads (parallel_for over worlds; progress advanced once per world, may
// be null).
[[nodiscard]] World1DStudy run_world1d_study(const World1DStudyOptions& options,
                                             core::Progress* progress = nullptr);

// How selectors compare with the combinatorial maximum over a study's worlds (Fig. 2.2): histograms over
// ranges shared by all the selectors compared.
struct SelectorComparison {
  Selector1D selector = Selector1D::pcm_exact;
  double match_rate = 0.0, larger_rate = 0.0,
         smaller_rate = 0.0;                              // fractions of worlds where the selection's size
                                                          // equals / exceeds / falls short of the maximum
  long long inconsistent_total = 0;                       // pairs violating eq. 2.3, summed over the worlds
  double inconsistent_mean = 0.0;                         // per world
  double inconsistent_rate = 0.0;                         // fraction of worlds with at least one
  double time_mean_s = 0.0;                               // mean selection wall time
  std::vector<double> size_diff_hist, inconsistent_hist;  // fractions of worlds per bin
};
struct CombinatorialComparison {
  std::vector<double> size_diff_bins;     // size returned − maximum size, one bin per integer
  std::vector<double> inconsistent_bins;  // 0 … the largest count of inconsistent pairs
  std::vector<SelectorComparison> rows;   // one per selector compared, in the order given
  int heuristic_above_exact = 0;  // worlds where PCM-Heuristic returned more than PCM-Exact (when both ran)
};
// Needs the combinatorial selector in the study; throws std::invalid_argument naming a selector that was not
// run.
[[nodiscard]] CombinatorialComparison compare_to_combinatorial(const World1DStudy& study,
                                                               const std::vector<Selector1D>& selectors);

// Fig. 2.3: selection time against the number of measurements m. For each m, worlds of exactly m measurements
// (sim::world1d_options_with_total with the given fractions) drawn from streams (seed, k << 32 | i), the same
// for every curve; PCM-Exact, PCM-Heuristic, SCGP, RANSAC and the exhaustive enumeration (m <=
// exhaustive_max) in one pass, the pruned subset search (m <= pruned_max) in a second pass over the same
// worlds.
struct TimingSweepOptions {
  World1DStudyOptions
      base;  // noise model, thresholds, SCGP, worlds per size, seed, threads (counts are replaced)
  std::vector<int> sizes;  // m, increasing, >= 1
  double inlier_fraction = 0.5, aliased_fraction = 0.25;
  int exhaustive_max = kCombinatorialExhaustiveMax;  // in [1, kCombinatorialExhaustiveMax]
  int pruned_max = kCombinatorialPrunedMax;          // in [1, kCombinatorialPrunedMax]
  void validate() const;                             // throws std::invalid_argument naming the field
  [[nodiscard]] std::size_t work() const;            // worlds × passes: the progress total
};
struct TimingCurve {
  std::string name;  // combinatorial_exhaustive, combinatorial_pruned, pcm_exact, pcm_heuristic, scgp, ransac
  std::vector<double> m;              // the sizes this curve ran at
  std::vector<double> median_time_s;  // median wall time of one selection at each m (robust to preemption)
  std::vector<double> size_mean;      // mean selected size at each m
};
struct TimingSweep {
  std::vector<TimingCurve> curves;       // in the order listed above
  std::vector<double> heuristic_match;   // per m: fraction of worlds where PCM-Heuristic's size = PCM-Exact's
  long long combinatorial_checked = 0;   // combinatorial runs (both variants) compared with PCM-Exact's size
  long long combinatorial_mismatch = 0;  // … of which with a different size
};
[[nodiscard]] TimingSweep run_timing_sweep(const TimingSweepOptions& options,
                                           core::Progress* progress = nullptr);

// Number of pairs {u, v} of `set` that violate eq. 2.3 (q_uv > γ or q_vu > γ). `set` must hold distinct
// indices in range (std::invalid_argument otherwise).
[[nodiscard]] int count_inconsistent_pairs(const pcm::ConsistencyMatrix& Q, const std::vector<int>& set,
                                           double gamma);

}  // namespace keel::eval
